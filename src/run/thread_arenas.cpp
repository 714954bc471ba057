// Binds each worker thread to a jemalloc arena of its own (see thread_arenas.hpp).
#include "run/thread_arenas.hpp"

#include <tbb/info.h>

#include <algorithm>
#include <cstddef>
#include <mutex>
#include <vector>

// jemalloc's control interface, when jemalloc is the process's allocator; null otherwise.
extern "C" int mallctl(const char* name, void* oldp, size_t* oldlenp, void* newp, size_t newlen)
    __attribute__((weak));

namespace carve {

namespace {

// A thread keeps its arena for its life: TBB's workers outlive a run, and a test running many
// slices in one process binds each worker once.
thread_local bool g_has_own_arena = false;

// The arenas made so far. Each keeps a megabyte or so of pages of its own, so there are no more
// than the cores can run at once beside the main thread's: with more threads than cores
// (--threads 16 on 2 cores) workers share them round the slots (fandisk at --scale 2.5 took
// 50 MB at 16 threads with an arena for each, 30 MB with one).
std::mutex g_mutex;
std::vector<unsigned> g_arenas;

}  // namespace

ThreadArenas::ThreadArenas(tbb::task_arena& arena) : tbb::task_scheduler_observer(arena) {
    if (!mallctl) return;
    // observe() initialises the task arena itself if it is not yet, and oneTBB 2021.8 leaves
    // the observer half registered when that throws (out of memory): its destructor then
    // crashed. Initialised here first, a failure throws before anything is registered.
    arena.initialize();
    observe(true);
}

ThreadArenas::~ThreadArenas() {
    observe(false);
}

void ThreadArenas::on_scheduler_entry(bool worker) {
    if (!worker || g_has_own_arena) return;
    g_has_own_arena = true;  // tried once: a failure is not retried on every task
    const size_t most = size_t(std::max(1, tbb::info::default_concurrency() - 1));
    const int slot = std::max(1, tbb::this_task_arena::current_thread_index());
    const size_t pick = size_t(slot - 1) % most;
    unsigned index = 0;
    {
        std::lock_guard lock(g_mutex);
        if (pick < g_arenas.size()) {
            index = g_arenas[pick];
        } else {
            size_t size = sizeof(index);
            if (mallctl("arenas.create", &index, &size, nullptr, 0) != 0) return;
            g_arenas.push_back(index);
        }
    }
    mallctl("thread.arena", nullptr, nullptr, &index, sizeof(index));
}

}  // namespace carve

// Binds each worker thread to a jemalloc arena of its own (see thread_arenas.hpp).
#include "run/thread_arenas.hpp"

#include <cstddef>

// jemalloc's control interface, when jemalloc is the process's allocator; null otherwise.
extern "C" int mallctl(const char* name, void* oldp, size_t* oldlenp, void* newp, size_t newlen)
    __attribute__((weak));

namespace carve {

namespace {

// A thread keeps its arena for its life: TBB's workers outlive a run, and a test running many
// slices in one process creates at most one arena for each worker.
thread_local bool g_has_own_arena = false;

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
    unsigned index = 0;
    size_t size = sizeof(index);
    if (mallctl("arenas.create", &index, &size, nullptr, 0) != 0) return;
    mallctl("thread.arena", nullptr, nullptr, &index, sizeof(index));
}

}  // namespace carve

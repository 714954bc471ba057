// One jemalloc arena for each worker thread of a run (private to run/pipeline.cpp).
//
// carve links jemalloc with a single automatic arena (see cli/main.cpp: under `ulimit -v`,
// jemalloc crashed creating a thread's arena lazily instead of failing the allocation). With
// every thread on that arena, the pipeline's threads contend for its lock whenever their caches
// fill or drain, which Clipper's allocation of every edge and point makes constant: on 2 cores
// skull took 10 % more CPU than on one. A worker joining the run's task arena is given an arena
// of its own, created explicitly: a creation that fails leaves the worker on the shared arena.
// Without jemalloc (a sanitizer build, glibc's malloc) this does nothing.
#pragma once

#include <tbb/task_arena.h>
#include <tbb/task_scheduler_observer.h>

namespace carve {

class ThreadArenas : public tbb::task_scheduler_observer {
  public:
    explicit ThreadArenas(tbb::task_arena& arena);
    ~ThreadArenas() override;
    void on_scheduler_entry(bool worker) override;
};

}  // namespace carve

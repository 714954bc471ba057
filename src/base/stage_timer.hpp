// Per-stage CPU accounting for finding hot spots: CARVE_PROFILE=1 in the environment makes
// `carve slice` print, on stderr at the end of the run, the thread CPU time and call count of
// each instrumented stage (inclusive: a skeleton inside the sweep counts in both). Without the
// variable a timer costs one relaxed atomic load.
#pragma once

#include <cstdint>
#include <string>

namespace carve {

enum class Stage {
    kSlice,
    kCovers,
    kSweep,       // the first carving iteration (C^1)
    kSweepLater,  // the others (C^2..C^k)
    kSkeleton,
    kVoronoi,
    kBridges,
    kRibs,  // the ribs and their vaults (supports/ribs*.cpp); counted as kBridges before issue 50
    kToolpaths,
    kGcode,
    kMorphology,  // geometry's operations, reported through its probe (geometry/probe.hpp)
    kBoolean,
    kCount
};

bool profiling_enabled();

// The thread's CPU clock in nanoseconds, and a time to add to a stage's counters (one call):
// what StageTimer does, for code that times itself another way (geometry's probe, src/run).
int64_t thread_cpu_ns();
void add_stage_time(Stage stage, int64_t ns);

class StageTimer {
  public:
    explicit StageTimer(Stage stage);
    ~StageTimer();
    StageTimer(const StageTimer&) = delete;
    StageTimer& operator=(const StageTimer&) = delete;

  private:
    Stage stage_;
    int64_t start_ns_ = -1;
};

// The table of stages with CPU seconds and calls; empty when profiling is off.
std::string profile_table();

}  // namespace carve

// Thread CPU clocks rather than wall clocks: stages run on two threads and the machines we
// measure on are shared, so CPU time is the figure that stays comparable between runs.
#include "base/stage_timer.hpp"

#include <time.h>

#include <array>
#include <atomic>
#include <cstdio>
#include <cstdlib>

namespace carve {

namespace {

struct Counter {
    std::atomic<int64_t> ns{0};
    std::atomic<int64_t> calls{0};
};

std::array<Counter, size_t(Stage::kCount)> counters;

constexpr std::array<const char*, size_t(Stage::kCount)> kNames{
    "slice",   "covers", "sweep C1",  "sweep C2..", "skeleton",   "voronoi",
    "bridges", "ribs",   "toolpaths", "gcode",      "morphology", "boolean"};

}  // namespace

int64_t thread_cpu_ns() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return int64_t(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}

void add_stage_time(Stage stage, int64_t ns) {
    Counter& c = counters[size_t(stage)];
    c.ns.fetch_add(ns, std::memory_order_relaxed);
    c.calls.fetch_add(1, std::memory_order_relaxed);
}

bool profiling_enabled() {
    static const bool on = [] {
        const char* v = std::getenv("CARVE_PROFILE");
        return v && *v && std::string(v) != "0";
    }();
    return on;
}

StageTimer::StageTimer(Stage stage) : stage_(stage) {
    if (profiling_enabled()) start_ns_ = thread_cpu_ns();
}

StageTimer::~StageTimer() {
    if (start_ns_ >= 0) add_stage_time(stage_, thread_cpu_ns() - start_ns_);
}

std::string profile_table() {
    if (!profiling_enabled()) return {};
    std::string out = "stage          CPU s      calls\n";
    // snprintf rather than fmt: the fuzz targets link the slicer, and with it this file, alone.
    char line[96];
    for (size_t i = 0; i < counters.size(); ++i) {
        std::snprintf(line, sizeof line, "%-12s %8.3f %10lld\n", kNames[i],
                      double(counters[i].ns.load()) * 1e-9,
                      static_cast<long long>(counters[i].calls.load()));
        out += line;
    }
    return out;
}

}  // namespace carve

// The profile of the run's pipeline under CARVE_PROFILE (private to run/pipeline.cpp): the
// CPU time of each layer in each filter, the critical path through them, and the table that
// sets them against the serial parts of the run.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "base/stage_timer.hpp"

namespace carve {

// Under CARVE_PROFILE, the thread CPU time each layer spent in each filter, from which the
// critical path follows: a filter's work on a layer waits for the filter before it on the same
// layer, and a serial filter's also for its own work on the layer before. That chain is the
// CPU time no other thread can overlap, whatever the number of cores. (The hold-back filter
// releases layer n when layer n + 1 arrives; the log books it on the released layer, which
// shortens the chain by at most one layer's sweep.)
struct SpanLog {
    SpanLog(int rows, int filter_count)
        : filters(filter_count), ns(size_t(rows) * size_t(filter_count), 0) {}
    int filters;
    std::vector<int64_t> ns;   // [seq][filter]
    std::vector<bool> serial;  // a filter that takes one layer at a time, in order
    bool on() const { return !ns.empty(); }
    int rows() const { return filters > 0 ? int(ns.size() / size_t(filters)) : 0; }

    double filter_s(int f) const {
        int64_t sum = 0;
        for (int n = 0; n < rows(); ++n) sum += ns[size_t(n) * filters + f];
        return double(sum) * 1e-9;
    }
    double critical_path_s() const { return critical_path_by_filter_s().first; }
    // The critical path and what each filter's layers add to it: where to look next.
    std::pair<double, std::vector<double>> critical_path_by_filter_s() const {
        std::vector<int64_t> done(ns.size(), 0);        // when each cell finishes at the earliest
        std::vector<size_t> from(ns.size(), SIZE_MAX);  // the cell it waited for
        size_t last = SIZE_MAX;
        for (int n = 0; n < rows(); ++n)
            for (int f = 0; f < filters; ++f) {
                const size_t at = size_t(n) * filters + f;
                int64_t ready = 0;
                if (f > 0) ready = done[at - 1], from[at] = at - 1;
                if (serial[f] && n > 0 && done[at - filters] > ready)
                    ready = done[at - filters], from[at] = at - filters;
                done[at] = ready + ns[at];
                if (last == SIZE_MAX || done[at] > done[last]) last = at;
            }
        std::vector<double> by_filter(size_t(filters), 0.0);
        if (last == SIZE_MAX) return {0.0, by_filter};
        for (size_t at = last; at != SIZE_MAX; at = from[at])
            by_filter[at % size_t(filters)] += double(ns[at]) * 1e-9;
        return {double(done[last]) * 1e-9, by_filter};
    }
};

class SpanTimer {
  public:
    SpanTimer(SpanLog& log, int seq, int filter) : log_(log) {
        if (log.on() && seq < log.rows()) {
            at_ = size_t(seq) * log.filters + filter;
            start_ = thread_cpu_ns();
        }
    }
    ~SpanTimer() {
        if (start_ >= 0) log_.ns[at_] += thread_cpu_ns() - start_;
    }
    SpanTimer(const SpanTimer&) = delete;
    SpanTimer& operator=(const SpanTimer&) = delete;

  private:
    SpanLog& log_;
    size_t at_ = 0;
    int64_t start_ = -1;
};

// The serial parts (mesh loading before the pipeline; after it the G-code assembly, the resin
// zip and the HTML report) and the pipeline's critical path against all the CPU the run used,
// with Amdahl's projection. The G-code's chunks of layers written side by side
// (`finish_parallel_s`) are work that more cores share, not serial.
std::string span_table(const SpanLog& span, const std::vector<std::string>& filter_names,
                       double load_s, double finish_s, double finish_parallel_s, int threads);

// Under CARVE_PROFILE, where the run's wall time went, phase by phase, and the process CPU
// spent before the run began (starting the process: loading its shared libraries, and
// parsing the options). On a run of a quarter second these fixed parts, which no core
// shortens, are what keeps 2 cores from 2x. The page faults of each phase are counted too:
// on a virtual machine a fault costs some 10 us, and a megabyte of fresh pages 2.5 ms.
class WallPhases {
  public:
    WallPhases();                  // at the run's start
    void mark(const char* phase);  // the phase that ends now
    std::string table() const;

  private:
    struct Phase {
        const char* name;
        double ms;
        long faults;  // page faults (minor and major)
    };
    double process_cpu_ms_at_start_ = 0;
    long faults_at_start_ = 0, last_faults_ = 0;
    std::chrono::steady_clock::time_point last_;
    std::vector<Phase> phases_;
};

// Geometry sits below the stage timer and times its booleans and morphology through a probe;
// the profile shows them as stages of their own.
void profile_geometry();

}  // namespace carve

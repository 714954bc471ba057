// The pipeline's profile: its table, and the geometry probe (see span_log.hpp).
#include "run/span_log.hpp"

#include <fmt/format.h>
#include <sys/resource.h>

#include <ctime>

#include "geometry/probe.hpp"

namespace carve {

std::string span_table(const SpanLog& span, const std::vector<std::string>& filter_names,
                       double load_s, double finish_s, double finish_parallel_s, int threads) {
    double pipeline_s = 0;
    std::string out = "pipeline filter CPU s\n";
    for (int f = 0; f < span.filters; ++f) {
        pipeline_s += span.filter_s(f);
        out += fmt::format("  {:<12} {:8.3f}{}\n", filter_names[f], span.filter_s(f),
                           span.serial[f] ? "  serial" : "  parallel");
    }
    const auto [path_s, on_path] = span.critical_path_by_filter_s();
    std::string parts;
    for (int f = 0; f < span.filters; ++f)
        if (on_path[size_t(f)] >= 0.0005)
            parts += fmt::format("{}{} {:.3f}", parts.empty() ? "" : ", ", filter_names[f],
                                 on_path[size_t(f)]);
    out += fmt::format("critical path: {}\n", parts.empty() ? "-" : parts);
    const double work_s = load_s + pipeline_s + finish_s + finish_parallel_s;
    const double serial_s = load_s + path_s + finish_s;
    const double f = work_s > 0 ? serial_s / work_s : 1;
    auto amdahl = [f](int cores) { return 1 / (f + (1 - f) / cores); };
    out += fmt::format(
        "assembly: {:.3f} s CPU in chunks of layers side by side\n"
        "serial: load {:.3f} + pipeline critical path {:.3f} + assembly {:.3f} = {:.3f} s "
        "of {:.3f} s CPU: serial fraction {:.1f} %\n"
        "Amdahl: {:.2f}x on 2 cores, {:.2f}x on 8, {:.2f}x on 16 (ran on {} threads)\n",
        finish_parallel_s, load_s, path_s, finish_s, serial_s, work_s, 100 * f, amdahl(2),
        amdahl(8), amdahl(16), threads);
    return out;
}

namespace {
double process_cpu_ms() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}
long page_faults() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return u.ru_minflt + u.ru_majflt;
}
}  // namespace

WallPhases::WallPhases()
    : process_cpu_ms_at_start_(process_cpu_ms()),
      faults_at_start_(page_faults()),
      last_faults_(faults_at_start_),
      last_(std::chrono::steady_clock::now()) {}

void WallPhases::mark(const char* phase) {
    const auto now = std::chrono::steady_clock::now();
    const long faults = page_faults();
    phases_.push_back({phase, std::chrono::duration<double, std::milli>(now - last_).count(),
                       faults - last_faults_});
    last_ = now;
    last_faults_ = faults;
}

std::string WallPhases::table() const {
    std::string ms, faults;
    double total_ms = 0;
    long total_faults = 0;
    for (const Phase& p : phases_) {
        ms += fmt::format("{}{} {:.1f}", ms.empty() ? "" : ", ", p.name, p.ms);
        faults += fmt::format("{}{} {}", faults.empty() ? "" : ", ", p.name, p.faults);
        total_ms += p.ms;
        total_faults += p.faults;
    }
    return fmt::format(
        "wall ms: {} = {:.1f} in the run, after {:.1f} ms of CPU starting the process\n"
        "page faults: {} = {} in the run, after {} starting the process\n",
        ms.empty() ? "-" : ms, total_ms, process_cpu_ms_at_start_, faults.empty() ? "-" : faults,
        total_faults, faults_at_start_);
}

void profile_geometry() {
    static const GeometryProbe probe{
        thread_cpu_ns, [](GeometryOp op, int64_t ns) {
            add_stage_time(op == GeometryOp::kBoolean ? Stage::kBoolean : Stage::kMorphology, ns);
        }};
    set_geometry_probe(&probe);
}

}  // namespace carve

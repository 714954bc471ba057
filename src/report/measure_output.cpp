// carve slice's measure of its own G-code (see measure_output.hpp).
#include "report/measure_output.hpp"

#include <chrono>
#include <memory>

#include "report/stats.hpp"

namespace carve {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

void measure_output(const std::string& gcode_path, const Mesh& mesh, const Vec3& offset,
                    OutputMeasure measure, RunResult& result) {
    if (!measure.check && !measure.strength) return;
    const auto start = std::chrono::steady_clock::now();
    std::unique_ptr<StrengthMeter> meter;
    if (measure.strength) {
        meter = std::make_unique<StrengthMeter>(measure.strength_options);
        measure.analysis.untyped_is_object = !has_type_comments(gcode_path);
        measure.analysis.object_layer = [&meter](double z, double h, const Paths& f, double v) {
            meter->layer(z, h, f, v);
        };
    }
    if (measure.check) {
        result.check = analyse_gcode_on_mesh(gcode_path, mesh, measure.analysis, offset);
        result.check_time_s = seconds_since(start);
    } else {
        // The mesh is not needed for the strength: the file alone is cheaper to read.
        measure.analysis.keep_layers = false;
        analyse_gcode(gcode_path, measure.analysis);
    }
    if (!meter) return;
    const auto solve_start = std::chrono::steady_clock::now();
    result.strength = meter->finish();
    result.strength_time_s = seconds_since(measure.check ? solve_start : start);
}

}  // namespace carve

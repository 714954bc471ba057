// The figures of one run, filled in by src/run and read by the outputs (stats JSON, summary,
// HTML report). It lives here, below src/run, so that the outputs need not include the
// orchestration that calls them.
#pragma once

#include <optional>
#include <vector>

#include "check/gcode_analysis.hpp"
#include "gcode/gcode.hpp"
#include "mesh/mesh.hpp"

namespace carve {

// Figures of one run; the stats JSON is made from these.
struct RunResult {
    MeshReport mesh;
    PrintStats print;
    int layers = 0;
    int cavities = 0;  // cavities that hold anything
    int bridges = 0;
    double bridge_length_mm = 0;
    double carvable_volume_mm3 = 0;
    std::vector<double> cavity_volume_mm3;  // per cavity C^j
    double remainder_volume_mm3 = 0;        // V^k
    double cover_volume_mm3 = 0;
    double processing_time_s = 0;
    double peak_memory_mb = 0;
    std::vector<double> layer_material_mm3;  // per layer, bottom up (for the report's plot)
    std::optional<GcodeAnalysis> check;      // with RunOptions::check_output
    double check_time_s = 0;                 // its cost, not in processing_time_s
    double material_percent() const {
        return mesh.volume_mm3 > 0 ? 100.0 * print.extruded_volume_mm3 / mesh.volume_mm3 : 0;
    }
};

}  // namespace carve

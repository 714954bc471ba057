// The figures of one run, filled in by src/run and read by the outputs (stats JSON, summary,
// HTML report). It lives here, below src/run, so that the outputs need not include the
// orchestration that calls them.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "check/gcode_analysis.hpp"
#include "check/strength.hpp"
#include "gcode/gcode.hpp"
#include "mesh/mesh.hpp"
#include "mesh/orient.hpp"
#include "toolpath/toolpath.hpp"

namespace carve {

// One orientation --orient auto tried: carved at coarse layers (so its figures compare with the
// other candidates', not with the run's own), or refused because it does not fit the printer.
struct OrientationTrial {
    OrientationCandidate candidate;
    bool fits = true;
    std::string refused;      // why it does not fit, when it does not
    double material_mm3 = 0;  // extruded, supports included
    double support_mm3 = 0;
    double print_time_s = 0;
    double overhang_mm2 = 0;     // the model's own, summed over the layers
    double layer_height_mm = 0;  // the coarse layers it was carved at
    // Stopped once its layers so far had extruded more than a lighter candidate's whole run
    // (material_mm3 is then what they had: a lower bound of its own), so it cannot be chosen.
    bool given_up = false;
    int layers_left = 0;  // of a candidate given up: its layers not carved (those lowest)
    int layers = 0;       // its coarse layers in all
};
struct OrientationChoice {
    std::vector<OrientationTrial> trials;
    size_t chosen = 0;
    double choice_time_s = 0;  // wall time of the whole choice
    // CPU time (user + system, every thread of the process) of the whole choice: what the
    // machine's load moves far less than the wall time.
    double choice_cpu_s = 0;
};

// Figures of one run; the stats JSON is made from these.
struct RunResult {
    MeshReport mesh;
    PrintStats print;
    int layers = 0;
    int cavities = 0;  // cavities that hold anything
    int bridges = 0;
    int cover_bridges = 0;  // of them, covers bridging a cavity below
    // Of them, over the report's islands (4.4.1: an empty hole of a cavity that the slice below
    // covers); the others hold edge-like minima, which the report's own code left unsupported.
    int island_bridges = 0;
    double island_bridge_length_mm = 0;
    int minima_found = 0;         // local minima and ceilings over a cavity, all slices
    int minima_unsupported = 0;   // of them, left without a support that prints
    int minima_held_by_wall = 0;  // no bridge, but within a line width of the wall below
    int minima_held_by_ribs = 0;  // no printable bridge, but ribs under them
    int ceilings_found = 0;       // of the minima, covers over a cavity below
    int ceilings_unsupported = 0;
    int ceilings_held_by_ribs = 0;
    int ribs = 0;  // rib pieces printed, all layers
    // The model's own overhang, summed over the layers: beyond the slice below by more than
    // h tan(support angle), and of that more than 2 mm beyond it (supports/overhang.hpp).
    double external_overhang_mm2 = 0;
    double far_external_overhang_mm2 = 0;
    // Of the model's slices, narrower than --min-feature-size: printed by nothing (#47).
    double unprinted_mm2 = 0;
    int unprinted_layers = 0;
    // Supports (--support): the overhang area they start under, summed over the layers, and the
    // volume of their regions (what a solid support would fill).
    double supported_area_mm2 = 0;
    double support_region_volume_mm3 = 0;
    // Extruded volume by feature (index: Feature), the remainder's solid fill apart, and the
    // walls of each cavity (index j; 0 unused).
    double feature_mm3[kFeatureCount] = {};
    double remainder_fill_mm3 = 0;
    double raft_mm3 = 0;  // the raft's lines (--raft-layers), its skirt and brim apart
    std::vector<double> cavity_wall_mm3;
    double bridge_length_mm = 0;
    double carvable_volume_mm3 = 0;
    std::vector<double> cavity_volume_mm3;  // per cavity C^j
    double remainder_volume_mm3 = 0;        // V^k
    double cover_volume_mm3 = 0;
    double processing_time_s = 0;
    double peak_memory_mb = 0;
    std::vector<double> layer_material_mm3;        // per layer, bottom up (for the report's plot)
    std::optional<OrientationChoice> orientation;  // with --orient auto
    std::optional<GcodeAnalysis> check;            // with RunOptions::check_output
    double check_time_s = 0;                       // its cost, not in processing_time_s
    std::optional<StrengthFigures> strength;       // with RunOptions::strength_output
    // Its cost, not in processing_time_s: the finite elements, and the reading of the G-code
    // unless the check read it too (then in check_time_s).
    double strength_time_s = 0;
    double material_percent() const {
        return mesh.volume_mm3 > 0 ? 100.0 * print.extruded_volume_mm3 / mesh.volume_mm3 : 0;
    }
};

}  // namespace carve

// The main job, stage after stage: load, slice, covers, carving, supports, toolpaths, G-code,
// report. Data flows one way; each stage pulls from the one before it, layer by layer.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/settings.hpp"
#include "gcode/gcode.hpp"
#include "mesh/mesh.hpp"

namespace carve {

struct RunOptions {
    std::string model_path;
    std::string gcode_path;
    std::string svg_dir;            // layer pictures, empty = none
    int svg_every = 0;              // draw every n-th layer (0 = a handful spread over the height)
    std::string raster_dir;         // resin slice stack, empty = none
    double raster_pixel_mm = 0.05;  // pixel size of the resin images
    double raster_min_wall_mm = 0.4;  // thinnest cured wall: cavity outlines are thickened to it
    std::string report_path;        // HTML report, empty = none
    bool progress = false;          // progress on stderr
    bool progress_bar = true;       // a redrawn bar (terminal), else a plain line per 10 %
    std::function<void(const std::string&)> note;  // warnings for the user (stderr)
};

// Figures of one run; the stats JSON is made from these.
struct RunResult {
    MeshReport mesh;
    PrintStats print;
    int layers = 0;
    int cavities = 0;  // cavities that hold anything
    int bridges = 0;
    int cover_bridges = 0;       // of them, covers bridging a cavity below
    int minima_found = 0;        // local minima and ceilings over a cavity, all slices
    int minima_unsupported = 0;  // of them, left without a support that prints
    int ceilings_found = 0;      // of the minima, covers over a cavity below
    int ceilings_unsupported = 0;
    // Extruded volume by feature (index: Feature), the remainder's solid fill apart, and the
    // walls of each cavity (index j; 0 unused).
    double feature_mm3[5] = {0, 0, 0, 0, 0};
    double remainder_fill_mm3 = 0;
    std::vector<double> cavity_wall_mm3;
    double bridge_length_mm = 0;
    double carvable_volume_mm3 = 0;
    std::vector<double> cavity_volume_mm3;  // per cavity C^j
    double remainder_volume_mm3 = 0;        // V^k
    double cover_volume_mm3 = 0;
    double processing_time_s = 0;
    double peak_memory_mb = 0;
    std::vector<double> layer_material_mm3;  // per layer, bottom up (for the report's plot)
    double material_percent() const {
        return mesh.volume_mm3 > 0 ? 100.0 * print.extruded_volume_mm3 / mesh.volume_mm3 : 0;
    }
};

RunResult run_slice(const Settings& settings, const RunOptions& options);

double peak_memory_mb();

}  // namespace carve

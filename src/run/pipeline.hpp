// The main job, stage after stage: load, slice, covers, carving, supports, toolpaths, G-code,
// report. Data flows one way; each stage pulls from the one before it, layer by layer.
#pragma once

#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "base/atomic_file.hpp"
#include "config/settings.hpp"
#include "report/run_result.hpp"

namespace carve {

struct RunOptions {
    std::string model_path;
    std::string gcode_path;
    std::string svg_dir;            // layer pictures, empty = none
    int svg_every = 0;              // draw every n-th layer (0 = a handful spread over the height)
    std::string raster_dir;         // resin slice stack, empty = none
    double raster_pixel_mm = 0.05;  // pixel size of the resin images
    double raster_min_wall_mm = 0.4;  // thinnest cured wall: cavity outlines are thickened to it
    std::string report_path;          // HTML report, empty = none
    std::string stats_path;           // stats JSON, empty = none
    bool progress = false;            // progress on stderr
    bool progress_bar = true;         // a redrawn bar (terminal), else a plain line per 10 %
    std::function<void(const std::string&)> note;  // warnings for the user (stderr)
    // Measure the written G-code as `carve check --mesh` does, with the loaded mesh at its
    // exact place. Off by default: it costs as much again as the slicing (CPU of the whole run,
    // cat 1.7 s -> 3.4 s, skull 3.8 s -> 8.8 s; wall on a loaded 2-core machine 3.0 -> 7.6 s
    // and 9.3 -> 17.6 s), far above the 5 % that would make it worth doing every time.
    bool check_output = false;
    // --strict: the written G-code measured as check_output does, and the run refused (RuleError,
    // nothing written) when it fails a rule of `carve check --strict`; each plate of a --cut.
    bool strict = false;
    // Measure the written G-code's strength as `carve check --strength` does (2 mm voxels,
    // linear law, the run's filament density), read together with check_output's. Off by
    // default for the same reason: see docs/check.md for what it costs.
    bool strength_output = false;
    // Called on a worker thread for each layer, in the parallel filter after its toolpaths
    // are planned. Tests throw from it to see an error in a parallel stage reach the caller.
    std::function<void(int layer)> in_parallel_stage;
    // Make every output under its temporary name and remove it at the end (the candidates of
    // --orient auto: their figures are wanted, not their G-code).
    bool discard_outputs = false;
    // A candidate of --orient auto stops (throws RunGivenUp) as soon as the layers done so far,
    // with the least the layers below them can extrude (below_at_least_mm3[i]: layers 0 .. i-1,
    // when given), extrude more than this, mm^3: a lighter candidate is known already. 0 = never.
    double give_up_above_mm3 = 0;
    std::vector<double> below_at_least_mm3;
    // When set, the run's finished outputs are handed to this group instead of renamed into
    // place: the plates of a --cut are all renamed once the last is done.
    OutputGroup* outputs_to = nullptr;
    // --plate-meshes, with --cut: each plate's pieces also as a binary STL, <-o stem>-plateN.stl,
    // where the plate's G-code prints them (for carve check --mesh, or another slicer).
    bool plate_meshes = false;
};

// What a run stopped by RunOptions::give_up_above_mm3 throws: how many of its layers were not
// carved (the stats say how early a candidate of --orient auto was given up).
struct RunGivenUp : std::runtime_error {
    RunGivenUp(const std::string& what, int left, int all)
        : std::runtime_error(what), layers_left(left), layers(all) {}
    int layers_left = 0, layers = 0;
};

RunResult run_slice(const Settings& settings, const RunOptions& options);

// --cut (settings.cutting()): the model cut into pieces, laid on the bed, arranged onto plates
// and each plate sliced as run_slice does, one G-code each (-o with -plateN before its
// extension), and an SVG of the plates' pieces, cut faces and connectors (-o's name with
// -pieces.svg for its extension); the stats JSON lists the plates and the pieces. A piece that
// cannot fit is refused before anything is sliced, and nothing is written unless every plate is
// done.
struct CutRunResult {
    std::vector<RunResult> plates;
    std::vector<std::string> gcode_paths;  // one per plate
    std::string picture_path;              // the plates seen from above (SVG), beside -o
    std::vector<std::string> mesh_paths;   // one per plate with RunOptions::plate_meshes
    size_t pieces = 0;
};
CutRunResult run_cut(const Settings& settings, const RunOptions& options);

// The threads a run uses: --threads, or every core the process may run on.
int thread_count(const Settings& settings);

double peak_memory_mb();

}  // namespace carve

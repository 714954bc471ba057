// --orient auto: every candidate orientation carved at coarse layers, one after another, each on
// the run's own parallel pipeline, its G-code made (the time estimate needs it) and thrown away.
#include "run/orient.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "base/error.hpp"
#include "base/stage_timer.hpp"

namespace carve {

namespace {

// The coarse layers the candidates are carved at: material is a sum over the layers of what
// each prints, so it changes little with their height, while the work falls with their number.
// At most the line width (a thicker layer is no print), at least twice the run's, and no more
// than about 150 of them over the model's height.
double coarse_layer_mm(const Settings& settings, double height_mm) {
    const double h = std::max(2 * settings.layer_height, height_mm / 150);
    return std::max(settings.layer_height, std::min(h, settings.width_mm()));
}

// The settings a candidate is carved with: the run's, at coarse layers with the covers as thick
// as the run's, supports on (they are what most tells orientations apart), and nothing that
// depends on the orientation the user gave (--pause-at heights) or shapes no figure.
Settings candidate_settings(const Settings& settings, double layer_mm) {
    Settings s = settings;
    s.orient = OrientMode::Given;
    s.scale = 1.0;
    s.copies = 1;
    s.layer_height = layer_mm;
    const double covers_mm = settings.covers * settings.layer_height;
    s.covers = std::max(settings.covers > 0 ? 1 : 0, int(std::lround(covers_mm / layer_mm)));
    if (s.support == SupportMode::None) s.support = SupportMode::Auto;
    s.pause_at.clear();
    s.thumbnails.clear();
    return s;
}

RunOptions candidate_options(const RunOptions& options) {
    RunOptions o;
    o.model_path = options.model_path;
    o.gcode_path = options.gcode_path;  // a temporary beside it, never renamed into place
    o.discard_outputs = true;
    return o;
}

// Less material; within half a percent, the shorter print; within half a percent of that, less
// overhang. The candidates come in order, "as given" first, so that a tie keeps the earlier.
bool better(const OrientationTrial& a, const OrientationTrial& b) {
    auto differs = [](double x, double y) { return std::fabs(x - y) > 0.005 * std::max(x, y); };
    if (differs(a.material_mm3, b.material_mm3)) return a.material_mm3 < b.material_mm3;
    if (differs(a.print_time_s, b.print_time_s)) return a.print_time_s < b.print_time_s;
    return a.overhang_mm2 < b.overhang_mm2 - 1e-6;
}

// The candidate turned, and a quarter turn about z more when that makes it fit the bed.
Mesh turned(const Mesh& mesh, OrientationCandidate& c, const Settings& settings) {
    Mesh m = mesh;
    rotate_mesh(m, c.rotation);
    const BBox3 b = bounding_box(m);
    const double x = b.max.x - b.min.x, y = b.max.y - b.min.y;
    if ((x > settings.bed_x || y > settings.bed_y) && y <= settings.bed_x && x <= settings.bed_y) {
        c.rotation = compose(quarter_turn_z(), c.rotation);
        c.name += " z+90";
        m = mesh;
        rotate_mesh(m, c.rotation);
    }
    return m;
}

OrientationTrial try_candidate(const Mesh& mesh, OrientationCandidate c, const Settings& settings,
                               const RunOptions& options, const RunResult& loaded) {
    OrientationTrial t;
    Mesh m = turned(mesh, c, settings);
    t.candidate = c;
    const BBox3 box = bounding_box(m);
    const Settings s =
        candidate_settings(settings, coarse_layer_mm(settings, box.max.z - box.min.z));
    t.layer_height_mm = s.layer_height;
    RunResult start;
    start.mesh = loaded.mesh;
    start.mesh.bbox = box;
    start.mesh.items.clear();
    RunMesh run{std::move(m), box, {}, {}};
    try {
        // The run's own limits refuse what does not fit the bed or the printer's height.
        const RunResult r =
            slice_run_mesh(s, candidate_options(options), std::move(run), std::move(start),
                           std::chrono::steady_clock::now(), thread_cpu_ns());
        t.material_mm3 = r.print.extruded_volume_mm3;
        t.support_mm3 = r.feature_mm3[size_t(Feature::Support)] +
                        r.feature_mm3[size_t(Feature::SupportInterface)];
        t.print_time_s = r.print.estimated_print_time_s;
        t.overhang_mm2 = r.external_overhang_mm2;
    } catch (const InputError& e) {
        t.fits = false;
        t.refused = e.what();
    }
    return t;
}

}  // namespace

void choose_orientation(const Settings& settings, const RunOptions& options, Mesh& mesh,
                        RunResult& result) {
    const auto start = std::chrono::steady_clock::now();
    if (result.mesh.items.size() > 1)
        throw InputError(fmt::format(
            "{}: --orient auto turns one model; this 3MF plate holds {} objects (orient each "
            "alone, or pass --orient given)",
            options.model_path, result.mesh.items.size()));
    constexpr int kHullFaces = 6;
    OrientationChoice choice;
    const std::vector<OrientationCandidate> candidates = orientation_candidates(mesh, kHullFaces);
    for (size_t k = 0; k < candidates.size(); ++k) {
        // The choice takes a few slices' time before the run's own progress starts.
        if (options.progress)
            std::fprintf(stderr, "carve: orientation %zu/%zu: %s\n", k + 1, candidates.size(),
                         describe(candidates[k]).c_str());
        choice.trials.push_back(try_candidate(mesh, candidates[k], settings, options, result));
    }
    std::optional<size_t> best;
    for (size_t k = 0; k < choice.trials.size(); ++k)
        if (choice.trials[k].fits && (!best || better(choice.trials[k], choice.trials[*best])))
            best = k;
    if (!best)
        throw InputError(
            fmt::format("{}: --orient auto: no orientation fits the printer; as "
                        "given: {}",
                        options.model_path, choice.trials.front().refused));
    choice.chosen = *best;
    rotate_mesh(mesh, choice.trials[*best].candidate.rotation);
    result.mesh.bbox = bounding_box(mesh);
    choice.choice_time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    result.orientation = std::move(choice);
}

}  // namespace carve

// --orient auto: every candidate orientation carved at coarse layers, one after another, each on
// the run's own parallel pipeline, its G-code made (the time estimate needs it) and thrown away;
// a candidate whose layers outweigh the lightest one carved before it is given up part way.
#include "run/orient.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <utility>
#include <vector>

#include "base/error.hpp"
#include "base/stage_timer.hpp"
#include "geometry/polygon.hpp"
#include "slice/slicer.hpp"

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

// The least the layers under each layer extrude: their outer walls, a line round every contour
// of their slices, and their covers, solid where a slice is not inside those `covers` above and
// below it; each taken at 0.7 of what it measures (the wall runs half a line inside, a part too
// thin to print has none, a cover's lines leave gaps at its edges).
std::vector<double> walls_and_covers_below(const Mesh& mesh, const Settings& s) {
    TopDownSlicer slicer(mesh, s.layer_height, s.model_layer_mm(0));
    std::vector<Paths> slices(size_t(std::max(slicer.layer_count(), 0)));
    while (std::optional<Slice> slice = slicer.next())
        if (size_t(slice->index) < slices.size())
            slices[size_t(slice->index)] = std::move(slice->region);
    const int n = int(slices.size());
    std::vector<double> below(slices.size(), 0.0);
    for (int i = 0; i + 1 < n; ++i) {
        const double w = s.width_mm(), h = s.model_layer_mm(i);
        const double wall = to_mm(Coord(length(slices[size_t(i)], true))) * w;
        Paths core = i >= s.covers && i + s.covers < n ? slices[size_t(i)] : Paths{};
        for (int j = i - s.covers; j <= i + s.covers && !core.empty(); ++j)
            if (j != i) core = intersect(core, slices[size_t(j)]);
        const double cover = area_mm2(slices[size_t(i)]) - area_mm2(core);
        below[size_t(i) + 1] = below[size_t(i)] + 0.7 * (wall + std::max(0.0, cover - wall)) * h;
    }
    return below;
}

// The candidate carved at the coarse layers; it stops, given up, once its layers with the least
// of those still to come (walls_and_covers_below) extrude more than `give_up_above_mm3` (0:
// never). `layer_sum_mm3` is set to what its layers extruded in all.
OrientationTrial try_candidate(const Mesh& mesh, OrientationCandidate c, const Settings& settings,
                               const RunOptions& options, const RunResult& loaded,
                               double give_up_above_mm3, double& layer_sum_mm3) {
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
        RunOptions o = candidate_options(options);
        o.give_up_above_mm3 = give_up_above_mm3;
        if (give_up_above_mm3 > 0) o.below_at_least_mm3 = walls_and_covers_below(run.mesh, s);
        const RunResult r = slice_run_mesh(s, o, std::move(run), std::move(start),
                                           std::chrono::steady_clock::now(), thread_cpu_ns());
        layer_sum_mm3 = 0;
        for (double v : r.layer_material_mm3) layer_sum_mm3 += v;
        t.material_mm3 = r.print.extruded_volume_mm3;
        t.support_mm3 = r.feature_mm3[size_t(Feature::Support)] +
                        r.feature_mm3[size_t(Feature::SupportInterface)];
        t.print_time_s = r.print.estimated_print_time_s;
        t.overhang_mm2 = r.external_overhang_mm2;
    } catch (const InputError& e) {
        t.fits = false;
        t.refused = e.what();
    } catch (const RunGivenUp&) {
        t.given_up = true;
        t.material_mm3 = give_up_above_mm3;
    }
    return t;
}

// How much the candidate's overhangs would want held up: the area of the faces that look down
// more steeply than the printer bridges, each times its height over the bed. Only an order to
// carve the candidates in (the lightest likely first, so that the others are given up early).
double hanging_estimate(const Mesh& mesh, OrientationCandidate c, const Settings& settings) {
    const Mesh m = turned(mesh, c, settings);
    const double bottom = bounding_box(m).min.z;
    const double angle =
        settings.support_angle > 0 ? settings.support_angle : settings.max_overhang;
    const double limit = -std::sin(angle * std::numbers::pi / 180);
    double sum = 0;
    for (const auto& t : m.triangles) {
        const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &d = m.vertices[t[2]];
        const Vec3 u{b.x - a.x, b.y - a.y, b.z - a.z}, v{d.x - a.x, d.y - a.y, d.z - a.z};
        const double nz = u.x * v.y - u.y * v.x;  // twice the area seen from below, signed
        const double len = std::hypot(u.y * v.z - u.z * v.y, u.z * v.x - u.x * v.z, nz);
        if (len <= 0 || nz / len > limit) continue;
        sum += -nz / 2 * ((a.z + b.z + d.z) / 3 - bottom);
    }
    return sum;
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
    // Carved in the order of what they would hang, the least first; each next one is given up
    // once its layers (summed top down), with the least the layers still to come extrude,
    // outweigh the lightest so far by kGiveUp: it cannot be the lightest, nor within the half
    // percent where the print time decides.
    constexpr double kGiveUp = 1.01;
    std::vector<double> estimate;
    for (const OrientationCandidate& c : candidates)
        estimate.push_back(hanging_estimate(mesh, c, settings));
    std::vector<size_t> order(candidates.size());
    for (size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return estimate[a] < estimate[b]; });
    choice.trials.resize(candidates.size());
    double lightest = 0;  // the least any candidate's layers extruded in all, 0 before the first
    for (size_t n = 0; n < order.size(); ++n) {
        const size_t k = order[n];
        // The choice takes a few slices' time before the run's own progress starts.
        if (options.progress)
            std::fprintf(stderr, "carve: orientation %zu/%zu: %s\n", n + 1, candidates.size(),
                         describe(candidates[k]).c_str());
        double layers_mm3 = 0;
        choice.trials[k] = try_candidate(mesh, candidates[k], settings, options, result,
                                         lightest * kGiveUp, layers_mm3);
        const OrientationTrial& t = choice.trials[k];
        if (t.fits && !t.given_up && (lightest == 0 || layers_mm3 < lightest))
            lightest = layers_mm3;
    }
    // In the candidates' own order, so that a tie keeps the earlier.
    std::optional<size_t> best;
    for (size_t k = 0; k < choice.trials.size(); ++k) {
        const OrientationTrial& t = choice.trials[k];
        if (t.fits && !t.given_up && (!best || better(t, choice.trials[*best]))) best = k;
    }
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

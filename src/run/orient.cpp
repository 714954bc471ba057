// --orient auto: every candidate orientation carved at coarse layers, one after another, each on
// the run's own parallel pipeline, its G-code made (the time estimate needs it) and thrown away;
// a candidate whose layers, with the least those below them extrude (their outer walls, covers
// and supports, from a slicing and support-planning pass of their own), outweigh the lightest
// one carved before it is given up part way.
#include "run/orient.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <memory>
#include <numbers>
#include <optional>
#include <utility>
#include <vector>

#include "base/error.hpp"
#include "base/stage_timer.hpp"
#include "carving/covers.hpp"
#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"
#include "run/run_setup.hpp"
#include "slice/slicer.hpp"
#include "supports/support_volume.hpp"

namespace carve {

namespace {

// The process's CPU time, every thread's, user and system.
double process_cpu_s() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + double(ts.tv_nsec) * 1e-9;
}

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

// What share of the outer wall, of the covers and of the supports the bound counts. The wall's
// centreline is the contour of the slice eroded by half a line (carving/covers.cpp), the very
// loops the wall prints: its length measures the wall within rounding (the candidates of the
// shared models: 0.997 to 1.001 of their outer wall). The covers' measure leaves out what is
// solid only for the carving's shells, so it runs below their lines. The supports are planned
// here as the run plans them (the same planner fed the same outlines), and measured as their
// loops, single walls, sparse lines and dense interface would print, less what the lines lose at
// their ends.
constexpr double kWallShare = 0.97, kCoverShare = 0.85, kSupportShare = 0.8;

// The least a layer's supports extrude, mm^2 of line (times the layer's thickness: mm^3).
double support_least_mm2(const SupportLayer& support, const Settings& s) {
    const double w = s.width_mm();
    double line_mm = to_mm(Coord(length(support.walls, false)));
    double area_mm2_sparse = 0, area_mm2_dense = 0;
    if (!support.region.empty()) {
        const Paths body = support.interface.empty() ? support.region
                                                     : subtract(support.region, support.interface);
        const Paths inner = erode(body, s.nozzle_radius());
        line_mm += to_mm(Coord(length(inner, true)));
        area_mm2_sparse = area_mm2(inner);
        area_mm2_dense = area_mm2(erode(support.interface, s.nozzle_radius()));
    }
    // The sparse lines 2.5 mm apart (toolpath.cpp), the interface's 2 w apart.
    return line_mm * w + area_mm2_sparse * w / 2.5 + area_mm2_dense / 2;
}

// The least the layers under each layer extrude: their outer walls, the loops round every
// contour of their slices eroded by half a line; their covers, solid where a slice is not
// inside those `covers` above and below it, less the wall's own strip; and their supports.
std::vector<double> least_extruded_below(const Mesh& mesh, const Settings& s, double z0) {
    TopDownSlicer slicer(mesh, s.layer_height, s.model_layer_mm(0));
    const int n = std::max(slicer.layer_count(), 0);
    std::vector<CoverSlice> slices(static_cast<size_t>(n));
    while (std::optional<Slice> slice = slicer.next())
        if (slice->index >= 0 && slice->index < n) {
            const size_t i = size_t(slice->index);
            slices[i] = cover_slice(std::move(*slice), s);
        }
    std::vector<double> support(size_t(n), 0.0);
    if (s.support != SupportMode::None) {
        std::unique_ptr<ModelShadow> shadow;
        if (s.support == SupportMode::Buildplate)
            shadow = std::make_unique<ModelShadow>(mesh.vertices, mesh.triangles, 0.5);
        SupportPlanner planner(support_options(s, z0), shadow.get());
        auto plan_ready = [&](bool finished) {
            for (int r = planner.ready(finished); r >= 0; r = planner.ready(finished))
                support[size_t(r)] = support_least_mm2(planner.plan(r), s);
        };
        for (int i = n - 1; i >= 0; --i) {
            planner.add_outline(i, slices[size_t(i)].slice.region);
            plan_ready(false);
        }
        plan_ready(true);
    }
    std::vector<double> below(size_t(n), 0.0);
    for (int i = 0; i + 1 < n; ++i) {
        const double w = std::min(s.width_mm(), s.layer_width_mm(i));
        const double h = s.model_layer_mm(i) * s.extrusion_multiplier;
        const Paths& region = slices[size_t(i)].slice.region;
        const double wall = to_mm(Coord(length(slices[size_t(i)].wall_region, true))) * w;
        Paths core = i >= s.covers && i + s.covers < n ? region : Paths{};
        for (int j = i - s.covers; j <= i + s.covers && !core.empty(); ++j)
            if (j != i) core = intersect(core, slices[size_t(j)].slice.region);
        const double cover = std::max(0.0, area_mm2(region) - area_mm2(core) - wall);
        below[size_t(i) + 1] =
            below[size_t(i)] +
            (kWallShare * wall + kCoverShare * cover + kSupportShare * support[size_t(i)]) * h;
    }
    return below;
}

// The candidate carved at the coarse layers; it stops, given up, once its layers with the least
// of those still to come (least_extruded_below) extrude more than `give_up_above_mm3` (0:
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
        // Before the bound's pass, which a candidate that does not fit would waste.
        check_run_size(s, o, box);
        if (give_up_above_mm3 > 0) {
            o.below_at_least_mm3 = least_extruded_below(run.mesh, s, box.min.z);
            // Heavier by the bound alone: given up before the pipeline starts, whose layers in
            // flight would be carved for nothing (the pipeline would give it up at its top).
            const std::vector<double>& b = o.below_at_least_mm3;
            if (!b.empty() && b.back() > give_up_above_mm3)
                throw RunGivenUp("heavier than a candidate already carved by its bound alone",
                                 int(b.size()), int(b.size()));
        }
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
    } catch (const RunGivenUp& e) {
        t.given_up = true;
        t.layers_left = e.layers_left;
        t.layers = e.layers;
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
    const double start_cpu_s = process_cpu_s();
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
    choice.choice_cpu_s = process_cpu_s() - start_cpu_s;
    result.orientation = std::move(choice);
}

}  // namespace carve

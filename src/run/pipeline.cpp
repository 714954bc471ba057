// Runs the stages in order and gathers the figures of the run.
#include "run/pipeline.hpp"

#include <fmt/format.h>
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>

#include "base/atomic_file.hpp"
#include "base/error.hpp"
#include "base/stage_timer.hpp"
#include "carving/carving.hpp"
#include "geometry/polygon.hpp"
#include "geometry/probe.hpp"
#include "report/html_report.hpp"
#include "report/stats.hpp"
#include "report/svg.hpp"
#include "resin/raster.hpp"
#include "run/layer_queue.hpp"
#include "slice/slicer.hpp"
#include "supports/bridges.hpp"
#include "toolpath/toolpath.hpp"

namespace carve {

double peak_memory_mb() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_maxrss / 1024.0;  // Linux reports kilobytes
}

namespace {

void progress_bar(int done, int total, double elapsed_s) {
    const int width = 30;
    const double f = total > 0 ? double(done) / total : 1.0;
    const int filled = static_cast<int>(f * width);
    const double left = f > 0 ? elapsed_s * (1 - f) / f : 0;
    std::fprintf(stderr, "\r[%.*s%*s] %d/%d layers, %.0f s left ", filled,
                 "##############################", width - filled, "", done, total, left);
    if (done == total) std::fputc('\n', stderr);
    std::fflush(stderr);
}

// Without a terminal (a log file, a pipe, a CI job) a redrawn bar would be one long line full
// of carriage returns: plain lines instead.
void progress_line(int done, int total, double elapsed_s) {
    const double f = total > 0 ? double(done) / total : 1.0;
    const double left = f > 0 ? elapsed_s * (1 - f) / f : 0;
    std::fprintf(stderr, "carve: %d/%d layers (%.0f %%), %.0f s left\n", done, total, 100 * f,
                 left);
    std::fflush(stderr);
}

double toolpath_volume_mm3(const LayerToolpaths& paths, const Settings& settings) {
    double v = 0;
    for (const Extrusion& e : paths.extrusions)
        v += to_mm(static_cast<Coord>(length(Paths{e.points}, e.closed))) * settings.nozzle *
             settings.layer_height * e.flow;
    return v;
}

// Geometry sits below the stage timer and times its booleans and morphology through a probe;
// the profile shows them as stages of their own.
void profile_geometry() {
    static const GeometryProbe probe{
        thread_cpu_ns, [](GeometryOp op, int64_t ns) {
            add_stage_time(op == GeometryOp::kBoolean ? Stage::kBoolean : Stage::kMorphology, ns);
        }};
    set_geometry_probe(&probe);
}

}  // namespace

RunResult run_slice(const Settings& settings, const RunOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    auto note = [&](const std::string& s) {
        if (options.note) options.note(s);
    };
    RunResult result;
    if (profiling_enabled()) profile_geometry();

    Mesh mesh = load_mesh(options.model_path, result.mesh);
    for (const std::string& w : result.mesh.warnings) note(w);
    // A triangle soup (most edges belong to one triangle only) is no solid: its slices are
    // thousands of crossing segments whose union costs the square of their number (5,000
    // random triangles ran for minutes). An open mesh with a hole has a few open edges.
    const MeshReport& m = result.mesh;
    if (m.triangles_read > 1000 && m.open_edges * 2 > 3 * m.triangles_read)
        throw InputError(fmt::format(
            "{}: not a solid: {} of the {} triangles' edges are shared with no other triangle "
            "(a triangle soup); repair the mesh first",
            options.model_path, m.open_edges, 3 * m.triangles_read));
    if (settings.scale != 1.0) {
        // Scale about the bottom centre so that the model stays on the bed where it was.
        const BBox3 b = result.mesh.bbox;
        const Vec3 c{(b.min.x + b.max.x) / 2, (b.min.y + b.max.y) / 2, b.min.z};
        for (Vec3& v : mesh.vertices)
            v = {c.x + (v.x - c.x) * settings.scale, c.y + (v.y - c.y) * settings.scale,
                 c.z + (v.z - c.z) * settings.scale};
        result.mesh.bbox = bounding_box(mesh);
        result.mesh.volume_mm3 = signed_volume(mesh);
    }
    const BBox3& box = result.mesh.bbox;
    const double size_x = box.max.x - box.min.x, size_y = box.max.y - box.min.y;
    if (settings.bed_check && (size_x > settings.bed_x || size_y > settings.bed_y))
        throw InputError(fmt::format(
            "{}: the model ({:.1f} x {:.1f} mm) is larger than the bed ({:.0f} x {:.0f} mm); "
            "scale it down, choose a larger --bed, or pass --no-bed-check",
            options.model_path, size_x, size_y, settings.bed_x, settings.bed_y));
    const double offset_x = settings.bed_x / 2 - (box.min.x + box.max.x) / 2;
    const double offset_y = settings.bed_y / 2 - (box.min.y + box.max.y) / 2;

    // Scale times size: the work grows with (size / line width)^2 per layer and with the
    // number of layers. A model 5 m across at 0.05 mm lines, or a million layers, is refused
    // before slicing starts (with --no-bed-check and --scale 100 nothing else stops it).
    const double size_z = box.max.z - box.min.z;
    constexpr double kMaxLinesAcross = 100000, kMaxLayers = 200000;
    if (std::max(size_x, size_y) / settings.nozzle > kMaxLinesAcross ||
        size_z / settings.layer_height > kMaxLayers)
        throw InputError(fmt::format(
            "{}: the model ({:.1f} x {:.1f} x {:.1f} mm) is too large for the {} mm nozzle and "
            "{} mm layers (limits: {:.0f} line widths across, {:.0f} layers); scale it down",
            options.model_path, size_x, size_y, size_z, settings.nozzle, settings.layer_height,
            kMaxLinesAcross, kMaxLayers));
    TopDownSlicer slicer(mesh, settings.layer_height);
    const int layer_count = slicer.layer_count();
    if (layer_count == 0)
        throw InputError(fmt::format("{}: the model is thinner than one layer ({} mm)",
                                     options.model_path, settings.layer_height));
    if (settings.max_vertices_per_layer > 0 || settings.max_vertices_total > 0) {
        // Checked as each slice is cut, before covers and carving spend hours on it.
        slicer.on_slice([&settings, &options, total = 0LL](const Slice& slice) mutable {
            long long vertices = 0;
            for (const Path& p : slice.region) vertices += static_cast<long long>(p.size());
            total += vertices;
            if (settings.max_vertices_total > 0 && total > settings.max_vertices_total)
                throw InputError(fmt::format(
                    "{}: the slices down to layer {} (z = {:.2f} mm) hold {} contour vertices, "
                    "more than the limit of {}; simplify the mesh or raise --max-vertices "
                    "(0 = no limit)",
                    options.model_path, slice.index, slice.z, total, settings.max_vertices_total));
            if (settings.max_vertices_per_layer > 0 && vertices > settings.max_vertices_per_layer)
                throw InputError(fmt::format(
                    "{}: layer {} (z = {:.2f} mm) has {} contour vertices, more than the limit of "
                    "{}; simplify the mesh or raise --max-vertices-per-layer (0 = no limit)",
                    options.model_path, slice.index, slice.z, vertices,
                    settings.max_vertices_per_layer));
        });
    }
    CarvableStream carvable(slicer, settings);
    // Up to five threads, each a stretch of the stream handing layers on through a bounded
    // queue: slicing and covers; the first carving iteration (C^1); the others (C^2..C^k);
    // bridges; toolpaths and G-code. Each sweep stage must run in slice order, but C^1 of a
    // slice only needs C^1 of the slice above, so the two sweep stages overlap like a
    // wavefront. Fewer threads merge neighbouring stretches, cutting first where the work is
    // most even (2: slicing and the sweep | the rest; 3: also after C^1; 4: also after the
    // covers). On two cores the threads mostly just keep both busy; the total CPU is the limit.
    // Each queue is declared after the stage its thread pulls from, so that when an error
    // unwinds this frame the thread is joined before that stage is destroyed.
    auto queue_after = [&settings](LayerSource& stage, int min_threads) {
        return settings.threads >= min_threads ? std::make_unique<ThreadedSource>(stage)
                                               : std::unique_ptr<ThreadedSource>{};
    };
    auto from = [](std::unique_ptr<ThreadedSource>& queue, LayerSource& stage) -> LayerSource& {
        return queue ? static_cast<LayerSource&>(*queue) : stage;
    };
    auto sliced = queue_after(carvable, 4);
    CarvingSweep first_cavity(from(sliced, carvable), settings, 0, 1);
    auto first_carved = queue_after(first_cavity, 3);
    CarvingSweep other_cavities(from(first_carved, first_cavity), settings, 1);
    auto carved = queue_after(other_cavities, 2);
    BridgeStage bridged(from(carved, other_cavities), settings);
    auto supported = queue_after(bridged, 5);
    LayerSource& supports = from(supported, bridged);
    // Every output of the run is complete under a temporary name before any is renamed into
    // place (group.commit_all() at the end); a run failing at any point leaves none of them,
    // and the folders of pictures are written into temporary folders moved in at the end.
    // The group is declared first so that it is destroyed last: the writers it holds back
    // remove their temporaries when an error unwinds this frame.
    OutputGroup group;
    GcodeWriter writer(options.gcode_path, settings, offset_x, offset_y, layer_count);
    writer.commit_with(group);
    std::unique_ptr<AtomicDir> svg_dir, raster_dir;
    std::unique_ptr<SvgLayerWriter> svg;
    if (!options.svg_dir.empty()) {
        svg_dir = std::make_unique<AtomicDir>(options.svg_dir);
        svg = std::make_unique<SvgLayerWriter>(
            options.svg_every > 0
                ? SvgLayerWriter::every(svg_dir->folder(), options.svg_every)
                : SvgLayerWriter(svg_dir->folder(), SvgLayerWriter::spread(layer_count, 8)));
    }
    std::unique_ptr<HtmlReportWriter> html;
    if (!options.report_path.empty()) {
        html = std::make_unique<HtmlReportWriter>(options.report_path, settings);
        html->commit_with(group);
    }
    if (html) html->set_model_name(options.model_path);
    std::unique_ptr<RasterWriter> raster;
    if (!options.raster_dir.empty()) {
        raster_dir = std::make_unique<AtomicDir>(options.raster_dir);
        const BBox2 footprint{to_units(box.min.x), to_units(box.min.y), to_units(box.max.x),
                              to_units(box.max.y), false};
        raster =
            std::make_unique<RasterWriter>(raster_dir->folder(), settings, footprint,
                                           options.raster_pixel_mm, options.raster_min_wall_mm);
    }

    result.layers = layer_count;
    result.cavity_volume_mm3.assign(sweep_iterations(settings), 0.0);
    result.layer_material_mm3.assign(layer_count, 0.0);
    const double h = settings.layer_height;
    int done = 0;
    double sliced_volume = 0;  // what the slices hold: the model's volume if the mesh is open
    while (auto layer = supports.next()) {
        for (const std::string& w : layer->warnings) note(w);
        LayerToolpaths paths = plan_layer(*layer, settings);
        if (svg) svg->add(*layer, &paths);
        if (html) html->add_layer(*layer, paths);
        if (raster) raster->add_layer(*layer);
        writer.add_layer(paths);

        sliced_volume += area_mm2(layer->outline) * h;
        result.carvable_volume_mm3 += area_mm2(layer->carvable) * h;
        for (size_t j = 0; j < layer->cavities.size(); ++j)
            result.cavity_volume_mm3[j] += area_mm2(layer->cavities[j]) * h;
        result.remainder_volume_mm3 += area_mm2(layer->remainder) * h;
        result.cover_volume_mm3 += area_mm2(layer->covers) * h;
        result.layer_material_mm3[layer->index] = toolpath_volume_mm3(paths, settings);
        result.minima_found += layer->minima_found;
        result.minima_unsupported += layer->minima_unsupported;
        result.minima_held_by_wall += layer->minima_held_by_wall;
        result.ceilings_found += layer->ceilings_found;
        result.ceilings_unsupported += layer->ceilings_unsupported;
        for (const Extrusion& e : paths.extrusions) {
            const double v = to_mm(static_cast<Coord>(length(Paths{e.points}, e.closed))) *
                             settings.nozzle * settings.layer_height * e.flow;
            int f = static_cast<int>(e.feature);
            if (e.feature == Feature::CavityWall) {
                if (result.cavity_wall_mm3.size() <= size_t(e.cavity))
                    result.cavity_wall_mm3.resize(e.cavity + 1, 0.0);
                result.cavity_wall_mm3[e.cavity] += v;
            }
            if (e.feature == Feature::Cover && e.cavity < 0) f = -1;
            if (f >= 0)
                result.feature_mm3[f] += v;
            else
                result.remainder_fill_mm3 += v;
        }
        for (const Bridge& b : layer->bridges) {
            ++result.bridges;
            if (b.cover) ++result.cover_bridges;
            result.bridge_length_mm += to_mm(static_cast<Coord>(length(b.lines, false)));
        }
        ++done;
        const int tenth = std::max(1, layer_count / 10);
        if (options.progress && options.progress_bar && (done % 10 == 0 || done == layer_count)) {
            const double t =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            progress_bar(done, layer_count, t);
        } else if (options.progress && !options.progress_bar &&
                   (done % tenth == 0 || done == layer_count)) {
            const double t =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            progress_line(done, layer_count, t);
        }
    }
    for (double v : result.cavity_volume_mm3)
        if (v > 0) ++result.cavities;
    // An open mesh has no inside of its own: its signed volume depends on where the hole is
    // (a cube missing its top gives 2/3 of the cube), while the slicer closes each slice with
    // non-zero fill. What is printed, and what "% of the model" means, is the sliced volume.
    if (!result.mesh.closed()) result.mesh.volume_mm3 = sliced_volume;

    double material = 0;
    for (double v : result.layer_material_mm3) material += v;
    if (material <= 0)
        throw InputError(fmt::format(
            "{}: nothing to print: every part of the model is thinner than the {} mm line width",
            options.model_path, settings.nozzle));

    std::vector<std::string> header{
        fmt::format("model = {}", options.model_path),
        fmt::format("model_volume_mm3 = {:.1f}", result.mesh.volume_mm3),
        fmt::format("cavities = {}", result.cavities),
    };
    result.print = writer.finish(header);
    result.processing_time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (options.check_output) {
        // The mesh is where the slicer had it: moved by the bed offset, its lowest point on z = 0.
        const auto check_start = std::chrono::steady_clock::now();
        GcodeAnalysisOptions check_options;
        check_options.filament_diameter_mm = settings.filament_diameter;
        check_options.keep_layers = false;
        result.check = analyse_gcode_on_mesh(writer.written_path(), mesh, check_options,
                                             Vec3{offset_x, offset_y, -box.min.z});
        result.check_time_s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - check_start).count();
    }
    if (raster) raster->finish();
    result.peak_memory_mb = peak_memory_mb();
    if (html) html->finish(result, stats_json(result, settings));
    if (!options.stats_path.empty())
        write_file_atomically(options.stats_path, stats_json(result, settings).dump(2) + "\n",
                              &group);
    if (svg_dir) group.hold(std::move(svg_dir));
    if (raster_dir) group.hold(std::move(raster_dir));
    group.commit_all();
    if (profiling_enabled()) std::fputs(profile_table().c_str(), stderr);
    return result;
}

}  // namespace carve

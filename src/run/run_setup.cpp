// What the run does before its layers flow: the mesh loaded and placed, the limits checked,
// the G-code's objects named, the outputs opened (see run_setup.hpp).
#include "run/run_setup.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <utility>

#include "base/error.hpp"
#include "base/numbers.hpp"
#include "carving/covers.hpp"
#include "gcode/labels.hpp"
#include "gcode/thumbnail.hpp"
#include "geometry/polygon.hpp"
#include "report/stats.hpp"
#include "run/layer_figures.hpp"
#include "run/orient.hpp"
#include "toolpath/raft.hpp"
#include "toolpath/skirt.hpp"

namespace carve {

RunMesh load_run_mesh(const Settings& settings, const RunOptions& options, RunResult& result,
                      const std::function<void(const std::string&)>& note) {
    RunMesh run;
    // A triangle soup cannot be sliced (see is_triangle_soup); the loader refuses it as soon as
    // its edges are counted, before the rest of the repair spends memory on it.
    LoadOptions load_options;
    load_options.refuse_soup = true;
    run.mesh = load_mesh(options.model_path, result.mesh, load_options);
    for (const std::string& w : result.mesh.warnings) note(w);
    run.loaded_box = result.mesh.bbox;  // before scaling: the 3MF items' frame
    if (settings.scale != 1.0) {
        // Scale about the bottom centre so that the model stays on the bed where it was.
        const BBox3 b = result.mesh.bbox;
        const Vec3 c{(b.min.x + b.max.x) / 2, (b.min.y + b.max.y) / 2, b.min.z};
        for (Vec3& v : run.mesh.vertices)
            v = {c.x + (v.x - c.x) * settings.scale, c.y + (v.y - c.y) * settings.scale,
                 c.z + (v.z - c.z) * settings.scale};
        result.mesh.bbox = bounding_box(run.mesh);
        result.mesh.volume_mm3 = signed_volume(run.mesh);
    }
    // Turned before it is copied: each copy lies as the one chosen.
    if (settings.orient == OrientMode::Auto)
        choose_orientation(settings, options, run.mesh, result);
    if (settings.copies > 1) {
        // The copies are one mesh of disjoint shells: every stage works on them as on islands
        // of one model; only the G-code labels each copy as its own object.
        run.mesh = arrange_copies(run.mesh, settings.copies, settings.copy_gap, run.copy_boxes);
        result.mesh.bbox = bounding_box(run.mesh);
        result.mesh.volume_mm3 = signed_volume(run.mesh);
    }
    return run;
}

Placement centre_on_bed(const Settings& settings, const BBox3& box) {
    Placement place;
    place.offset_x = settings.bed_x / 2 - (box.min.x + box.max.x) / 2;
    place.offset_y = settings.bed_y / 2 - (box.min.y + box.max.y) / 2;
    place.z0 = box.min.z;
    return place;
}

void check_run_size(const Settings& settings, const RunOptions& options, const BBox3& box) {
    const double size_x = box.max.x - box.min.x, size_y = box.max.y - box.min.y;
    if (settings.bed_check && (size_x > settings.bed_x || size_y > settings.bed_y))
        throw InputError(fmt::format(
            "{}: the model{} ({:.1f} x {:.1f} mm) is larger than the bed ({:.0f} x {:.0f} mm); "
            "{}scale it down, choose a larger --bed, or pass --no-bed-check",
            options.model_path,
            settings.copies > 1 ? fmt::format(" in {} copies", settings.copies) : "", size_x,
            size_y, settings.bed_x, settings.bed_y,
            settings.copies > 1 ? "print fewer copies, " : ""));

    // Printed into the gantry otherwise; the supports and brim add nothing above the model, a
    // raft the height it lifts the model by, --z-offset what it adds to every Z (a 205 mm
    // tower with --z-offset 10 extruded at Z 215 on a 210 mm printer, issue #52).
    const double height = box.max.z - box.min.z + settings.model_base_mm();
    if (settings.bed_check && height + settings.z_offset > settings.max_print_height + 1e-6)
        throw InputError(fmt::format(
            "{}: the model is {:.1f} mm tall{}{}, taller than the {} mm the printer prints "
            "(--max-print-height, a profile's max_print_height); scale it down, choose a "
            "taller printer, or pass --no-bed-check",
            options.model_path, height, settings.raft_layers > 0 ? " on its raft" : "",
            settings.z_offset != 0
                ? fmt::format(" and printed at Z {:.2f} with --z-offset {} (a profile's "
                              "z_offset)",
                              height + settings.z_offset, plain_number(settings.z_offset))
                : "",
            plain_number(settings.max_print_height)));
    // A pause above the model's top would never come: the run asked for a colour change that
    // no layer reaches.
    const double model_height = box.max.z - box.min.z;
    for (double z : settings.pause_at)
        if (z > model_height + 1e-6)
            throw InputError(fmt::format(
                "{}: --pause-at {} mm is above the model's top ({:.2f} mm): no layer reaches it",
                options.model_path, plain_number(z), model_height));

    // Scale times size: the work grows with (size / line width)^2 per layer and with the
    // number of layers. A model 5 m across at 0.05 mm lines, or a million layers, is refused
    // before slicing starts (with --no-bed-check and --scale 100 nothing else stops it).
    const double size_z = box.max.z - box.min.z;
    constexpr double kMaxLinesAcross = 100000, kMaxLayers = 200000;
    // The line width, not the nozzle: --extrusion-width may be far thinner than the nozzle.
    const double line_mm = std::min(settings.nozzle, settings.width_mm());
    if (std::max(size_x, size_y) / line_mm > kMaxLinesAcross ||
        size_z / settings.layer_height > kMaxLayers)
        throw InputError(fmt::format(
            "{}: the model ({:.1f} x {:.1f} x {:.1f} mm) is too large for {} mm lines and "
            "{} mm layers (limits: {:.0f} line widths across, {:.0f} layers); scale it down",
            options.model_path, size_x, size_y, size_z, line_mm, settings.layer_height,
            kMaxLinesAcross, kMaxLayers));
}

void check_loops_on_bed(const FirstLayerLoops& loops, const Paths& raft, const Settings& settings,
                        const RunOptions& options, double offset_x, double offset_y) {
    if (!settings.bed_check) return;
    auto check = [&](const Paths& paths, const char* what, const char* options_to_change) {
        if (paths.empty()) return;
        const BBox2 b = bounds(paths);
        const double min_x = to_mm(b.min_x) + offset_x, max_x = to_mm(b.max_x) + offset_x;
        const double min_y = to_mm(b.min_y) + offset_y, max_y = to_mm(b.max_y) + offset_y;
        const double out =
            std::max({-min_x, -min_y, max_x - settings.bed_x, max_y - settings.bed_y});
        if (out > 1e-3)
            throw InputError(fmt::format(
                "{}: the {} reaches {:.1f} mm beyond the {:.0f} x {:.0f} mm bed (it spans X {:.1f} "
                "to {:.1f}, Y {:.1f} to {:.1f}); lower {}, or pass --no-bed-check",
                options.model_path, what, out, settings.bed_x, settings.bed_y, min_x, max_x, min_y,
                max_y, options_to_change));
    };
    check(raft, "raft", "--raft-first-layer-expansion and --raft-expansion");
    check(loops.brim, "brim", "--brim-width");
    check(loops.skirt, "skirt", "--skirt-distance or --skirts (0: none)");
}

void check_plane_segments(const TopDownSlicer& slicer, const Settings& settings,
                          const RunOptions& options) {
    if (settings.max_vertices_per_layer <= 0 && settings.max_vertices_total <= 0) return;
    // Twice the limits: a quad split into two triangles gives two segments for each contour
    // vertex, the one on the diagonal dropped as straight when the loop is cleaned, and the
    // limits themselves stay on the slices' vertices (vertex_limits()). Only a mesh with more
    // than twice the limit of segments is refused here, and whatever cleaning could do.
    const std::vector<uint32_t> segments = slicer.plane_segments();
    long long total = 0;
    for (int i = int(segments.size()) - 1; i >= 0; --i) {
        const long long cut = segments[size_t(i)];
        total += cut;
        if (settings.max_vertices_total > 0 && total > 2 * settings.max_vertices_total)
            throw InputError(fmt::format(
                "{}: the slices down to layer {} (z = {:.2f} mm) cut {} segments, more than "
                "twice the limit of {} contour vertices before any simplification; simplify the "
                "mesh or raise --max-vertices (0 = no limit)",
                options.model_path, i, slicer.plane_z(i), total, settings.max_vertices_total));
        if (settings.max_vertices_per_layer > 0 && cut > 2 * settings.max_vertices_per_layer)
            throw InputError(fmt::format(
                "{}: layer {} (z = {:.2f} mm) cuts {} segments, more than twice the limit of {} "
                "contour vertices before any simplification; simplify the mesh or raise "
                "--max-vertices-per-layer (0 = no limit)",
                options.model_path, i, slicer.plane_z(i), cut, settings.max_vertices_per_layer));
    }
}

std::function<void(const Slice&)> vertex_limits(const Settings& settings,
                                                const RunOptions& options) {
    if (settings.max_vertices_per_layer <= 0 && settings.max_vertices_total <= 0) return {};
    // Checked as each slice is cut, in order, before covers and carving spend hours on it.
    return [&settings, &options, total = 0LL](const Slice& slice) mutable {
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
    };
}

void label_objects(GcodeWriter& writer, const RunOptions& options, const Settings& settings,
                   const RunMesh& run_mesh, const RunResult& result) {
    const std::vector<CopyBox>& copy_boxes = run_mesh.copy_boxes;
    const BBox3& loaded_box = run_mesh.loaded_box;
    writer.set_object_name(object_label(options.model_path));
    if (!copy_boxes.empty()) {
        std::vector<ObjectLabel> objects;
        for (size_t k = 0; k < copy_boxes.size(); ++k) {
            const CopyBox& c = copy_boxes[k];
            objects.push_back({k < run_mesh.object_names.size()
                                   ? object_label(run_mesh.object_names[k])
                                   : fmt::format("{}_{}", object_label(options.model_path), k + 1),
                               c.min_x, c.min_y, c.max_x, c.max_y});
        }
        writer.set_objects(std::move(objects));
    } else if (result.mesh.items.size() > 1) {
        // A 3MF plate of several build items: each labelled as the object it is, scaled as the
        // mesh was (about its bottom centre), named as the file names it (made safe, and
        // numbered when two share a name).
        std::vector<ObjectLabel> objects;
        const double s = settings.scale;
        const double cx = (loaded_box.min.x + loaded_box.max.x) / 2;
        const double cy = (loaded_box.min.y + loaded_box.max.y) / 2;
        std::map<std::string, int> seen;
        for (const MeshReport::BuildItem& it : result.mesh.items) {
            std::string name = object_label(it.name);
            if (++seen[name] > 1) name += fmt::format("_{}", seen[name]);
            objects.push_back({name, cx + (it.min_x - cx) * s, cy + (it.min_y - cy) * s,
                               cx + (it.max_x - cx) * s, cy + (it.max_y - cy) * s});
        }
        writer.set_objects(std::move(objects));
    }
}

std::vector<Point> skirt_shield_points(const Mesh& mesh, double bottom, const Settings& settings) {
    // The skirt's last layer, numbered as the model's; the model's first layer is the first
    // slice itself (and a raft's layers are under the model).
    const int last = settings.first_print_layer() + settings.skirt_height - 1;
    if (settings.skirts <= 0 || last < (settings.raft_layers > 0 ? 0 : 1)) return {};
    const double top = bottom + settings.layer_top_mm(last) - settings.model_base_mm();
    // The convex hull of every slice up to `top` is that of the model's part below it: of its
    // vertices below and of the points where its edges cross that height.
    std::vector<Point> points;
    auto add = [&](double x, double y) { points.push_back(Point{to_units(x), to_units(y)}); };
    for (const Vec3& v : mesh.vertices)
        if (v.z <= top) add(v.x, v.y);
    for (const auto& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) {
            const Vec3& a = mesh.vertices[t[size_t(k)]];
            const Vec3& b = mesh.vertices[t[size_t(k + 1) % 3]];
            if ((a.z < top) == (b.z < top)) continue;
            const double f = (top - a.z) / (b.z - a.z);
            add(a.x + f * (b.x - a.x), a.y + f * (b.y - a.y));
        }
    return points;
}

int checked_layer_count(const TopDownSlicer& slicer, const Settings& settings,
                        const RunOptions& options) {
    const int layer_count = slicer.layer_count();
    if (layer_count == 0)
        throw InputError(fmt::format("{}: the model is thinner than one layer ({} mm)",
                                     options.model_path, settings.layer_height));
    return layer_count;
}

RunOutputs::RunOutputs(const Settings& settings, const RunOptions& options, const RunMesh& run_mesh,
                       RunResult& result, int layer_count, const Placement& place)
    : writer(options.gcode_path, settings, place.offset_x, place.offset_y,
             layer_count + settings.raft_layers) {
    const Mesh& mesh = run_mesh.mesh;
    const BBox3& box = result.mesh.bbox;
    writer.commit_with(group);
    label_objects(writer, options, settings, run_mesh, result);
    // Skirt and brim from the first layer's slice, cut ahead of the sweep (which reaches the
    // first layer last, after the skirt's other layers), and held against the bed now: a run
    // whose skirt or brim would leave the bed stops before any work, with one line.
    const Paths first_slice =
        compensated_slice(slice_at(mesh, box.min.z + settings.layer_middle_mm(0)), 0, settings);
    Raft raft = plan_raft(first_slice, settings);
    first_loops = plan_skirt_and_brim(settings.raft_layers > 0 ? raft.footprint : first_slice,
                                      settings, skirt_shield_points(mesh, box.min.z, settings));
    check_loops_on_bed(first_loops, raft.footprint, settings, options, place.offset_x,
                       place.offset_y);
    // The raft's layers, whole before the sweep starts: the skirt and brim on them, their
    // material counted apart from the model's.
    for (LayerToolpaths& layer : raft.layers) {
        add_skirt_and_brim(layer, first_loops, settings);
        const std::vector<double> v = extrusion_volumes_mm3(layer, settings);
        for (size_t k = 0; k < v.size(); ++k) {
            const Feature f = layer.extrusions[k].feature;
            if (f == Feature::Skirt || f == Feature::Brim)
                result.feature_mm3[size_t(f)] += v[k];
            else
                result.raft_mm3 += v[k];
        }
        writer.add_layer(layer);
    }
    if (!settings.thumbnails.empty())
        writer.set_thumbnails(thumbnail_blocks(mesh.vertices, mesh.triangles, settings.thumbnails));
    if (!options.svg_dir.empty()) {
        svg_dir = std::make_unique<AtomicDir>(options.svg_dir);
        svg = std::make_unique<SvgLayerWriter>(
            options.svg_every > 0
                ? SvgLayerWriter::every(svg_dir->folder(), options.svg_every)
                : SvgLayerWriter(svg_dir->folder(), SvgLayerWriter::spread(layer_count, 8)));
    }
    if (!options.report_path.empty()) {
        html = std::make_unique<HtmlReportWriter>(options.report_path, settings);
        html->commit_with(group);
    }
    if (html) html->set_model_name(options.model_path);
    if (!options.raster_dir.empty()) {
        raster_dir = std::make_unique<AtomicDir>(options.raster_dir);
        const BBox2 footprint{to_units(box.min.x), to_units(box.min.y), to_units(box.max.x),
                              to_units(box.max.y), false};
        raster =
            std::make_unique<RasterWriter>(raster_dir->folder(), settings, footprint,
                                           options.raster_pixel_mm, options.raster_min_wall_mm);
    }
}

void RunOutputs::finish(RunResult& result, const Settings& settings, const RunOptions& options) {
    if (raster) raster->finish();
    result.peak_memory_mb = peak_memory_mb();
    if (html) html->finish(result, stats_json(result, settings));
    if (!options.stats_path.empty())
        write_file_atomically(options.stats_path, stats_json(result, settings).dump(2) + "\n",
                              &group);
    if (svg_dir) group.hold(std::move(svg_dir));
    if (raster_dir) group.hold(std::move(raster_dir));
    // The candidates of --orient auto keep nothing: the group removes its temporaries.
    if (options.outputs_to)
        group.hand_over(*options.outputs_to);
    else if (!options.discard_outputs)
        group.commit_all();
}

}  // namespace carve

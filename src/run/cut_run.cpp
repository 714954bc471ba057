// run_cut (run/pipeline.hpp, issue #48): the model cut across z (mesh/cut.hpp), each piece laid
// on the bed (the bottom one as the model stood, the others on their lower cut face, or with
// --orient auto each in its own lightest orientation; turned a quarter about z when that is what
// fits), the pieces packed in shelves onto as few plates as hold them, each plate sliced as one
// run whose objects are its pieces, and a picture of the plates written beside the G-code.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>

#include "base/error.hpp"
#include "base/numbers.hpp"
#include "base/output_paths.hpp"
#include "base/stage_timer.hpp"
#include "mesh/cut.hpp"
#include "report/stats.hpp"
#include "run/cut_picture.hpp"
#include "run/orient.hpp"
#include "run/pipeline.hpp"
#include "run/run_setup.hpp"

namespace carve {

namespace {

// "out.gcode" -> "out-plate2.gcode", in the same folder.
std::string plate_path(const std::string& path, size_t plate) {
    if (path.empty()) return path;
    const std::filesystem::path p(path);
    std::string name = p.stem().string() + fmt::format("-plate{}", plate) + p.extension().string();
    return (p.parent_path() / name).string();
}

struct Laid {
    Mesh mesh;  // on the bed (lowest z = 0), its box's corner at x = y = 0
    double w = 0, d = 0, h = 0;
    size_t plate = 0;
    double x = 0, y = 0;  // where its corner goes on its plate
    BedFrame frame;       // the piece's model frame to its plate's (for the picture)
};

// A quarter turn about z, exactly: the one lay() makes.
Rotation quarter_turn() {
    Rotation r;
    r.m = {{{0, -1, 0}, {1, 0, 0}, {0, 0, 1}}};
    return r;
}

// `turned` is the piece's mesh after `turn_so_far` (from the model's frame).
Laid lay(const Mesh& turned, const Rotation& turn_so_far, bool turn) {
    Laid l;
    l.mesh = turned;
    if (turn)
        for (Vec3& v : l.mesh.vertices) v = {-v.y, v.x, v.z};
    const BBox3 b = bounding_box(l.mesh);
    for (Vec3& v : l.mesh.vertices) v = {v.x - b.min.x, v.y - b.min.y, v.z - b.min.z};
    l.w = b.max.x - b.min.x;
    l.d = b.max.y - b.min.y;
    l.h = b.max.z - b.min.z;
    l.frame.turn = turn ? compose(quarter_turn(), turn_so_far) : turn_so_far;
    l.frame.shift = {-b.min.x, -b.min.y, -b.min.z};
    return l;
}

// What a plate keeps clear around its pieces: the skirt, brim and raft reach beyond them.
double plate_margin(const Settings& s) {
    double m =
        std::max(s.brim_width, s.skirts > 0 ? s.skirt_distance + s.skirts * s.width_mm() : 0);
    if (s.raft_layers > 0) m += s.raft_expansion + s.raft_first_layer_expansion;
    return m + 1;
}

// Shelves, tallest pieces first: each piece onto the first plate with room for it.
size_t arrange(std::vector<Laid>& laid, double bed_w, double bed_d, double gap) {
    struct Shelf {
        double y, depth, used;
    };
    std::vector<std::vector<Shelf>> plates;
    std::vector<size_t> order(laid.size());
    for (size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return laid[a].d > laid[b].d; });
    for (size_t k : order) {
        Laid& l = laid[k];
        bool placed = false;
        for (size_t p = 0; p < plates.size() && !placed; ++p) {
            for (Shelf& s : plates[p])
                if (l.d <= s.depth && s.used + gap + l.w <= bed_w) {
                    l.plate = p;
                    l.x = s.used + gap;
                    l.y = s.y;
                    s.used += gap + l.w;
                    placed = true;
                    break;
                }
            if (placed) break;
            const double top = plates[p].back().y + plates[p].back().depth + gap;
            if (top + l.d <= bed_d) {
                plates[p].push_back({top, l.d, l.w});
                l.plate = p;
                l.x = 0;
                l.y = top;
                placed = true;
            }
        }
        if (!placed) {
            plates.push_back({{0, l.d, l.w}});
            l.plate = plates.size() - 1;
            l.x = l.y = 0;
        }
    }
    return plates.size();
}

ConnectorSpec connector_spec(const Settings& s) {
    ConnectorSpec spec;
    spec.kind = s.cut_connectors == CutConnectors::None  ? ConnectorKind::None
                : s.cut_connectors == CutConnectors::Pin ? ConnectorKind::Pin
                                                         : ConnectorKind::Dowel;
    spec.diameter_mm = s.dowel_diameter;
    spec.depth_mm = s.dowel_depth;
    spec.clearance_mm = s.connector_clearance;
    return spec;
}

CutLimits cut_limits(const Settings& settings) {
    const ConnectorSpec spec = connector_spec(settings);
    CutLimits limits;
    const double margin = 2 * plate_margin(settings);
    limits.max_x = settings.bed_x - margin;
    limits.max_y = settings.bed_y - margin;
    limits.max_height = settings.max_print_height - settings.model_base_mm() - settings.z_offset -
                        (spec.kind == ConnectorKind::Pin ? spec.depth_mm : 0);
    limits.min_height = spec.kind == ConnectorKind::None ? 2 : 2 * spec.depth_mm + 2;
    // Planes on layer boundaries of the piece below.
    limits.step = settings.layer_height * std::max(1.0, std::round(1.0 / settings.layer_height));
    return limits;
}

std::vector<double> cut_heights(const Settings& settings, const RunOptions& options,
                                const BBox3& box) {
    const double height = box.max.z - box.min.z;
    std::vector<double> zs;
    for (double z : settings.cut_at) {
        if (!(z > 0 && z < height))
            throw InputError(
                fmt::format("{}: --cut {} mm is not inside the model (0 to {:.2f} mm "
                            "above its bottom)",
                            options.model_path, z, height));
        zs.push_back(box.min.z + z);
    }
    // settings.cut_at is sorted (the field sorts its heights).
    for (size_t k = 1; k < settings.cut_at.size(); ++k)
        if (settings.cut_at[k] - settings.cut_at[k - 1] < 1.0)
            throw InputError(fmt::format("{}: --cut {} and {} mm are closer than 1 mm",
                                         options.model_path, settings.cut_at[k - 1],
                                         settings.cut_at[k]));
    return zs;
}

// Where the model is cut: heights across z (each piece laid as before), or planes in any
// direction (each piece on its largest cut face).
struct CutPlan {
    std::vector<double> zs;
    std::vector<CutPlane> planes;
};

CutPlan plan_cut(const Settings& settings, const RunOptions& options, const Mesh& mesh,
                 const BBox3& box) {
    CutPlan plan;
    if (!settings.cut_planes.empty()) {
        if (settings.cut_auto)
            throw InputError(
                fmt::format("{}: --cut auto chooses its planes; --cut-plane is "
                            "not taken with it",
                            options.model_path));
        bool across_z = true;
        for (size_t k = 0; k < settings.cut_planes.size(); k += 6) {
            const double* v = &settings.cut_planes[k];
            const double n = std::hypot(v[3], v[4], v[5]);
            CutPlane p{{box.min.x + v[0], box.min.y + v[1], box.min.z + v[2]},
                       {v[3] / n, v[4] / n, v[5] / n}};
            across_z = across_z && std::abs(p.normal.z) > 1 - 1e-12;
            plan.planes.push_back(p);
        }
        for (double z : settings.cut_at) plan.planes.push_back({{0, 0, box.min.z + z}, {0, 0, 1}});
        if (across_z) {
            // Planes across z are heights: the pieces lie as --cut lays them.
            Settings heights = settings;
            for (const CutPlane& p : plan.planes) heights.cut_at.push_back(p.point.z - box.min.z);
            std::sort(heights.cut_at.begin(), heights.cut_at.end());
            heights.cut_at.erase(std::unique(heights.cut_at.begin(), heights.cut_at.end()),
                                 heights.cut_at.end());
            plan.planes.clear();
            plan.zs = cut_heights(heights, options, box);
        }
        return plan;
    }
    if (!settings.cut_auto) {
        plan.zs = cut_heights(settings, options, box);
        return plan;
    }
    // Across z alone when that fits in as few pieces as any, with as little cut face; planes
    // across x and y (with z) otherwise, and for a footprint no cut across z can fit.
    const CutLimits limits = cut_limits(settings);
    size_t pieces = std::numeric_limits<size_t>::max();
    double area = std::numeric_limits<double>::infinity();
    std::string refused;
    try {
        plan.zs = plan_cuts(mesh, limits, options.model_path);
        pieces = plan.zs.size() + 1;
        area = 0;
        for (double z : plan.zs) area += std::abs(section_area_mm2(mesh, z));
    } catch (const InputError& e) {
        refused = e.what();
    }
    double planar_area = 0;
    plan.planes = plan_planar_cuts(mesh, limits, pieces, area, planar_area);
    if (!plan.planes.empty())
        plan.zs.clear();
    else if (!refused.empty())
        throw InputError(refused + "; nor do planes across x and y (up to 3 each, with z)");
    return plan;
}

nlohmann::json piece_json(const MeshPiece& p, const Laid& l, size_t k, double bottom,
                          const std::string& name) {
    nlohmann::json connectors = nlohmann::json::array();
    for (const Connector& c : p.connectors)
        connectors.push_back({{"kind", c.pin ? "pin" : "hole"},
                              {"x_mm", c.x},
                              {"y_mm", c.y},
                              {"face_z_mm", c.face_z - bottom},
                              {"diameter_mm", c.diameter_mm},
                              {"depth_mm", c.depth_mm},
                              {"normal", {c.normal.x, c.normal.y, c.normal.z}}});
    const BBox3 b = bounding_box(p.mesh);
    return {{"piece", k + 1},
            {"name", name},
            {"plate", l.plate + 1},
            {"z_from_mm", p.z_from - bottom},
            {"z_to_mm", p.z_to - bottom},
            {"volume_mm3", signed_volume(p.mesh)},
            {"bbox",
             {{"min", {b.min.x, b.min.y, b.min.z - bottom}},
              {"max", {b.max.x, b.max.y, b.max.z - bottom}}}},
            {"size_mm", {l.w, l.d, l.h}},
            {"connectors", connectors}};
}

// The whole run's figures: the plates' sums, each plate's own stats, the pieces.
nlohmann::json cut_stats(const RunResult& loaded, const std::vector<RunResult>& plates,
                         const std::vector<std::string>& paths, const Settings& settings,
                         nlohmann::json pieces, const std::vector<double>& heights,
                         nlohmann::json planes, double wall_s) {
    nlohmann::json j;
    j["model_volume_mm3"] = loaded.mesh.volume_mm3;
    j["triangles"] = loaded.mesh.triangles;
    nlohmann::json list = nlohmann::json::array();
    double extruded = 0, length = 0, weight = 0, time = 0, memory = 0;
    int layers = 0, cavities = 0, bridges = 0;
    for (size_t p = 0; p < plates.size(); ++p) {
        nlohmann::json s = stats_json(plates[p], settings);
        s["plate"] = p + 1;
        s["gcode"] = paths[p];
        extruded += plates[p].print.extruded_volume_mm3;
        length += plates[p].print.filament_length_mm;
        weight += plates[p].print.filament_weight_g;
        time += plates[p].print.estimated_print_time_s;
        memory = std::max(memory, plates[p].peak_memory_mb);
        layers = std::max(layers, plates[p].layers);
        cavities += plates[p].cavities;
        bridges += plates[p].bridges;
        list.push_back(std::move(s));
    }
    j["layers"] = layers;
    j["cavities"] = cavities;
    j["bridges"] = bridges;
    j["extruded_volume_mm3"] = extruded;
    j["filament_length_mm"] = length;
    j["filament_weight_g"] = weight;
    j["material_percent"] =
        loaded.mesh.volume_mm3 > 0 ? extruded / loaded.mesh.volume_mm3 * 100 : 0;
    j["estimated_print_time_s"] = time;
    j["processing_time_s"] = wall_s;
    j["peak_memory_mb"] = memory;
    j["cut"] = {{"auto", settings.cut_auto}, {"planes_mm", heights}, {"planes", planes}};
    j["plates"] = std::move(list);
    j["pieces"] = std::move(pieces);
    return j;
}

// "out.gcode" -> "out-pieces.svg": the picture of the plates, beside the G-code.
std::string picture_path(const std::string& gcode_path) {
    const std::filesystem::path p(gcode_path);
    return (p.parent_path() / (p.stem().string() + "-pieces.svg")).string();
}

// "out.gcode" -> "out-plate2.stl": plate 2's pieces as a mesh, beside its G-code.
std::string plate_mesh_path(const std::string& gcode_path, size_t plate) {
    const std::filesystem::path p(plate_path(gcode_path, plate));
    return (p.parent_path() / (p.stem().string() + ".stl")).string();
}

// The files a cut writes in place of the run's own (-plateN beside each, the picture, the
// plates' meshes) are checked as the CLI checks the run's: none may be the model or another of
// them, nor a device, and this before anything is sliced.
void check_cut_outputs(const RunOptions& options, size_t plates) {
    std::vector<NamedPath> outputs;
    for (size_t p = 1; p <= plates; ++p) {
        const std::string plate = fmt::format("plate {}'s", p);
        outputs.push_back({plate_path(options.gcode_path, p), plate + " G-code"});
        outputs.push_back({plate_path(options.report_path, p), plate + " --report"});
        outputs.push_back({plate_path(options.svg_dir, p), plate + " --svg-layers", true});
        outputs.push_back({plate_path(options.raster_dir, p), plate + " --raster", true});
        if (options.plate_meshes)
            outputs.push_back({plate_mesh_path(options.gcode_path, p), plate + " mesh"});
    }
    outputs.push_back({picture_path(options.gcode_path), "the pieces' picture"});
    outputs.push_back({options.stats_path, "--stats"});
    check_output_paths({{options.model_path, "the model"}}, outputs);
}

// --pause-at with --cut: heights on each plate (a piece lies on its cut face, so the model's
// heights are not the plate's). A plate lower than a height prints without that pause, which
// is said; a height no plate reaches is refused, as a pause above the model's top is.
std::vector<double> plate_pauses(const Settings& settings, const RunOptions& options, size_t plate,
                                 double height,
                                 const std::function<void(const std::string&)>& note) {
    std::vector<double> kept;
    for (double z : settings.pause_at)
        if (z <= height + 1e-6)
            kept.push_back(z);
        else
            note(
                fmt::format("{}: plate {} is {:.2f} mm tall and prints without the pause at "
                            "{} mm",
                            options.model_path, plate, height, plain_number(z)));
    return kept;
}

// Each piece on the bed, on its cut face (or, with --orient auto, in the orientation that prints
// it lightest), turned a quarter when only that fits; one that fits neither way (or is too tall)
// is refused by its number before anything is sliced.
std::vector<Laid> lay_pieces(const std::vector<MeshPiece>& pieces, bool any_plane,
                             const Settings& settings, const RunOptions& options,
                             const RunResult& loaded, const BBox3& box,
                             std::vector<std::optional<OrientationChoice>>& orientations) {
    const double margin = 2 * plate_margin(settings);
    const double bed_w = settings.bed_x - margin, bed_d = settings.bed_y - margin;
    const double max_h = settings.max_print_height - settings.model_base_mm() - settings.z_offset;
    // The orientations are tried on the bed a plate leaves a piece, not the whole bed.
    Settings choosing = settings;
    choosing.bed_x = bed_w;
    choosing.bed_y = bed_d;
    std::vector<Laid> laid;
    for (size_t k = 0; k < pieces.size(); ++k) {
        // A piece of planes in any direction lies on its largest cut face.
        Mesh down = pieces[k].mesh;
        Rotation turn;
        if (any_plane) {
            turn = lay_on_cut_face(pieces[k]);
            rotate_mesh(down, turn);
        }
        std::optional<OrientationChoice> choice;
        if (settings.orient == OrientMode::Auto) {
            // The candidates start from the piece as it would lie: "as given" is its cut face.
            RunResult r;
            r.mesh = loaded.mesh;
            r.mesh.items.clear();
            r.mesh.bbox = bounding_box(down);
            RunOptions o = options;
            o.model_path =
                fmt::format("{} (piece {} of {})", options.model_path, k + 1, pieces.size());
            choose_orientation(choosing, o, down, r);
            choice = std::move(r.orientation);
            turn = compose(choice->trials[choice->chosen].candidate.rotation, turn);
        }
        orientations.push_back(std::move(choice));
        Laid l = lay(down, turn, false);
        if ((l.w > bed_w || l.d > bed_d) && l.d <= bed_w && l.w <= bed_d) l = lay(down, turn, true);
        if (settings.bed_check && (l.w > bed_w || l.d > bed_d || l.h > max_h + 1e-6))
            throw InputError(fmt::format(
                "{}: piece {} of {} ({:.1f} to {:.1f} mm of the model's height) is {:.1f} x {:.1f} "
                "x {:.1f} mm, larger than the {:.0f} x {:.0f} mm the bed holds with its skirt "
                "or {:.0f} mm tall; cut elsewhere, try --cut auto, or scale the model down",
                options.model_path, k + 1, pieces.size(), pieces[k].z_from - box.min.z,
                pieces[k].z_to - box.min.z, l.w, l.d, l.h, bed_w, bed_d, max_h));
        laid.push_back(std::move(l));
    }
    return laid;
}

// --pause-at with --cut: a height no plate reaches is refused before anything is sliced.
void check_pauses(const Settings& settings, const RunOptions& options,
                  const std::vector<Laid>& laid) {
    double tallest = 0;
    for (const Laid& l : laid) tallest = std::max(tallest, l.h);
    for (double z : settings.pause_at)
        if (z > tallest + 1e-6)
            throw InputError(
                fmt::format("{}: --pause-at {} mm is above every plate's top (the tallest piece is "
                            "{:.2f} mm): with --cut, pauses are heights on the plates",
                            options.model_path, plain_number(z), tallest));
}

// Plate p's pieces as one mesh where the arrangement put them, each a labelled object;
// `on_plate` gets their numbers.
RunMesh gather_plate(const std::vector<Laid>& laid, size_t p, const std::string& stem,
                     std::vector<size_t>& on_plate) {
    RunMesh plate;
    for (size_t k = 0; k < laid.size(); ++k) {
        if (laid[k].plate != p) continue;
        const Laid& l = laid[k];
        const uint32_t base = uint32_t(plate.mesh.vertices.size());
        for (const Vec3& v : l.mesh.vertices)
            plate.mesh.vertices.push_back({v.x + l.x, v.y + l.y, v.z});
        for (const auto& t : l.mesh.triangles)
            plate.mesh.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
        plate.copy_boxes.push_back({l.x, l.y, l.x + l.w, l.y + l.d});
        plate.object_names.push_back(fmt::format("{}_piece{}", stem, k + 1));
        on_plate.push_back(k);
    }
    plate.loaded_box = bounding_box(plate.mesh);
    return plate;
}

// The run's options for plate p: its outputs -plateN beside the run's, handed to the group so
// that none is renamed into place before the last plate is done.
RunOptions plate_run_options(const RunOptions& options, size_t p,
                             const std::vector<size_t>& on_plate,
                             const std::function<void(const std::string&)>& note,
                             OutputGroup& group) {
    RunOptions plate_options = options;
    plate_options.gcode_path = plate_path(options.gcode_path, p + 1);
    plate_options.report_path = plate_path(options.report_path, p + 1);
    plate_options.svg_dir = plate_path(options.svg_dir, p + 1);
    plate_options.raster_dir = plate_path(options.raster_dir, p + 1);
    plate_options.stats_path.clear();
    plate_options.outputs_to = &group;
    // A plate's warnings say which plate and pieces they are about.
    std::string names;
    for (size_t k : on_plate) names += fmt::format("{}{}", names.empty() ? "" : ", ", k + 1);
    plate_options.note = [note, p, names, many = on_plate.size() > 1](const std::string& s) {
        note(fmt::format("plate {} (piece{} {}): {}", p + 1, many ? "s" : "", names, s));
    };
    // Issue #48: every plate must pass the rules of carve check --strict, or none is written.
    plate_options.strict = options.strict;
    return plate_options;
}

}  // namespace

CutRunResult run_cut(const Settings& settings, const RunOptions& options) {
    const auto started = std::chrono::steady_clock::now();
    const std::function<void(const std::string&)> note = [&](const std::string& s) {
        if (options.note) options.note(s);
    };
    if (settings.copies > 1)
        throw InputError(
            fmt::format("{}: --cut prints the pieces of one model; --copies is not "
                        "taken with it",
                        options.model_path));
    RunResult loaded;
    // With --orient auto each piece is oriented once cut, the model is cut as given.
    Settings as_given = settings;
    as_given.orient = OrientMode::Given;
    RunMesh run_mesh = load_run_mesh(as_given, options, loaded, note);
    if (!loaded.mesh.closed())
        throw InputError(
            fmt::format("{}: --cut needs a closed surface; the mesh has {} open and "
                        "{} non-manifold edges",
                        options.model_path, loaded.mesh.open_edges, loaded.mesh.nonmanifold_edges));
    const BBox3 box = loaded.mesh.bbox;
    const CutPlan plan = plan_cut(settings, options, run_mesh.mesh, box);
    const std::vector<double>& zs = plan.zs;
    std::vector<MeshPiece> pieces;
    try {
        pieces = plan.planes.empty()
                     ? cut_across_z(run_mesh.mesh, zs, connector_spec(settings))
                     : cut_by_planes(run_mesh.mesh, plan.planes, connector_spec(settings));
    } catch (const InputError& e) {
        throw InputError(fmt::format("{}: {}", options.model_path, e.what()));
    }
    std::vector<std::optional<OrientationChoice>> orientations;
    std::vector<Laid> laid =
        lay_pieces(pieces, !plan.planes.empty(), settings, options, loaded, box, orientations);
    const double margin = 2 * plate_margin(settings);
    const size_t plate_count =
        arrange(laid, settings.bed_x - margin, settings.bed_y - margin, settings.copy_gap);
    check_cut_outputs(options, plate_count);
    check_pauses(settings, options, laid);
    const std::string stem = std::filesystem::path(options.model_path).stem().string();
    OutputGroup group;
    CutRunResult out;
    out.pieces = pieces.size();
    std::vector<PlateDrawing> drawings;
    for (size_t p = 0; p < plate_count; ++p) {
        std::vector<size_t> on_plate;
        RunMesh plate = gather_plate(laid, p, stem, on_plate);
        // The picture draws the pieces where the G-code prints them: the plate centred on the bed.
        const Placement place = centre_on_bed(settings, plate.loaded_box);
        PlateDrawing drawing;
        drawing.bed_x = settings.bed_x;
        drawing.bed_y = settings.bed_y;
        for (size_t k : on_plate) {
            BedFrame frame = laid[k].frame;
            frame.shift = {frame.shift.x + laid[k].x + place.offset_x,
                           frame.shift.y + laid[k].y + place.offset_y, frame.shift.z};
            drawing.pieces.push_back(draw_piece(
                pieces[k],
                plan.planes.empty() ? faces_across_z(pieces[k], k == 0, k + 1 == pieces.size())
                                    : pieces[k].faces,
                frame, plate.object_names[drawing.pieces.size()]));
        }
        RunResult result;
        result.mesh = loaded.mesh;
        result.mesh.warnings.clear();
        result.mesh.items.clear();
        result.mesh.bbox = plate.loaded_box;
        result.mesh.volume_mm3 = signed_volume(plate.mesh);
        result.mesh.triangles = plate.mesh.triangles.size();
        result.mesh.vertices = plate.mesh.vertices.size();
        const RunOptions plate_options = plate_run_options(options, p, on_plate, note, group);
        if (options.plate_meshes) {
            Mesh placed = plate.mesh;
            for (Vec3& v : placed.vertices) v = {v.x + place.offset_x, v.y + place.offset_y, v.z};
            out.mesh_paths.push_back(plate_mesh_path(options.gcode_path, p + 1));
            write_file_atomically(out.mesh_paths.back(),
                                  binary_stl(placed, fmt::format("{} plate {}", stem, p + 1)),
                                  &group);
        }
        Settings plate_settings = settings;
        plate_settings.pause_at = plate_pauses(
            settings, options, p + 1, plate.loaded_box.max.z - plate.loaded_box.min.z, note);
        out.plates.push_back(slice_run_mesh(plate_settings, plate_options, std::move(plate),
                                            std::move(result), std::chrono::steady_clock::now(),
                                            thread_cpu_ns()));
        out.gcode_paths.push_back(plate_options.gcode_path);
        drawing.gcode = std::filesystem::path(plate_options.gcode_path).filename().string();
        drawings.push_back(std::move(drawing));
    }
    out.picture_path = picture_path(options.gcode_path);
    write_file_atomically(
        out.picture_path,
        cut_plates_svg(drawings, fmt::format("{}: {} pieces on {} plates, seen from above", stem,
                                             pieces.size(), plate_count)),
        &group);
    if (!options.stats_path.empty()) {
        nlohmann::json list = nlohmann::json::array();
        for (size_t k = 0; k < pieces.size(); ++k) {
            list.push_back(piece_json(pieces[k], laid[k], k, box.min.z,
                                      fmt::format("{}_piece{}", stem, k + 1)));
            if (orientations[k]) list.back()["orientation"] = orientation_json(*orientations[k]);
        }
        std::vector<double> heights;
        for (double z : zs) heights.push_back(z - box.min.z);
        nlohmann::json planes = nlohmann::json::array();
        for (const CutPlane& c : plan.planes)
            planes.push_back(
                {{"point_mm",
                  {c.point.x - box.min.x, c.point.y - box.min.y, c.point.z - box.min.z}},
                 {"normal", {c.normal.x, c.normal.y, c.normal.z}}});
        const double wall_s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
        nlohmann::json stats = cut_stats(loaded, out.plates, out.gcode_paths, settings,
                                         std::move(list), heights, std::move(planes), wall_s);
        stats["cut"]["picture"] = out.picture_path;
        write_file_atomically(options.stats_path, stats.dump(2) + "\n", &group);
    }
    group.commit_all();
    return out;
}

}  // namespace carve

// Figures of a run for machines (JSON) and for people (a few lines of text).
#include "report/stats.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <string_view>
#include <variant>

#include "config/setting_table.hpp"
#include "gcode/gcode.hpp"
#include "slice/slicer.hpp"

namespace carve {

std::string stats_key(const SettingSpec& spec) {
    // The keys written before the table was used were spelt this way and other tools read
    // them: a count names what it counts already ("covers", "support_interface_layers") and a
    // flag is a JSON bool, so neither takes a suffix; nor does a word ("walls": "single").
    static const std::map<std::string_view, std::string_view> suffixes = {
        {"mm", "_mm"},    {"degrees", "_deg"},  {"mm/s", "_mm_s"}, {"mm/s^2", "_mm_s2"},
        {"C", "_c"},      {"g/cm^3", "_g_cm3"}, {"seconds", "_s"}, {"%", "_percent"},
        {"layers", ""},   {"lines", ""},        {"copies", ""},    {"threads", ""},
        {"vertices", ""}, {"ratio", ""},        {"0/1", ""},       {"", ""},
    };
    std::string key = spec.name();
    if (const auto it = suffixes.find(spec.unit); it != suffixes.end())
        return key + std::string(it->second);
    // A new unit still gives a key, so that a new setting cannot go missing from the JSON.
    key += '_';
    for (char c : std::string_view(spec.unit)) {
        if (std::isalnum(static_cast<unsigned char>(c)))
            key += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        else if (c == '/')
            key += '_';
    }
    return key;
}

// What the supports under the model's own overhangs extruded, interface included (not the ribs
// inside the model).
static double support_mm3(const RunResult& run) {
    return run.feature_mm3[size_t(Feature::Support)] +
           run.feature_mm3[size_t(Feature::SupportInterface)];
}

// The rotation of one candidate: its name, axis and angle, the matrix (v' = m v about the
// origin) and which direction of the model as loaded faces the bed.
static nlohmann::json rotation_json(const OrientationCandidate& c) {
    nlohmann::json j;
    j["name"] = c.name;
    j["description"] = describe(c);
    const Vec3 a = c.rotation.axis();
    j["axis"] = {a.x, a.y, a.z};
    j["angle_deg"] = c.rotation.angle_deg();
    j["matrix"] = c.rotation.m;
    j["down"] = {c.down.x, c.down.y, c.down.z};
    return j;
}

nlohmann::json orientation_json(const OrientationChoice& o) {
    nlohmann::json j;
    j["chosen"] = rotation_json(o.trials[o.chosen].candidate);
    j["choice_time_s"] = o.choice_time_s;
    j["choice_cpu_s"] = o.choice_cpu_s;
    nlohmann::json list = nlohmann::json::array();
    for (size_t k = 0; k < o.trials.size(); ++k) {
        const OrientationTrial& t = o.trials[k];
        nlohmann::json c = rotation_json(t.candidate);
        c["fits"] = t.fits;
        c["chosen"] = k == o.chosen;
        if (t.fits) {
            // At the coarse layers the choice carves at, with supports: figures to compare
            // with one another, not with the run's own.
            c["layer_height_mm"] = t.layer_height_mm;
            // Given up: heavier than one carved before it, its layers stopped part way.
            c["given_up"] = t.given_up;
            if (t.given_up) {
                c["extruded_at_least_mm3"] = t.material_mm3;
                // How early: the layers (of its coarse ones, bottom up) it never carved.
                c["layers_not_carved"] = t.layers_left;
                c["layers"] = t.layers;
            } else {
                c["extruded_volume_mm3"] = t.material_mm3;
                c["support_volume_mm3"] = t.support_mm3;
                c["estimated_print_time_s"] = t.print_time_s;
                c["external_overhang_mm2"] = t.overhang_mm2;
            }
        } else {
            c["refused"] = t.refused;
        }
        list.push_back(std::move(c));
    }
    j["candidates"] = std::move(list);
    return j;
}

nlohmann::json stats_json(const RunResult& run, const Settings& settings) {
    nlohmann::json j;
    j["model_volume_mm3"] = run.mesh.volume_mm3;
    j["triangles"] = run.mesh.triangles;
    j["layers"] = run.layers;
    j["cavities"] = run.cavities;
    j["bridges"] = run.bridges;
    j["bridge_length_mm"] = run.bridge_length_mm;
    j["extruded_volume_mm3"] = run.print.extruded_volume_mm3;
    j["filament_length_mm"] = run.print.filament_length_mm;
    j["filament_weight_g"] = run.print.filament_weight_g;
    j["material_percent"] = run.material_percent();
    j["estimated_print_time_s"] = run.print.estimated_print_time_s;
    j["processing_time_s"] = run.processing_time_s;
    j["peak_memory_mb"] = run.peak_memory_mb;
    j["travel_length_mm"] = run.print.travel_length_mm;
    j["retractions"] = run.print.retractions;
    j["arcs"] = run.print.arcs;
    j["lines_saved_by_arcs"] = run.print.lines_saved_by_arcs;
    // Which of the two carvings made the interior (--carving): the figures mean little without.
    j["carving_scheme"] = scheme_name(settings.carving);
    j["carvable_volume_mm3"] = run.carvable_volume_mm3;
    j["cavity_volume_mm3"] = run.cavity_volume_mm3;
    j["remainder_volume_mm3"] = run.remainder_volume_mm3;
    j["cover_volume_mm3"] = run.cover_volume_mm3;
    j["cover_bridges"] = run.cover_bridges;
    j["island_bridges"] = run.island_bridges;
    j["island_bridge_length_mm"] = run.island_bridge_length_mm;
    j["minima_found"] = run.minima_found;
    j["minima_bridged"] = run.minima_found - run.minima_unsupported - run.minima_held_by_wall -
                          run.minima_held_by_ribs;  // wholly, by bridges
    // Held by the wall below: no deeper than a line width inside the cavity below.
    j["minima_supported_otherwise"] = run.minima_held_by_wall;
    // No printable bridge, but ribs under what of them lies deeper than --rib-reach.
    j["minima_held_by_ribs"] = run.minima_held_by_ribs;
    j["minima_unsupported"] = run.minima_unsupported;
    j["ceilings_found"] = run.ceilings_found;
    j["ceilings_held_by_ribs"] = run.ceilings_held_by_ribs;
    j["ceilings_unsupported"] = run.ceilings_unsupported;
    // The model's own overhang (no supports are printed): what only supports would hold.
    j["external_overhang_mm2"] = run.external_overhang_mm2;
    j["far_external_overhang_mm2"] = run.far_external_overhang_mm2;
    j["unprinted_mm2"] = run.unprinted_mm2;
    j["unprinted_layers"] = run.unprinted_layers;
    // Supports: what they print (body and interface), the overhang they start under, and the
    // volume their regions span.
    j["support_volume_mm3"] = support_mm3(run);
    j["supported_area_mm2"] = run.supported_area_mm2;
    j["support_region_volume_mm3"] = run.support_region_volume_mm3;
    nlohmann::json m;
    m["outer_wall_mm3"] = run.feature_mm3[size_t(Feature::OuterWall)];
    m["shells_mm3"] = run.feature_mm3[size_t(Feature::Shell)];
    m["covers_mm3"] = run.feature_mm3[size_t(Feature::Cover)];
    m["cavity_walls_mm3"] = run.feature_mm3[size_t(Feature::CavityWall)];
    m["bridges_mm3"] = run.feature_mm3[size_t(Feature::Bridge)];
    m["ribs_mm3"] = run.feature_mm3[size_t(Feature::Rib)];
    m["ties_mm3"] = run.feature_mm3[size_t(Feature::Tie)];  // --ties: not cavity walls
    m["support_mm3"] = run.feature_mm3[size_t(Feature::Support)];
    m["support_interface_mm3"] = run.feature_mm3[size_t(Feature::SupportInterface)];
    m["remainder_mm3"] = run.remainder_fill_mm3;
    m["raft_mm3"] = run.raft_mm3;
    std::vector<double> walls(run.cavity_wall_mm3.begin() + (run.cavity_wall_mm3.empty() ? 0 : 1),
                              run.cavity_wall_mm3.end());
    m["walls_of_cavity_mm3"] = walls;
    j["material_by_feature"] = m;
    j["mesh_closed"] = run.mesh.closed();
    j["mesh_warnings"] = run.mesh.warnings;
    if (run.orientation) j["orientation"] = orientation_json(*run.orientation);
    if (run.check) {
        // What `carve check --mesh --json` says of the written G-code (--stats-check).
        j["check"] = to_json(*run.check);
        j["check"]["time_s"] = run.check_time_s;
    }
    if (run.strength) {
        // What `carve check --strength --json` says of it (--stats-strength), but the table of
        // every layer, which is carve check --layers' to give.
        j["strength"] = to_json(*run.strength);
        j["strength"].erase("layers");
        j["strength"]["time_s"] = run.strength_time_s;
    }
    nlohmann::json s;
    for (const SettingSpec& spec : setting_table())
        std::visit([&](auto v) { s[stats_key(spec)] = v; }, spec.value(settings));
    // Values as the run used them rather than as given, under the table's keys: the contract
    // has always given them so (DESIGN.md, "stats JSON").
    // 0 means "the same as --max-overhang".
    s["support_angle_deg"] =
        settings.support_angle > 0 ? settings.support_angle : settings.max_overhang;
    // The gap is printed in whole layers.
    s["support_z_gap_mm"] = settings.support_gap_layers() * settings.layer_height;
    // 0 means "the layer height" and "the line width".
    s["first_layer_height_mm"] = settings.first_layer_mm();
    s["first_layer_extrusion_width_mm"] = settings.layer_width_mm(settings.first_print_layer());
    // Without pruning no bridge is cut to a length.
    s["max_bridge_length_mm"] = settings.prune_bridges ? settings.max_bridge_length : 0.0;
    // Not a setting but where they came from (--printer's preset).
    s["printer"] = settings.printer_name;
    j["settings"] = s;
    return j;
}

// --orient auto's candidates, one line each, the chosen one marked.
static std::string orientation_text(const OrientationChoice& o) {
    std::string out = fmt::format(
        "orient     {} of {} orientations, chosen in {:.2f} s (carved at {} mm layers with "
        "supports):\n",
        describe(o.trials[o.chosen].candidate), o.trials.size(), o.choice_time_s,
        o.trials[o.chosen].layer_height_mm);
    for (size_t k = 0; k < o.trials.size(); ++k) {
        const OrientationTrial& t = o.trials[k];
        const std::string name = describe(t.candidate);
        if (!t.fits) {
            out += fmt::format("  {} {:<44} does not fit the printer\n", k == o.chosen ? '*' : ' ',
                               name);
            continue;
        }
        if (t.given_up) {
            out += fmt::format("  {} {:<44} >{:7.2f} cm3: heavier than a lighter one, given up\n",
                               k == o.chosen ? '*' : ' ', name, t.material_mm3 / 1000);
            continue;
        }
        out +=
            fmt::format("  {} {:<44} {:8.2f} cm3 ({:.2f} supports) {:>12} {:8.0f} mm2 overhang\n",
                        k == o.chosen ? '*' : ' ', name, t.material_mm3 / 1000,
                        t.support_mm3 / 1000, format_duration(t.print_time_s), t.overhang_mm2);
    }
    return out;
}

std::string summary_text(const RunResult& run, const Settings& settings) {
    std::string out;
    if (run.orientation) out += orientation_text(*run.orientation);
    out += fmt::format("model      {:.1f} cm3, {} triangles, {} layers of {} mm\n",
                       run.mesh.volume_mm3 / 1000, run.mesh.triangles, run.layers,
                       settings.layer_height);
    double carved = 0;
    for (double v : run.cavity_volume_mm3) carved += v;
    out += fmt::format(
        "cavities   {} carved {:.1f} % of the volume, --carving {} ({} bridges, {:.0f} mm)\n",
        run.cavities, run.mesh.volume_mm3 > 0 ? 100 * carved / run.mesh.volume_mm3 : 0.0,
        scheme_name(settings.carving), run.bridges, run.bridge_length_mm);
    out += fmt::format(
        "material   {:.2f} cm3 = {:.1f} % of the model, {:.2f} m of filament, {:.1f} g\n",
        run.print.extruded_volume_mm3 / 1000, run.material_percent(),
        run.print.filament_length_mm / 1000, run.print.filament_weight_g);
    if (const double v = support_mm3(run); v > 0)
        out += fmt::format("supports   {:.2f} cm3 under {:.0f} mm2 of overhang\n", v / 1000,
                           run.supported_area_mm2);
    out += fmt::format("print time {} (estimate)\n",
                       format_duration(run.print.estimated_print_time_s));
    if (run.check)
        out += fmt::format(
            "hanging    {:.1f} mm2 inside the model, {:.1f} mm2 overhang (checked in {:.2f} s)\n",
            run.check->hanging_inside_mm2, run.check->hanging_overhang_mm2, run.check_time_s);
    if (run.check) out += describe_printability(*run.check);
    if (run.strength) {
        const StrengthFigures& f = *run.strength;
        out += fmt::format("strength   weakest section {:.1f} mm4 at z {:.2f} mm",
                           f.weakest_section_mm4, f.weakest_section_z_mm);
        if (f.has_weakest_bond)
            out += fmt::format(", weakest bond {:.1f} mm2 at z {:.2f} mm", f.weakest_bond_mm2,
                               f.weakest_bond_z_mm);
        out += fmt::format(
            "\n           compression {:.0f} N/mm, shear {:.0f} N/mm ({} law, {:g} mm voxels; "
            "measured in {:.2f} s)\n",
            f.stiffness.compression_n_per_mm, f.stiffness.shear_n_per_mm, f.law, f.voxel_mm,
            run.strength_time_s);
    }
    out += fmt::format("sliced in  {:.2f} s, peak memory {:.0f} MB\n", run.processing_time_s,
                       run.peak_memory_mb);
    return out;
}

std::string describe(const GcodeAnalysis& a) {
    std::string out;
    if (!a.generator.empty()) out += fmt::format("generator        {}\n", a.generator);
    out += fmt::format("layers           {} (z {:.2f} .. {:.2f} mm)\n", a.layers, a.first_z_mm,
                       a.last_z_mm);
    out += fmt::format("material         {:.1f} mm3, {:.2f} m of {} mm filament\n",
                       a.extruded_volume_mm3, a.filament_length_mm / 1000, a.filament_diameter_mm);
    out += fmt::format("footprint        {:.1f} mm2 over all layers\n", a.footprint_area_mm2);
    out += fmt::format("unsupported      {:.3f} % (nothing below within r)\n",
                       100 * a.unsupported_fraction);
    out += fmt::format("far-unsupported  {:.3f} % (nothing below within 2 mm)\n",
                       100 * a.far_unsupported_fraction);
    out += fmt::format("hanging          {:.1f} mm2 far-unsupported", a.far_unsupported_area_mm2);
    if (a.model_checked)
        out +=
            fmt::format(": {:.1f} mm2 inside (over the model's slice below), {:.1f} mm2 overhang",
                        a.hanging_inside_mm2, a.hanging_overhang_mm2);
    out += "\n";
    if (a.support_volume_mm3 > 0)
        out += fmt::format("support          {:.1f} mm3 extruded{}\n", a.support_volume_mm3,
                           a.hanging_support_mm2 > 0
                               ? fmt::format(", {:.1f} mm2 of it hanging", a.hanging_support_mm2)
                               : std::string());
    out += fmt::format("retractions      {}", a.retractions);
    if (a.firmware_retractions > 0) out += fmt::format(" ({} G10)", a.firmware_retractions);
    out += "\n";
    out += fmt::format("travel           {:.0f} mm", a.travel_length_mm);
    if (a.model_checked)
        out += fmt::format(" ({:.0f} mm outside the model, {} wall crossings)", a.travel_outside_mm,
                           a.wall_crossings);
    out += "\n";
    if (a.model_checked) {
        out += fmt::format("outside model    {:.1f} mm2 (farthest {:.2f} mm)", a.outside_area_mm2,
                           a.max_outside_model_mm);
        if (a.outside_support_mm2 > 0)
            out += fmt::format(": {:.1f} mm2 support, {:.1f} mm2 other", a.outside_support_mm2,
                               std::max(0.0, a.outside_area_mm2 - a.outside_support_mm2));
        out += "\n";
        if (!a.mesh_alignment.empty())
            out += fmt::format("mesh offset      {:.3f}, {:.3f}, {:.3f} mm ({})\n",
                               a.mesh_offset_mm[0], a.mesh_offset_mm[1], a.mesh_offset_mm[2],
                               a.mesh_alignment);
        if (a.mesh_extent_mismatch_mm >= 0)
            out += fmt::format("mesh fit         extents differ by {:.2f} mm\n",
                               a.mesh_extent_mismatch_mm);
    }
    double total = 0;
    for (const auto& [type, v] : a.volume_by_type_mm3) total += v;
    if (total > 0 && !(a.volume_by_type_mm3.size() == 1 && a.volume_by_type_mm3.count("none"))) {
        out += "material by type";
        const char* sep = " ";
        for (const auto& [type, v] : a.volume_by_type_mm3) {
            out += fmt::format("{}{} {:.1f} %", sep, type, 100 * v / total);
            sep = ", ";
        }
        out += "\n";
    }
    out += fmt::format("stick time       {} (no look-ahead, same stick for every slicer)\n",
                       format_duration(a.stick_time_s));
    if (a.estimated_time_from_header_s >= 0)
        out +=
            fmt::format("header time      {}\n", format_duration(a.estimated_time_from_header_s));
    out += describe_printability(a);
    return out;
}

std::string describe_layers(const GcodeAnalysis& a) {
    std::string out = "     z mm  footprint mm2  far mm2";
    if (a.model_checked) out += "  inside mm2  overhang mm2";
    out += "  retractions  travel mm";
    if (a.model_checked) out += "  outside mm  crossings";
    out += "  stick s\n";
    for (const LayerFigures& l : a.per_layer) {
        out += fmt::format("{:9.2f}  {:13.1f}  {:7.2f}", l.z_mm, l.footprint_area_mm2,
                           l.far_unsupported_area_mm2);
        if (a.model_checked)
            out +=
                fmt::format("  {:10.2f}  {:12.2f}", l.hanging_inside_mm2, l.hanging_overhang_mm2);
        out += fmt::format("  {:11}  {:9.1f}", l.retractions, l.travel_length_mm);
        if (a.model_checked)
            out += fmt::format("  {:10.1f}  {:9}", l.travel_outside_mm, l.wall_crossings);
        out += fmt::format("  {:7.1f}\n", l.stick_time_s);
    }
    return out;
}

GcodeAnalysis analyse_gcode_on_mesh(const std::string& gcode_path, const Mesh& mesh,
                                    GcodeAnalysisOptions options,
                                    const std::optional<Vec3>& offset) {
    const BBox3 box = bounding_box(mesh);
    Vec3 shift;
    std::string how = "given";
    double mismatch = -1;
    if (offset) {
        shift = *offset;
        if (std::isnan(shift.z)) shift.z = -box.min.z;  // X,Y given: z still on the bed
    } else {
        how = "automatic";
        const ExtrusionBounds b = extrusion_bounds(gcode_path, options);
        if (b.any) {
            shift.x = (b.min_x + b.max_x) / 2 - (box.min.x + box.max.x) / 2;
            shift.y = (b.min_y + b.max_y) / 2 - (box.min.y + box.max.y) / 2;
            mismatch = std::max(std::fabs((b.max_x - b.min_x) - (box.max.x - box.min.x)),
                                std::fabs((b.max_y - b.min_y) - (box.max.y - box.min.y)));
        }
        // On the bed, or on the raft the G-code prints under it.
        shift.z = (b.model_bottom_z > 0 ? b.model_bottom_z : 0.0) - box.min.z;
    }
    const Coord ux = to_units(shift.x), uy = to_units(shift.y);
    options.model_top_mm = box.max.z + shift.z;
    options.model_slice = [&mesh, shift, ux, uy](double z) {
        Paths region = slice_at(mesh, z - shift.z);
        for (Path& p : region)
            for (Point& q : p) q.X += ux, q.Y += uy;
        return region;
    };
    GcodeAnalysis a = analyse_gcode(gcode_path, options);
    a.mesh_alignment = how;
    a.mesh_offset_mm[0] = shift.x;
    a.mesh_offset_mm[1] = shift.y;
    a.mesh_offset_mm[2] = shift.z;
    a.mesh_extent_mismatch_mm = mismatch;
    return a;
}

}  // namespace carve

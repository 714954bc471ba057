// The JSON form of carve check's figures (the `--json` output and the stats' "check").
#include "check/gcode_analysis.hpp"

namespace carve {

namespace {

// The "per_layer" array: each layer's figures, the model's with --mesh.
nlohmann::json layers_json(const GcodeAnalysis& a) {
    nlohmann::json layers = nlohmann::json::array();
    for (const LayerFigures& l : a.per_layer) {
        nlohmann::json lj = {{"z_mm", l.z_mm},
                             {"height_mm", l.height_mm},
                             {"extruded_volume_mm3", l.extruded_volume_mm3},
                             {"path_length_mm", l.path_length_mm},
                             {"footprint_area_mm2", l.footprint_area_mm2},
                             {"unsupported_area_mm2", l.unsupported_area_mm2},
                             {"far_unsupported_area_mm2", l.far_unsupported_area_mm2},
                             {"retractions", l.retractions},
                             {"travel_length_mm", l.travel_length_mm},
                             {"stick_time_s", l.stick_time_s},
                             {"longest_bridge_mm", l.longest_bridge_mm}};
        if (a.model_checked) {
            lj["outside_area_mm2"] = l.outside_area_mm2;
            lj["max_outside_model_mm"] = l.max_outside_model_mm;
            lj["hanging_inside_mm2"] = l.hanging_inside_mm2;
            lj["hanging_overhang_mm2"] = l.hanging_overhang_mm2;
            lj["hanging_support_mm2"] = l.hanging_support_mm2;
            lj["outside_support_mm2"] = l.outside_support_mm2;
            lj["travel_inside_mm"] = l.travel_inside_mm;
            lj["travel_outside_mm"] = l.travel_outside_mm;
            lj["wall_crossings"] = l.wall_crossings;
            lj["uncovered_mm2"] = l.uncovered_mm2;
        }
        layers.push_back(std::move(lj));
    }
    return layers;
}

}  // namespace

nlohmann::json to_json(const GcodeAnalysis& a, bool with_layers) {
    nlohmann::json j = {
        {"generator", a.generator},
        {"layers", a.layers},
        {"first_z_mm", a.first_z_mm},
        {"last_z_mm", a.last_z_mm},
        {"filament_diameter_mm", a.filament_diameter_mm},
        {"filament_diameter_source", a.filament_diameter_source},
        {"nozzle_diameter_mm", a.nozzle_diameter_mm},
        {"filament_length_mm", a.filament_length_mm},
        {"extruded_volume_mm3", a.extruded_volume_mm3},
        {"path_length_mm", a.path_length_mm},
        {"travel_length_mm", a.travel_length_mm},
        {"mean_line_width_mm", a.mean_line_width_mm},
        {"bead_model", a.bead_model},
        {"footprint_area_mm2", a.footprint_area_mm2},
        {"unsupported_area_mm2", a.unsupported_area_mm2},
        {"far_unsupported_area_mm2", a.far_unsupported_area_mm2},
        {"unsupported_percent", 100 * a.unsupported_fraction},
        {"far_unsupported_percent", 100 * a.far_unsupported_fraction},
        {"estimated_time_from_header_s", a.estimated_time_from_header_s},
        {"filament_used_from_header_mm", a.filament_used_from_header_mm},
        {"moves", a.moves},
        {"extruding_moves", a.extruding_moves},
        {"retractions", a.retractions},
        {"firmware_retractions", a.firmware_retractions},
        {"stick_time_s", a.stick_time_s},
        {"arcs", a.arcs},
        {"z_reversals", a.z_reversals},
        {"model_checked", a.model_checked},
        {"support_volume_mm3", a.support_volume_mm3},
        {"support_gap_mm", a.support_gap_mm},
        {"longest_bridge",
         {{"length_mm", a.longest_bridge_mm},
          {"z_mm", a.longest_bridge_z_mm},
          {"x_mm", a.longest_bridge_x_mm},
          {"y_mm", a.longest_bridge_y_mm}}},
    };
    {
        double total = 0;
        for (const auto& [type, v] : a.volume_by_type_mm3) total += v;
        nlohmann::json types = nlohmann::json::object();
        for (const auto& [type, v] : a.volume_by_type_mm3)
            types[type] = {{"volume_mm3", v}, {"percent", total > 0 ? 100 * v / total : 0.0}};
        j["material_by_type"] = std::move(types);
    }
    if (a.model_checked) {
        j["outside_area_mm2"] = a.outside_area_mm2;
        // Split: support extrusion is meant to lie outside the model; the rest is not.
        j["outside_support_mm2"] = a.outside_support_mm2;
        j["outside_other_mm2"] = std::max(0.0, a.outside_area_mm2 - a.outside_support_mm2);
        j["max_outside_model_mm"] = a.max_outside_model_mm;
        j["hanging_inside_mm2"] = a.hanging_inside_mm2;
        j["hanging_overhang_mm2"] = a.hanging_overhang_mm2;
        j["hanging_support_mm2"] = a.hanging_support_mm2;
        j["travel_inside_mm"] = a.travel_inside_mm;
        j["travel_outside_mm"] = a.travel_outside_mm;
        j["wall_crossings"] = a.wall_crossings;
        j["model_tolerance_mm"] = a.model_tolerance_mm;
        const ColumnFigures& c = a.printability.columns;
        auto skin = [](const SkinFigures& f) {
            return nlohmann::json{{"region_mm2", f.region_mm2},
                                  {"open_mm2", f.open_mm2},
                                  {"open_percent", f.open_percent()},
                                  {"holes_1mm2", f.holes_1mm2},
                                  {"largest_hole_mm2", f.largest_hole_mm2},
                                  {"largest_hole_z_mm", f.largest_hole_z_mm}};
        };
        const UncoveredFigures& u = a.printability.uncovered;
        auto piece = [](const UncoveredPiece& p) {
            return nlohmann::json{{"area_mm2", p.area_mm2},
                                  {"layer", p.layer},
                                  {"z", p.z_mm},
                                  {"x", p.x_mm},
                                  {"y", p.y_mm}};
        };
        j["uncovered_mm2"] = u.uncovered_mm2;
        j["uncovered_percent"] = u.percent();
        j["largest_uncovered"] = piece(u.largest);
        j["uncovered"] = {{"slice_mm2", u.slice_mm2},
                          {"enclosed_mm2", u.enclosed_mm2},
                          {"deep_mm2", u.deep_mm2},
                          {"line_width_mm", u.line_width_mm},
                          {"line_width_source", u.line_width_source},
                          {"wide_pieces", u.wide_pieces},
                          {"wide_layers", u.wide_layers},
                          {"wide_mm2", u.wide_mm2},
                          {"largest_wide", piece(u.largest_wide)},
                          {"layers_above_print", u.layers_above_print}};
        const std::vector<std::string> failed = failed_rules(a);
        j["printability"] = {
            {"columns",
             {{"thin_interior", c.thin_interior},
              {"over_5mm", c.over_5mm},
              {"over_10mm", c.over_10mm},
              {"tallest",
               {{"height_mm", c.tallest_mm},
                {"layers", c.tallest_layers},
                {"width_mm", c.tallest_width_mm},
                {"z_from_mm", c.tallest_z_from_mm},
                {"z_to_mm", c.tallest_z_to_mm},
                {"x_mm", c.tallest_x_mm},
                {"y_mm", c.tallest_y_mm},
                {"top_x_mm", c.tallest_top_x_mm},
                {"top_y_mm", c.tallest_top_y_mm}}}}},
            {"top_skin", skin(a.printability.top)},
            {"bottom_skin", skin(a.printability.bottom)},
            {"hanging_inside_mm2", a.hanging_inside_mm2},
            {"hanging_overhang_mm2", a.hanging_overhang_mm2},
            {"passes", failed.empty()},
            {"failed_rules", failed},
        };
        if (!a.mesh_alignment.empty()) {
            j["mesh_alignment"] = a.mesh_alignment;
            j["mesh_offset_mm"] = {a.mesh_offset_mm[0], a.mesh_offset_mm[1], a.mesh_offset_mm[2]};
            if (a.mesh_extent_mismatch_mm >= 0)
                j["mesh_extent_mismatch_mm"] = a.mesh_extent_mismatch_mm;
        }
    }
    if (with_layers) j["per_layer"] = layers_json(a);
    return j;
}

}  // namespace carve

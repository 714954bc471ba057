// Figures of a run for machines (JSON) and for people (a few lines of text).
#include "report/stats.hpp"

#include <fmt/format.h>

namespace carve {

std::string format_duration(double seconds) {
    const long s = std::lround(seconds);
    if (s >= 3600) return fmt::format("{}h {:02}m {:02}s", s / 3600, (s / 60) % 60, s % 60);
    if (s >= 60) return fmt::format("{}m {:02}s", s / 60, s % 60);
    return fmt::format("{}s", s);
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
    j["carvable_volume_mm3"] = run.carvable_volume_mm3;
    j["cavity_volume_mm3"] = run.cavity_volume_mm3;
    j["remainder_volume_mm3"] = run.remainder_volume_mm3;
    j["cover_volume_mm3"] = run.cover_volume_mm3;
    j["cover_bridges"] = run.cover_bridges;
    j["minima_found"] = run.minima_found;
    j["minima_bridged"] = run.minima_found - run.minima_unsupported;  // wholly, by bridges
    j["minima_supported_otherwise"] = 0;  // every support today is a bridge
    j["minima_unsupported"] = run.minima_unsupported;
    j["ceilings_found"] = run.ceilings_found;
    j["ceilings_unsupported"] = run.ceilings_unsupported;
    nlohmann::json m;
    m["outer_wall_mm3"] = run.feature_mm3[0];
    m["shells_mm3"] = run.feature_mm3[1];
    m["covers_mm3"] = run.feature_mm3[2];
    m["cavity_walls_mm3"] = run.feature_mm3[3];
    m["bridges_mm3"] = run.feature_mm3[4];
    m["remainder_mm3"] = run.remainder_fill_mm3;
    std::vector<double> walls(run.cavity_wall_mm3.begin() + (run.cavity_wall_mm3.empty() ? 0 : 1),
                              run.cavity_wall_mm3.end());
    m["walls_of_cavity_mm3"] = walls;
    j["material_by_feature"] = m;
    j["mesh_closed"] = run.mesh.closed();
    j["mesh_warnings"] = run.mesh.warnings;
    nlohmann::json s;
    s["layer_height_mm"] = settings.layer_height;
    s["nozzle_mm"] = settings.nozzle;
    s["max_overhang_deg"] = settings.max_overhang;
    s["cavities"] = settings.cavities_auto ? nlohmann::json("auto") : nlohmann::json(settings.cavities);
    s["covers"] = settings.covers;
    s["shells"] = settings.shells;
    s["walls"] = settings.walls == WallMode::Single ? "single" : "double";
    s["filament_diameter_mm"] = settings.filament_diameter;
    s["tear_limit_mm"] = settings.tear_limit;
    s["whole_width_mm"] = settings.whole_width;
    s["max_bridge_length_mm"] = settings.prune_bridges ? settings.max_bridge_length : 0.0;
    s["prune_bridges"] = settings.prune_bridges;
    s["printer"] = settings.printer_name;
    j["settings"] = s;
    return j;
}

std::string summary_text(const RunResult& run, const Settings& settings) {
    std::string out;
    out += fmt::format("model      {:.1f} cm3, {} triangles, {} layers of {} mm\n",
                       run.mesh.volume_mm3 / 1000, run.mesh.triangles, run.layers,
                       settings.layer_height);
    double carved = 0;
    for (double v : run.cavity_volume_mm3) carved += v;
    out += fmt::format("cavities   {} carved {:.1f} % of the volume ({} bridges, {:.0f} mm)\n",
                       run.cavities,
                       run.mesh.volume_mm3 > 0 ? 100 * carved / run.mesh.volume_mm3 : 0.0,
                       run.bridges, run.bridge_length_mm);
    out += fmt::format("material   {:.2f} cm3 = {:.1f} % of the model, {:.2f} m of filament, {:.1f} g\n",
                       run.print.extruded_volume_mm3 / 1000, run.material_percent(),
                       run.print.filament_length_mm / 1000, run.print.filament_weight_g);
    out += fmt::format("print time {} (estimate)\n", format_duration(run.print.estimated_print_time_s));
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
    if (a.estimated_time_from_header_s >= 0)
        out += fmt::format("header time      {}\n", format_duration(a.estimated_time_from_header_s));
    return out;
}

}  // namespace carve

// The stats JSON of a run (contract in DESIGN.md) and the short summary printed at the end.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "check/gcode_analysis.hpp"
#include "config/setting_table.hpp"
#include "config/settings.hpp"
#include "report/run_result.hpp"

namespace carve {

// The key of a table setting in the stats JSON's "settings" block: its name and unit
// ("layer_height_mm", "max_overhang_deg", "covers").
std::string stats_key(const SettingSpec& spec);
nlohmann::json stats_json(const RunResult& run, const Settings& settings);
std::string summary_text(const RunResult& run, const Settings& settings);
// The stats' "orientation" block (--orient auto): the rotation chosen and every candidate.
nlohmann::json orientation_json(const OrientationChoice& o);
// The figures of `carve check` for people.
std::string describe(const GcodeAnalysis& analysis);
// `carve check --layers` without --json: one line per layer.
std::string describe_layers(const GcodeAnalysis& analysis);

// `carve check --mesh`: the analysis with the mesh as the model, sliced at the middle of every
// G-code layer. `offset` is where the mesh's coordinates land in the G-code's (G-code = mesh +
// offset). Without it the placement is found from the file: x and y put the centre of the
// extrusion's bounding box (first layer left out: prime lines, skirts) on the centre of the
// mesh's; z puts the mesh's lowest point on the bed (z = 0), as carve, PrusaSlicer and CuraEngine
// all do. That holds whatever the slicer did in x and y (carve centres on the bed, PrusaSlicer
// with --dont-arrange keeps the model's coordinates, CuraEngine may shift it), as long as the
// G-code prints this mesh at this scale and nothing else above its first layer.
GcodeAnalysis analyse_gcode_on_mesh(const std::string& gcode_path, const Mesh& mesh,
                                    GcodeAnalysisOptions options,
                                    const std::optional<Vec3>& offset = std::nullopt);

}  // namespace carve

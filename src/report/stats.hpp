// The stats JSON of a run (contract in DESIGN.md) and the short summary printed at the end.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "check/gcode_analysis.hpp"
#include "config/settings.hpp"
#include "report/run_result.hpp"

namespace carve {

nlohmann::json stats_json(const RunResult& run, const Settings& settings);
std::string summary_text(const RunResult& run, const Settings& settings);
// The figures of `carve check` for people.
std::string describe(const GcodeAnalysis& analysis);

}  // namespace carve

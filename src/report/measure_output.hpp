// carve slice's measure of the G-code it wrote (--stats-check, --stats-strength): what
// `carve check --mesh` and `carve check --strength` would say of it, from one reading of the
// file, into the run's figures.
#pragma once

#include <string>

#include "check/gcode_analysis.hpp"
#include "check/strength.hpp"
#include "geometry/types.hpp"
#include "mesh/mesh.hpp"
#include "report/run_result.hpp"

namespace carve {

struct OutputMeasure {
    bool check = false;     // RunResult::check, on `mesh` at `offset` (G-code = mesh + offset)
    bool strength = false;  // RunResult::strength
    GcodeAnalysisOptions analysis;
    StrengthOptions strength_options;
};

void measure_output(const std::string& gcode_path, const Mesh& mesh, const Vec3& offset,
                    OutputMeasure measure, RunResult& result);

}  // namespace carve

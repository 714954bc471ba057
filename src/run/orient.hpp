// --orient auto (issue #48): the orientation the run prints in, chosen by carving each candidate
// (mesh/orient.hpp) at coarse layers with supports and keeping the one extruding the least
// (private to src/run).
#pragma once

#include "config/settings.hpp"
#include "mesh/mesh.hpp"
#include "report/run_result.hpp"
#include "run/pipeline.hpp"
#include "run/run_setup.hpp"

namespace carve {

// Turns `mesh` (loaded and scaled, one copy) to the orientation chosen and fills
// result.orientation with every candidate's figures. Throws InputError when none fits the
// printer, naming why the first did not.
void choose_orientation(const Settings& settings, const RunOptions& options, Mesh& mesh,
                        RunResult& result);

}  // namespace carve

// The figures of the run summed as the layers come out of the pipeline (private to src/run):
// each layer's material by extrusion, then its volumes, minima, ceilings, ribs, bridges and
// material by feature added to the run's result. Kept out of pipeline.cpp, which wires the
// filters and calls these from the paths filter and the sink.
#pragma once

#include <vector>

#include "config/settings.hpp"
#include "report/run_result.hpp"
#include "run/tokens.hpp"
#include "supports/overhang.hpp"
#include "toolpath/toolpath.hpp"

namespace carve {

// The volume of each extrusion of a layer, in print order: the layer's material and the
// material by feature are both summed from these, so each path's length is taken once.
std::vector<double> extrusion_volumes_mm3(const LayerToolpaths& paths, const Settings& settings);

// Adds a layer's figures (its token as the sink receives it) to the run's: result, the sliced
// volume (what the slices hold) and the overhangs; each layer counts its own thickness (the
// first layer's may differ).
void add_layer_figures(const Token& t, const Settings& settings, RunResult& result,
                       double& sliced_volume, OverhangTally& overhangs);

}  // namespace carve

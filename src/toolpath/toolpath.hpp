// Print paths of one layer from its partition (report section 4): outer wall and shells, solid
// cover lines, cavity walls (single filament 4.3 or double 4.1) in cavity order C^0..C^k
// (4.2), bridges, ordered to keep travel short.
#pragma once

#include <string_view>
#include <vector>

#include "carving/partition.hpp"
#include "config/settings.hpp"

namespace carve {

enum class Feature { OuterWall, Shell, Cover, CavityWall, Bridge };
std::string_view feature_name(Feature f);  // the ;TYPE: comment (Cura/PrusaSlicer words)

struct Extrusion {
    Feature feature = Feature::OuterWall;
    Path points;          // micrometres, model XY coordinates
    bool closed = false;  // a loop returns to its first point
    double flow = 1.0;    // multiplier on the nominal width x height cross-section
    int cavity = 0;       // j for cavity walls (0 = the outer wall)
};

struct LayerToolpaths {
    int index = 0;
    double z = 0;  // nozzle height of the layer in mm above the bed: (i + 1) * h
    std::vector<Extrusion> extrusions;  // in print order
};

// Pure function of one layer: layers may be planned on worker threads.
LayerToolpaths plan_layer(const LayerPartition& layer, const Settings& settings);

}  // namespace carve

// Print paths of one layer from its partition (report section 4): outer wall and shells, solid
// cover lines, cavity walls (single filament 4.3 or double 4.1) in cavity order C^0..C^k
// (4.2), bridges, ordered to keep travel short.
#pragma once

#include <cstddef>
#include <string_view>
#include <vector>

#include "carving/partition.hpp"
#include "config/settings.hpp"

namespace carve {

// Rib: ribs under what would hang inside the model (supports/ribs.hpp). Support and
// SupportInterface: supports under the model's own overhangs, outside the model.
enum class Feature { OuterWall, Shell, Cover, CavityWall, Bridge, Rib, Support, SupportInterface };
// How many features there are: the size of the tables indexed by one.
inline constexpr size_t kFeatureCount = size_t(Feature::SupportInterface) + 1;
// How the travel to a path was planned: not at all (the first path of a layer: the G-code stage
// plans it, knowing where the layer below ended), inside the part (no retraction), or leaving it.
enum class TravelKind : unsigned char { Unplanned, Inside, Leaves };
std::string_view feature_name(Feature f);  // the ;TYPE: comment (Cura/PrusaSlicer words)

struct Extrusion {
    Feature feature = Feature::OuterWall;
    Path points;          // micrometres, model XY coordinates
    bool closed = false;  // a loop returns to its first point
    double flow = 1.0;    // multiplier on the nominal width x height cross-section
    int cavity = 0;       // j for cavity walls (0 = the outer wall)
};

// The travel that reaches a path from the previous one: the points it passes through before
// the path's first point (model XY coordinates, um), and how it was planned.
struct Travel {
    Path via;
    TravelKind kind = TravelKind::Unplanned;
};

struct LayerToolpaths {
    int index = 0;
    double z = 0;  // nozzle height of the layer in mm above the bed: (i + 1) * h
    std::vector<Extrusion> extrusions;  // in print order
    std::vector<Travel> travels;        // empty (none planned) or one per extrusion
    // Where travel may go without retracting (comb.hpp), for the travel into the layer; empty
    // without combing.
    Paths comb_region;
};

// Pure function of one layer: layers may be planned on worker threads.
LayerToolpaths plan_layer(const LayerPartition& layer, const Settings& settings);

}  // namespace carve

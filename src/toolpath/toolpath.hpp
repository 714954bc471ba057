// Print paths of one layer from its partition (report section 4): outer wall and shells, solid
// cover lines, cavity walls (single filament 4.3 or double 4.1) in cavity order C^0..C^k
// (4.2), bridges, ordered to keep travel short.
#pragma once

#include <cstddef>
#include <string_view>
#include <vector>

#include "carving/layer.hpp"
#include "config/settings.hpp"

namespace carve {

// Rib: ribs under what would hang inside the model (supports/ribs.hpp). Tie: the walls tied
// across the cavities (--ties), their own so that the stats show what they cost. Support and
// SupportInterface: supports under the model's own overhangs, outside the model.
// Skirt and Brim: loops on the bed around the first layer (toolpath/skirt.hpp).
enum class Feature {
    OuterWall,
    Shell,
    Cover,
    CavityWall,
    Bridge,
    Rib,
    Tie,
    Support,
    SupportInterface,
    Skirt,
    Brim
};
// How many features there are: the size of the tables indexed by one.
inline constexpr size_t kFeatureCount = size_t(Feature::Brim) + 1;
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
    // The region inside the outer wall's centreline, where the travel into the layer may go
    // where the comb region is too thin or splits (Combing::All); empty otherwise.
    Paths thin_region;
    // Islands printed one after the other: island k is extrusions [island_starts[k],
    // island_starts[k + 1]); what follows the last island (supports, paths of no island) comes
    // after them in either order. Empty for a layer of fewer than two islands. The G-code stage,
    // which knows where the layer below ended, may print them last to first so that the layer
    // starts in that island: the layers are planned in parallel and cannot know it.
    std::vector<size_t> island_starts;
    // What of the model's slice is narrower than --min-feature-size and printed by nothing, mm2
    // (thin_walls.hpp); not spilled: the run sums it before the layer is.
    double unprinted_mm2 = 0;
};

// The layer with its islands printed last to first, each island's paths in their order. The
// travel into each island's first path (and into the first path after the islands) is left
// unplanned, for the G-code stage to plan from where the nozzle is.
LayerToolpaths with_islands_reversed(const LayerToolpaths& layer);

// Pure function of one layer: layers may be planned on worker threads.
LayerToolpaths plan_layer(const LayerRecord& layer, const Settings& settings);

}  // namespace carve

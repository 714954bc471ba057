// Solid fill of cover regions (private to the toolpath stage).
//
// Parallel scanlines across each connected component, evenly spaced so that the first and last
// lines sit on the component's extremes, joined into zig-zags by the piece of the region's
// boundary between consecutive line ends (so every connector stays inside the region).
#pragma once

#include <vector>

#include "toolpath/toolpath.hpp"

namespace carve {

// Lines whose centres lie in `region`, at angle `angle_deg` to the x axis, spaced at most
// `spacing`. When a component's width is not a multiple of the spacing the lines get slightly
// closer and their flow is reduced in proportion, so the deposited volume matches the area.
std::vector<Extrusion> fill_solid(const Paths& region, double angle_deg, Coord spacing,
                                  Feature feature);

}  // namespace carve

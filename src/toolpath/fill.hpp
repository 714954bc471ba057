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

// One line along the medial axis of each piece of `region`, for strips too narrow for two lines
// (what the walls and the solid fill leave of a cover band on a slope). The line is as wide as
// the strip where it runs, plus `overlap` so that it joins what lies on either side: its path
// is cut where that width changes by more than a tenth of `line_width`, and each run is one
// extrusion with the flow of its mean width (the bead's width over `line_width`). Where the
// strip is narrower than `min_width` nothing is printed.
std::vector<Extrusion> fill_thin(const Paths& region, Coord line_width, Coord overlap,
                                 Coord min_width, Feature feature);

}  // namespace carve

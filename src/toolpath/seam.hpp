// Seam placement on closed loops (issue #18): which vertex the outer wall starts and ends at.
#pragma once

#include <cstddef>

#include "config/settings.hpp"
#include "geometry/types.hpp"

namespace carve {

// The vertex of `loop` (interior on its left: outer contours counter-clockwise, holes
// clockwise) where it should start. A pure function of the loop and the layer, so layers planned
// on different threads agree: `aligned` picks the sharpest concave corner (seen from outside:
// the bump hides in the crease), else a convex one, else a smooth point, and among equals the
// one furthest in one fixed direction, which is the same place from layer to layer on a prism or
// a cylinder. `rear` is the point furthest back (+Y), `random` a vertex drawn from the layer and
// loop numbers. `nearest` returns the vertex nearest `nozzle`.
size_t seam_vertex(const Path& loop, SeamMode mode, int layer, size_t loop_index,
                   const Point& nozzle);

}  // namespace carve

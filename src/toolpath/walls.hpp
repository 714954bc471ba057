// Single-filament cavity walls (report 4.3), private to the toolpath stage.
#pragma once

#include <vector>

#include "geometry/types.hpp"

namespace carve {

struct WallPiece {
    Path points;
    bool closed = false;
};

// The parts of the closed `loops` that lie in region ⊖ depth: inside `region` and at least
// `depth` from its boundary (the report's R = ∂P ∩ W with W = V ⊖ t, the disk a true disk).
// Each open piece is then extended by `extension` at both ends along its own loop, so that it
// runs on along the wall printed before it; pieces that meet after extension are merged, and a
// piece that covers its whole loop becomes a closed loop again. Pieces shorter than
// `min_length` before extension are dropped. Lengths in micrometres.
std::vector<WallPiece> loops_inside_erosion(const Paths& loops, const Paths& region, Coord depth,
                                            double extension, double min_length);

}  // namespace carve

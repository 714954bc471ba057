// Travel ordering of one group of print paths (private to the toolpath stage).
#pragma once

#include <vector>

#include "toolpath/toolpath.hpp"

namespace carve {

// Greedy nearest neighbour from `pos`: the next path is the one with the nearest entry point
// (any vertex of a closed loop, either end of an open path). Loops are rotated to start at
// that vertex, open paths reversed when entered from their last point. `pos` ends at the exit
// of the last path. Near-linear: entry points are kept in a uniform grid. With
// `keep_loop_starts`, closed loops are entered only at their first point (a placed seam).
void order_nearest(std::vector<Extrusion>& paths, Point& pos, bool keep_loop_starts = false);

// Shortens the travel of an order from `start` (nearest neighbour's, say): 2-opt moves (a run
// of paths printed in reverse, each open path reversed too) within a window of 24 paths, two
// passes, then every loop restarted at the vertex where the travel into and out of it is shortest
// (unless `keep_loop_starts`). Never lengthens the travel; `pos` ends at the new exit of the last
// path.
void improve_order(std::vector<Extrusion>& paths, const Point& start, Point& pos,
                   bool keep_loop_starts = false);

}  // namespace carve

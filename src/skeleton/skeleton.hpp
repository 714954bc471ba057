// SKEL (report section 5.2): the seed shape from which a cavity is torn open in a slice.
//
// Medial axis from Boost.Polygon's segment Voronoi diagram of the contours, interior primary
// edges only, pruned with the extended distance function of Liu et al. (2011) so that contour
// noise does not sprout branches, parabolic arcs linearised, then thickened by the nozzle radius.
#pragma once

#include "geometry/types.hpp"

namespace carve {

struct SkeletonOptions {
    Coord prune_threshold = 400;  // EDF - R below this (units) is pruned; order of the nozzle width
    Coord thickness = 200;        // half-width of the dilated axis: nozzle radius s
    Coord max_arc_error = 5;      // chord error when linearising parabolic arcs
};

// The pruned medial axis as open polylines (a point axis is a one-point path).
Paths medial_axis(const Paths& region, const SkeletonOptions& options);

// SKEL(S): the pruned medial axis thickened by options.thickness, clipped to S.
Paths skeleton(const Paths& region, const SkeletonOptions& options);

}  // namespace carve

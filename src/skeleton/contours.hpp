// SKEL internals: turning a region into input Boost's segment Voronoi builder accepts.
//
// The builder needs integer segments that meet only at their endpoints. Clipper's union gets
// close, but it leaves contours touching (a vertex on another edge), and its rounding leaves
// rare defects (a vertex a fraction of a unit across another contour's edge, a segment shared
// by two contours); these functions find and mend them. Private to src/skeleton (and its tests).
#pragma once

#include <vector>

#include "geometry/types.hpp"

namespace carve::skel {

// Components of the region (outer contour first, then its holes; interior on the left of every
// contour), cleaned of repeated, collinear and spike points, simplified so that no contour moves
// by more than `tolerance` units, and mended (mend_component) so that segments meet only at
// common endpoints. `mended`, if given, receives the number of components that needed mending.
std::vector<Paths> prepare_components(const Paths& region, double tolerance, int* mended = nullptr);

// Mends a component in place: segments meeting elsewhere than at a common endpoint (exact
// integer test) are split, at the other's vertex nearest to them when it is within 1.5 units
// (Clipper's rounding put it a hair across, or left it on the segment), else at their rounded
// crossing; pairs of edges along the same segment in opposite directions (spikes, zero-width
// walls between contours) are removed and the contours re-linked around them. Returns the
// number of changes; 0 means the component already met Boost's precondition.
int mend_component(Paths& component);

}  // namespace carve::skel

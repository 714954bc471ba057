// Boolean operations and measures on planar regions (thin wrappers over Clipper 6).
//
// Every function takes regions in any orientation and fill rule non-zero unless stated, and
// returns a normalised region: outer contours counter-clockwise, holes clockwise, no
// self-intersections. Free functions so that the stages read like the report's formulas.
#pragma once

#include "geometry/types.hpp"

namespace carve {

// Signed area in square units (positive for counter-clockwise).
double area(const Path& path);
// Area of a region in square units: outer areas minus holes.
double area(const Paths& region);
inline double area_mm2(const Paths& region) {
    return area(region) / (kUnitsPerMm * kUnitsPerMm);
}

Paths unite(const Paths& a);  // self-union: resolves overlaps, non-zero fill
Paths unite(const Paths& a, const Paths& b);
Paths intersect(const Paths& a, const Paths& b);
Paths subtract(const Paths& a, const Paths& b);
// The union of `a`'s contours (non-zero fill, overlaps allowed) minus `b`, in one pass.
Paths subtract_from_union(const Paths& a, const Paths& b);
Paths symmetric_difference(const Paths& a, const Paths& b);
// Union of contours whose orientation encodes the sign (convolution output): positive fill.
Paths unite_positive(const Paths& a);

// A region given by contours whose winding number is positive exactly inside it, crossings
// and overlaps allowed: a Minkowski sum before the union that resolves it (morphology.hpp).
// An operation that reads it with the positive fill rule takes it as is, so a morphology
// result used once saves that union, a whole Clipper pass over the sum's many crossings.
struct PositiveRegion {
    Paths contours;
};
Paths resolve(const PositiveRegion& a);  // the normalised region
Paths subtract(const PositiveRegion& a, const Paths& b);
// `a` minus, or within, a positive region: a normalised `a` against a region given by contours
// whose winding is positive exactly inside it and never negative (a dilation before its union,
// with normalised regions added to it: their union).
Paths subtract_positive(const Paths& a, const PositiveRegion& b);
Paths intersect_positive(const Paths& a, const PositiveRegion& b);

// Clips open polylines to a region: the parts of `lines` inside `region`.
Paths clip_lines(const Paths& lines, const Paths& region);

// Removes duplicate and almost-collinear points (distance tolerance in units).
Paths clean(const Paths& region, double tolerance = 1.415);

// How far (units) a contour may move when its points in line with their neighbours are dropped:
// far below a printer's resolution (an eightieth of a line width). The G-code and the regions
// that only feed a measure or a smoothing (the bridges' erosion, the walls' opening, the
// propagated cavity) are simplified this much; each Clipper pass costs per vertex.
constexpr double kSimplify = 5.0;

// Drops the points of a closed contour that lie within `tolerance` of the segment joining
// their neighbours, between them, never two in a row: unlike clean(), which re-tests after
// each removal and can flatten a finely sampled gentle curve by far more than its tolerance,
// no point ends further than `tolerance` from the result.
void drop_straight_points(Path& path, double tolerance);
Paths simplify(const Paths& region, double tolerance);

BBox2 bounds(const Path& path);
BBox2 bounds(const Paths& region);
// Grows `box` to hold `other` too (an empty box holds nothing).
void expand(BBox2& box, const BBox2& other);
// Whether two boxes share at least a point (closed boxes; an empty box overlaps nothing).
bool overlap(const BBox2& a, const BBox2& b);
// Whether `inner` lies in `outer` (closed boxes).
bool contains(const BBox2& outer, const BBox2& inner);

// Total length of polylines in units; closed = count the closing edge.
double length(const Paths& paths, bool closed);

// The outer contours with their holes, one region per connected component; `region`
// normalised (as every result here is).
std::vector<Paths> components(const Paths& region);
// The region split where no contour's box overlaps another part's: each cluster is a union of
// whole components (a hole's box lies in its outer's), found without a boolean. Operations
// local to components (morphology, booleans) can run cluster by cluster.
std::vector<Paths> clusters(const Paths& region);

// Each contour cut to an axis-aligned box (Sutherland-Hodgman), without a boolean: outside
// parts are replaced by runs along the box, so every point inside the box keeps its winding
// number, but contours may run over each other on its sides. Read the result under non-zero
// fill (any boolean), or unite it: it is then region ∩ box.
Paths clip_to_box(const Paths& region, const BBox2& box);

// The contours of a normalised `region` whose box, grown by `reach`, meets the box of an outer
// contour of `other`. What is left out is outers, with their holes and islands (which lie in
// their boxes), and holes, which are filled, all further than `reach` from `other`: a dilation
// by up to `reach` of the result equals that of `region` within `other`, and so does any
// boolean with it.
Paths contours_near(const Paths& region, const Paths& other, Coord reach);

// The region with its holes filled: the union of its outer (counter-clockwise) contours. What
// a brim, skirt or raft goes around.
Paths without_holes(const Paths& region);

// Holes of a normalised region that contain nothing else of the region (no island inside), as
// counter-clockwise contours. Used for island local minima.
Paths empty_holes(const Paths& region);

bool point_in_region(const Point& p, const Paths& region);

}  // namespace carve

// Exact morphology by a fixed disk: Minkowski sums with a regular polygon (report Appendix A).
//
// Dilation convolves each contour with the element and unites the result with positive winding;
// erosion reverses the contours, convolves, reverses back and unites. Because the structuring
// element is always the same polygon, dilate(dilate(S, a), b) equals dilate(S, a + b) up to
// rounding and the vertex count does not grow with repeated use, which is what the top-down
// sweep needs. Clipper's ClipperOffset is deliberately not used here.
#pragma once

#include "geometry/polygon.hpp"

namespace carve {

// Sides of the structuring element, 24 as DESIGN.md specifies. It is inscribed in the disk of
// radius r, so it reaches r at its vertices and r cos(pi / n) at the middle of its sides (0.86 %
// short with 24). Any multiple of 4 works (erode() needs vertices on both axes) and the tests
// follow it; 16 sides measured 11 % fewer instructions on fandisk (callgrind) for material
// within 0.1 %, but the element is part of the design other tools may rebuild.
constexpr int kDiskSides = 24;

// The structuring element of radius r: kDiskSides integer vertices, counter-clockwise, centred
// on 0.
Path disk(Coord radius);

// `region` must be normalised as every function of polygon.hpp returns it: outers
// counter-clockwise, holes clockwise, no overlaps. A region given wholly clockwise is accepted;
// overlapping outers (raw non-zero fill) are fine for dilate but must be united before erode.
// The result is exact for any radius, up to the rounding of the element to integers and of
// Clipper's intersections (about 1 um per use; repeated uses add up, see the tests).
Paths dilate(const Paths& region, Coord radius);  // S ⊕ D(r)
Paths erode(const Paths& region, Coord radius);  // S ⊖ D(r), complement of the dilated complement
// The dilation before its union: its winding is never negative (see morphology.cpp), so
// normalised regions added to it make their union, read with the positive fill rule.
PositiveRegion dilation(const Paths& region, Coord radius);
// The erosion before its union (see PositiveRegion), for an operation that uses it once.
PositiveRegion erosion(const Paths& region, Coord radius);
inline Paths open(const Paths& region, Coord radius) {
    return dilate(erode(region, radius), radius);
}
inline Paths close(const Paths& region, Coord radius) {
    return erode(dilate(region, radius), radius);
}

// The holes of `region` that hold no disk of radius `radius`, each less the islands inside it
// (a moat round an island is a narrow hole), as one region (outer contours counter-clockwise).
// Too narrow for a line, and the cover under one, where it starts over a cavity, too.
Paths narrow_holes(const Paths& region, Coord radius);

// Thickens open polylines (e.g. a pruned medial axis) into a region of half-width `radius`.
Paths dilate_lines(const Paths& polylines, Coord radius);

}  // namespace carve

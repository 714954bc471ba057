// Shapes the unit tests build their slices from.
#pragma once

#include <cmath>
#include <numbers>

#include "geometry/types.hpp"

namespace carve::test {

// The axis-aligned rectangle [x0, x1] x [y0, y1] as one counter-clockwise contour (x0 < x1 and
// y0 < y1), and as a region of that one contour.
inline Path rect(Coord x0, Coord y0, Coord x1, Coord y1) {
    return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}
inline Paths rect_region(Coord x0, Coord y0, Coord x1, Coord y1) {
    return {rect(x0, y0, x1, y1)};
}

// A regular n-gon of radius r around (cx, cy), counter-clockwise, vertices rounded to units.
inline Path circle(double cx, double cy, double r, int n = 64) {
    Path p;
    for (int i = 0; i < n; ++i) {
        const double t = 2 * std::numbers::pi * i / n;
        p.emplace_back(Coord(std::llround(cx + r * std::cos(t))),
                       Coord(std::llround(cy + r * std::sin(t))));
    }
    return p;
}

}  // namespace carve::test

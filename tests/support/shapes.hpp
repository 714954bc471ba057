// Shapes the unit tests build their slices from.
#pragma once

#include <algorithm>
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

// Distance from p to the nearest edge of region's contours (in units), inside or out.
inline double distance_to_boundary(const Point& p, const Paths& region) {
    double best = 1e18;
    for (const Path& c : region)
        for (size_t i = 0; i < c.size(); ++i) {
            const Point& a = c[i];
            const Point& b = c[(i + 1) % c.size()];
            const double dx = double(b.X - a.X), dy = double(b.Y - a.Y);
            const double len2 = dx * dx + dy * dy;
            double t = len2 > 0 ? ((p.X - a.X) * dx + (p.Y - a.Y) * dy) / len2 : 0;
            t = std::clamp(t, 0.0, 1.0);
            best = std::min(best, std::hypot(p.X - (a.X + t * dx), p.Y - (a.Y + t * dy)));
        }
    return best;
}

// Distance from p to the nearest segment of open polylines (in units).
inline double distance_to_lines(const Point& p, const Paths& lines) {
    double best = 1e18;
    for (const Path& l : lines)
        for (size_t k = 0; k + 1 < l.size(); ++k)
            best = std::min(best, distance_to_boundary(p, Paths{Path{l[k], l[k + 1]}}));
    return best;
}

}  // namespace carve::test

// Arc fitting (see arcs.hpp). Greedy and local: from the first point the run grows while one
// circle, through its first, middle and last points, still holds every point and every chord.
#include "gcode/arcs.hpp"

#include <cmath>
#include <numbers>

namespace carve {

namespace {

constexpr size_t kMaxRun = 256;  // points tried per arc: bounds the quadratic re-check

struct Circle {
    double cx, cy, r;
};

// Circle through three points; nothing when they are (nearly) in line.
std::optional<Circle> circumcircle(const Point& a, const Point& b, const Point& c) {
    const double bx = double(b.X - a.X), by = double(b.Y - a.Y);
    const double cx = double(c.X - a.X), cy = double(c.Y - a.Y);
    const double d = 2 * (bx * cy - by * cx);
    if (std::fabs(d) < 1e-9) return std::nullopt;
    const double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
    const double ux = (cy * b2 - by * c2) / d, uy = (bx * c2 - cx * b2) / d;
    return Circle{double(a.X) + ux, double(a.Y) + uy, std::hypot(ux, uy)};
}

double cross(const Point& o, const Point& a, const Point& b) {
    return double(a.X - o.X) * double(b.Y - o.Y) - double(a.Y - o.Y) * double(b.X - o.X);
}

// Whether points first..last sit on the circle within `tol`, turn one way round it, and each
// chord's arc bulges less than `tol` from it; the swept angle and direction when they do.
bool holds(const std::vector<Point>& p, size_t first, size_t last, const Circle& c, double tol,
           bool& ccw, double& sweep) {
    const double side = cross(p[first], p[first + 1], p[last]);
    ccw = side > 0;
    sweep = 0;
    for (size_t k = first; k <= last; ++k) {
        const double d = std::hypot(double(p[k].X) - c.cx, double(p[k].Y) - c.cy);
        if (std::fabs(d - c.r) > tol) return false;
        if (k == last) break;
        const double a0 = std::atan2(double(p[k].Y) - c.cy, double(p[k].X) - c.cx);
        const double a1 = std::atan2(double(p[k + 1].Y) - c.cy, double(p[k + 1].X) - c.cx);
        double step = a1 - a0;
        if (step > std::numbers::pi) step -= 2 * std::numbers::pi;
        if (step < -std::numbers::pi) step += 2 * std::numbers::pi;
        if ((step > 0) != ccw || step == 0) return false;
        // The arc over a chord of angle t bulges r (1 - cos(t / 2)) from it.
        if (c.r * (1 - std::cos(step / 2)) > tol) return false;
        sweep += step;
    }
    return std::fabs(sweep) < 2 * std::numbers::pi - 1e-6;
}

}  // namespace

std::optional<Arc> fit_arc(const std::vector<Point>& points, size_t first, double tolerance,
                           size_t min_points, double min_radius, double max_radius) {
    std::optional<Arc> best;
    const size_t end = std::min(points.size(), first + kMaxRun);
    for (size_t last = first + min_points - 1; last < end; ++last) {
        const auto c = circumcircle(points[first], points[(first + last) / 2], points[last]);
        if (!c || c->r < min_radius || c->r > max_radius) break;
        bool ccw = true;
        double sweep = 0;
        if (!holds(points, first, last, *c, tolerance, ccw, sweep)) break;
        best = Arc{last, c->cx, c->cy, ccw, std::fabs(sweep) * c->r};
    }
    return best;
}

}  // namespace carve

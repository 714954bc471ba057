// Minkowski sums by contour convolution with a regular 24-gon (report Appendix A).
//
// For each contour vertex the convolution walks the structuring element's vertices between the
// supporting vertices of the incoming and outgoing edges: forwards on a left turn, backwards on a
// right turn. The backwards walks create small loops of negative winding that the positive-fill
// union removes, leaving the exact sum of the polygon with the (integer) 24-gon.
#include "geometry/morphology.hpp"

#include <array>
#include <numbers>

#include "geometry/polygon.hpp"

namespace carve {

namespace {

constexpr int kSides = 24;
constexpr double kStep = 2.0 * std::numbers::pi / kSides;

std::array<Point, kSides> element(Coord radius) {
    std::array<Point, kSides> q;
    for (int m = 0; m < kSides; ++m)
        q[m] = Point(static_cast<Coord>(std::llround(radius * std::cos(m * kStep))),
                     static_cast<Coord>(std::llround(radius * std::sin(m * kStep))));
    return q;
}

// Index of the element vertex that supports the outward (right-hand) normal of edge d.
int support(const Point& d) {
    double theta = std::atan2(-double(d.X), double(d.Y));  // angle of (dy, -dx)
    int m = static_cast<int>(std::lround(theta / kStep));
    return ((m % kSides) + kSides) % kSides;
}

void convolve(const Path& contour, const std::array<Point, kSides>& q, Paths& out) {
    // Drop repeated points: a zero-length edge has no normal.
    Path p;
    p.reserve(contour.size());
    for (const Point& v : contour)
        if (p.empty() || v != p.back()) p.push_back(v);
    while (p.size() > 1 && p.front() == p.back()) p.pop_back();
    const size_t n = p.size();
    if (n == 0) return;
    Path result;
    if (n == 1) {
        for (const Point& v : q) result.emplace_back(p[0].X + v.X, p[0].Y + v.Y);
        out.push_back(std::move(result));
        return;
    }
    std::vector<int> idx(n);
    std::vector<Point> edge(n);
    for (size_t i = 0; i < n; ++i) {
        const Point& a = p[i];
        const Point& b = p[(i + 1) % n];
        edge[i] = Point(b.X - a.X, b.Y - a.Y);
        idx[i] = support(edge[i]);
    }
    result.reserve(n * 2 + kSides);
    for (size_t i = 0; i < n; ++i) {
        const size_t prev_edge = (i + n - 1) % n;
        const int from = idx[prev_edge];
        const int to = idx[i];
        const Point& e0 = edge[prev_edge];
        const Point& e1 = edge[i];
        const double turn = double(e0.X) * double(e1.Y) - double(e0.Y) * double(e1.X);
        int forward = ((to - from) % kSides + kSides) % kSides;
        int backward = (kSides - forward) % kSides;
        int dir = 1, steps = forward;
        if (turn < 0 || (turn == 0 && forward > kSides / 2)) dir = -1, steps = backward;
        if (steps > kSides / 2 && turn != 0) {  // rounding of the normal angle: take the short way
            dir = -dir;
            steps = kSides - steps;
        }
        const Point& v = p[i];
        for (int s = 0, m = from; s <= steps; ++s, m = ((m + dir) % kSides + kSides) % kSides)
            result.emplace_back(v.X + q[m].X, v.Y + q[m].Y);
    }
    out.push_back(std::move(result));
}

Paths convolve_all(const Paths& region, Coord radius) {
    const auto q = element(radius);
    Paths conv;
    conv.reserve(region.size());
    for (const Path& c : region) convolve(c, q, conv);
    return conv;
}

}  // namespace

Path disk(Coord radius) {
    const auto q = element(radius);
    return Path(q.begin(), q.end());
}

Paths dilate(const Paths& region, Coord radius) {
    if (radius <= 0 || region.empty()) return radius < 0 ? erode(region, -radius) : region;
    return unite_positive(convolve_all(region, radius));
}

Paths erode(const Paths& region, Coord radius) {
    if (radius <= 0 || region.empty()) return radius < 0 ? dilate(region, -radius) : region;
    Paths reversed = region;
    ClipperLib::ReversePaths(reversed);
    Paths conv = convolve_all(reversed, radius);  // the element is centrally symmetric
    ClipperLib::ReversePaths(conv);
    return unite_positive(conv);
}

Paths dilate_lines(const Paths& polylines, Coord radius) {
    Paths closed;
    closed.reserve(polylines.size());
    for (const Path& line : polylines) {
        if (line.empty()) continue;
        Path there_and_back = line;
        for (size_t i = line.size() - 1; i-- > 1;) there_and_back.push_back(line[i]);
        closed.push_back(std::move(there_and_back));
    }
    return unite_positive(convolve_all(closed, radius));
}

}  // namespace carve

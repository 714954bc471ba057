// Minkowski sums by contour convolution with a regular polygon (report Appendix A).
//
// For each contour vertex the convolution walks the structuring element's vertices between the
// supporting vertices of the incoming and outgoing edges. The report walks forwards on a left
// turn and backwards on a right turn, then keeps positive winding. That is only exact while no
// offset edge inverts: a hole smaller than the element, dilated, leaves a loop of winding -1
// that cancels the +1 of the outer contour and keeps a hole that should have closed (and
// erosion by more than the inradius leaves a phantom). So on a right turn we go back through
// the vertex itself instead (v + q_from, v, v + q_to). Then, contour by contour, the winding
// number of the cycle is the contour's own winding plus one for every swept edge (the edge and
// its translate by its supporting vertex) and every fan of the element at a left turn, all of
// them positive. Their union with the region is exactly the region plus the element: the
// positive-fill union is exact however large the radius. Erosion is the same on the reversed
// contours: the region minus the inward swept edges and fans.
#include "geometry/morphology.hpp"

#include <array>
#include <numbers>
#include <optional>

#include "geometry/polygon.hpp"
#include "geometry/probe.hpp"

namespace carve {

namespace {

constexpr int kSides = kDiskSides;
constexpr double kStep = 2.0 * std::numbers::pi / kSides;
static_assert(kSides % 4 == 0, "without_vanishing() needs vertices on both axes");

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

// At a right turn the two translated edges cross. Where they cross within the half of each
// edge nearest the vertex, the sum's boundary turns at the crossing, relative to the vertex: the
// spike out to the vertex and back (the general path) only adds a quadrilateral that both swept
// edges already cover. Dropping it matters for speed: on curved contours every spike, r long,
// crosses the translates of the neighbouring edges, and the union's cost grows with crossings.
// Half of each edge at most, so the corners at its two ends never trim it past each other.
std::optional<Point> corner(const Point& e0, const Point& e1, double turn, const Point& q_from,
                            const Point& q_to) {
    if (turn >= 0) return std::nullopt;
    // v + q_from - s e0 = v + q_to + u e1
    const double wx = double(q_from.X - q_to.X), wy = double(q_from.Y - q_to.Y);
    const double s = (wx * double(e1.Y) - wy * double(e1.X)) / turn;
    const double u = -(wx * double(e0.Y) - wy * double(e0.X)) / turn;
    if (!(s > 0 && s < 0.5 && u > 0 && u < 0.5)) return std::nullopt;
    return Point(q_to.X + std::llround(u * double(e1.X)), q_to.Y + std::llround(u * double(e1.Y)));
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
    result.reserve(n * 3 + kSides);
    for (size_t i = 0; i < n; ++i) {
        const size_t prev_edge = (i + n - 1) % n;
        const int from = idx[prev_edge];
        const int to = idx[i];
        const Point& e0 = edge[prev_edge];
        const Point& e1 = edge[i];
        // Exact for |coordinates| below 2^26 um (67 m).
        const double turn = double(e0.X) * double(e1.Y) - double(e0.Y) * double(e1.X);
        const double dot = double(e0.X) * double(e1.X) + double(e0.Y) * double(e1.Y);
        const int forward = ((to - from) % kSides + kSides) % kSides;
        const Point& v = p[i];
        // A left turn sweeps the fan of the element between the two normals. A reversal
        // (polyline end, spike) is treated as a left turn: its fan lies in the sum anyway, as
        // does any fan at a vertex of the region. A left turn whose rounded normals disagree
        // with the turn's sign (nearly straight edges) falls through to the vertex path.
        const bool fan = turn > 0 ? forward <= kSides / 2 + 1 : (turn == 0 && dot < 0);
        if (fan) {
            for (int s = 0, m = from; s <= forward; ++s, m = (m + 1) % kSides)
                result.emplace_back(v.X + q[m].X, v.Y + q[m].Y);
        } else if (from == to) {
            result.emplace_back(v.X + q[from].X, v.Y + q[from].Y);
        } else if (const auto x = corner(e0, e1, turn, q[from], q[to])) {
            result.emplace_back(v.X + x->X, v.Y + x->Y);
        } else {
            result.emplace_back(v.X + q[from].X, v.Y + q[from].Y);
            result.emplace_back(v);
            result.emplace_back(v.X + q[to].X, v.Y + q[to].Y);
        }
    }
    // Along an arc made by earlier uses of the element, each fan point and the next translated
    // edge are in line but for the rounding of the two elements: the convolution would carry
    // twice the arc's vertices into the booleans that read it unresolved, and Clipper's own
    // union drops only exactly collinear points.
    drop_straight_points(result, 1.0);
    out.push_back(std::move(result));
}

Paths convolve_all(const Paths& region, Coord radius) {
    const auto q = element(radius);
    Paths conv;
    conv.reserve(region.size());
    for (const Path& c : region) convolve(c, q, conv);
    return conv;
}

// The element reaches exactly ±r along both axes (it has vertices at 0 and 90 degrees), so a
// component whose outer contour's box is narrower than 2r in x or y holds no translate of it and
// erodes to nothing, with its holes and anything nested inside it. Late in the sweep slices
// hold dozens of such specks; leaving them out spares their convolution and its intersections
// in the union. Exact: a dropped outer's holes are found by a vertex inside it (in a normalised
// region a hole's contour does not cross an outer's).
Paths without_vanishing(const Paths& region, Coord radius) {
    const auto narrow = [radius](const BBox2& b) {
        return b.max_x - b.min_x < 2 * radius || b.max_y - b.min_y < 2 * radius;
    };
    std::vector<double> areas(region.size());  // signed: outers > 0, holes < 0
    std::vector<size_t> dropped;
    std::vector<BBox2> dropped_box;
    for (size_t i = 0; i < region.size(); ++i) {
        areas[i] = area(region[i]);
        if (areas[i] <= 0) continue;
        const BBox2 b = bounds(region[i]);
        if (narrow(b)) dropped.push_back(i), dropped_box.push_back(b);
    }
    if (dropped.empty()) return region;
    Paths out;
    out.reserve(region.size() - dropped.size());
    size_t next = 0;
    for (size_t i = 0; i < region.size(); ++i) {
        if (next < dropped.size() && dropped[next] == i) {
            ++next;
            continue;
        }
        const Path& c = region[i];
        bool inside_dropped = false;
        if (areas[i] < 0 && !c.empty()) {
            const BBox2 b = bounds(c);
            for (size_t d = 0; d < dropped.size() && !inside_dropped; ++d) {
                const BBox2& o = dropped_box[d];
                inside_dropped = b.min_x >= o.min_x && b.max_x <= o.max_x && b.min_y >= o.min_y &&
                                 b.max_y <= o.max_y &&
                                 ClipperLib::PointInPolygon(c.front(), region[dropped[d]]) != 0;
            }
        }
        if (!inside_dropped) out.push_back(c);
    }
    return out;
}

}  // namespace

Path disk(Coord radius) {
    const auto q = element(radius);
    return Path(q.begin(), q.end());
}

namespace {

// dilation() without its timer, so that dilate() counts once in the profile. The convolution
// reads orientation as sign, so a region given clockwise (a mirrored mesh, a hand-made square)
// is normalised first. Overlapping outers are not detected (see header).
PositiveRegion dilation_contours(const Paths& region, Coord radius) {
    if (radius <= 0 || region.empty()) return {radius < 0 ? erode(region, -radius) : region};
    if (area(region) < 0) return dilation_contours(unite(region), radius);
    return {convolve_all(region, radius)};
}

}  // namespace

Paths dilate(const Paths& region, Coord radius) {
    GeometryTimer timer(GeometryOp::kMorphology);
    if (radius <= 0 || region.empty()) return radius < 0 ? erode(region, -radius) : region;
    return resolve(dilation_contours(region, radius));
}

PositiveRegion dilation(const Paths& region, Coord radius) {
    GeometryTimer timer(GeometryOp::kMorphology);
    return dilation_contours(region, radius);
}

namespace {

// erosion() without its timer, so that erode() counts once in the profile.
PositiveRegion erosion_contours(const Paths& region, Coord radius) {
    if (radius <= 0 || region.empty()) return {radius < 0 ? dilate(region, -radius) : region};
    if (area(region) < 0) return erosion_contours(unite(region), radius);
    Paths reversed = without_vanishing(region, radius);
    if (reversed.empty()) return {};
    ClipperLib::ReversePaths(reversed);
    PositiveRegion out{convolve_all(reversed, radius)};  // the element is centrally symmetric
    ClipperLib::ReversePaths(out.contours);
    return out;
}

}  // namespace

PositiveRegion erosion(const Paths& region, Coord radius) {
    GeometryTimer timer(GeometryOp::kMorphology);
    return erosion_contours(region, radius);
}

Paths erode(const Paths& region, Coord radius) {
    GeometryTimer timer(GeometryOp::kMorphology);
    if (radius <= 0 || region.empty()) return radius < 0 ? dilate(region, -radius) : region;
    return resolve(erosion_contours(region, radius));
}

Paths narrow_holes(const Paths& region, Coord radius) {
    Paths out;
    if (radius <= 0) return out;
    std::vector<BBox2> boxes;
    boxes.reserve(region.size());
    for (const Path& p : region) boxes.push_back(bounds(p));
    auto within = [&](size_t inner, size_t hole) {
        if (inner == hole || !contains(boxes[hole], boxes[inner])) return false;
        for (const Point& v : region[inner])  // a vertex off the hole's contour decides
            if (const int in = ClipperLib::PointInPolygon(v, region[hole]); in >= 0) return in == 1;
        return false;
    };
    for (size_t h = 0; h < region.size(); ++h) {
        if (region[h].size() < 3 || area(region[h]) >= 0) continue;
        // The hole less what of the region lies inside it (a moat round an island is narrow).
        // What lies inside is nested and normalised, so the signed areas and the lengths add up
        // to the difference's before it is made. A region's area is at most its boundary's length
        // times its inradius: a wider hole is not subtracted or eroded at all.
        Paths inside;
        for (size_t k = 0; k < region.size(); ++k)
            if (within(k, h)) inside.push_back(region[k]);
        const double net = -area(region[h]) - area(inside);
        if (net <= 0 ||
            net >= (length(Paths{region[h]}, true) + length(inside, true)) * double(radius))
            continue;
        Paths hole{Path(region[h].rbegin(), region[h].rend())};
        if (!inside.empty()) hole = subtract(hole, inside);
        if (erode(hole, radius).empty()) out.insert(out.end(), hole.begin(), hole.end());
    }
    return out;
}

Paths dilate_lines(const Paths& polylines, Coord radius) {
    GeometryTimer timer(GeometryOp::kMorphology);
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

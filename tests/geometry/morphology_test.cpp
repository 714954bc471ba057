// Property tests of the polygonal-disk morphology (report Appendix A, section 5.1) on many
// shapes; n = kDiskSides.
//
// Exact answers exist only for a few shapes (squares, the n-gon itself, segments), so most
// checks are properties that hold for any region: inclusion, the semigroup law of dilation,
// duality with the complement, opening and closing. Clipper's ClipperOffset serves as an
// independent oracle: the n-gon is inscribed in its circle, so for every region
//   offset(S, r cos(pi / n)) <= S (+) Dn(r) <= offset(S, r).
// Distances are compared with a sampled Hausdorff distance between boundaries.
#include "geometry/morphology.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <iostream>
#include <limits>
#include <numbers>
#include <random>
#include <string>

#include "geometry/polygon.hpp"
#include "mesh/mesh.hpp"
#include "slice/slicer.hpp"
#include "support/models.hpp"
#include "support/shapes.hpp"
#include "support/test_rng.hpp"

using namespace carve;
using carve::test::rect;
using carve::test::rect_region;

namespace {

constexpr double kPi = std::numbers::pi;
const double kCos = std::cos(kPi / kDiskSides);  // inradius / circumradius of the element

// ---------------------------------------------------------------------------------------------
// Shapes. A small portable generator (not std distributions) so shapes are the same everywhere.

using carve::test::Rng;

Point at(double x, double y) {
    return Point(Coord(std::llround(x)), Coord(std::llround(y)));
}

Path rotated_rect(double cx, double cy, double len, double width, double angle) {
    const double c = std::cos(angle), s = std::sin(angle);
    Path p;
    for (auto [u, v] : {std::pair{-0.5, -0.5}, {0.5, -0.5}, {0.5, 0.5}, {-0.5, 0.5}})
        p.push_back(at(cx + c * u * len - s * v * width, cy + s * u * len + c * v * width));
    return p;
}

// Star-shaped polygon around (cx, cy): n vertices at jittered angles, radii in [rmin, rmax].
Path star(Rng& rng, double cx, double cy, int n, double rmin, double rmax) {
    Path p;
    for (int i = 0; i < n; ++i) {
        const double t = (i + rng.uniform(0.1, 0.9)) * 2 * kPi / n;
        const double rad = rng.uniform(rmin, rmax);
        p.push_back(at(cx + rad * std::cos(t), cy + rad * std::sin(t)));
    }
    return p;
}

Path noisy_circle(Rng& rng, double cx, double cy, double radius, int n, double noise) {
    Path p;
    for (int i = 0; i < n; ++i) {
        const double t = i * 2 * kPi / n;
        const double rad = radius + rng.uniform(-noise, noise);
        p.push_back(at(cx + rad * std::cos(t), cy + rad * std::sin(t)));
    }
    return p;
}

Path reversed(Path p) {
    std::reverse(p.begin(), p.end());
    return p;
}

// A comb: a bar with teeth, so that the outline has many reflex and convex right angles.
Paths comb(Coord tooth, Coord gap, int teeth, Coord height) {
    const Coord total = teeth * tooth + (teeth - 1) * gap;
    Paths parts = rect_region(0, 0, total, height / 3);
    for (int i = 0; i < teeth; ++i) {
        const Coord x = i * (tooth + gap);
        parts.push_back(rect_region(x, 0, x + tooth, height)[0]);
    }
    return unite(parts);
}

struct Shape {
    std::string name;
    Paths region;  // normalised: outers counter-clockwise, holes clockwise
};

std::vector<Shape> zoo() {
    std::vector<Shape> shapes;
    auto add = [&](std::string name, const Paths& region) {
        shapes.push_back({std::move(name), unite(region)});
    };
    Rng rng(20170601);
    for (int k = 0; k < 8; ++k) {
        const double big = rng.uniform(2000, 20000);
        const int n = rng.integer(5, 60);  // one draw per statement: argument order is unspecified
        add("star" + std::to_string(k), {star(rng, 0, 0, n, big * rng.uniform(0.2, 0.6), big)});
    }
    for (int k = 0; k < 4; ++k) {  // stars with star-shaped holes
        const double big = rng.uniform(6000, 20000);
        Paths r{star(rng, 0, 0, rng.integer(8, 40), 0.75 * big, big)};
        r.push_back(reversed(star(rng, 0, 0, rng.integer(4, 20), 0.1 * big, 0.45 * big)));
        add("holed_star" + std::to_string(k), r);
    }
    {  // several holes, two of them 150 um apart so that erosion merges them
        Paths r = rect_region(0, 0, 12000, 8000);
        r.push_back(reversed(rect_region(1000, 1000, 4000, 7000)[0]));
        r.push_back(reversed(rect_region(4150, 1000, 6000, 3000)[0]));
        r.push_back(reversed(star(rng, 9000, 4000, 12, 500, 1800)));
        add("many_holes", r);
    }
    add("thin_strip", rect_region(0, 0, 20000, 300));
    add("thin_strip_tilted", {rotated_rect(0, 0, 15000, 350, 0.3)});
    add("thin_ring",
        {noisy_circle(rng, 0, 0, 5000, 200, 0), reversed(noisy_circle(rng, 0, 0, 4700, 200, 0))});
    add("comb", comb(1100, 300, 6, 6600));
    add("L_shape", {{{0, 0}, {8000, 0}, {8000, 2000}, {2000, 2000}, {2000, 9000}, {0, 9000}}});
    add("noisy_circle", {noisy_circle(rng, 0, 0, 10000, 400, 60)});
    {  // far apart components plus two that a dilation merges
        Paths r{star(rng, 0, 0, 20, 1500, 3000), star(rng, 12000, 0, 20, 1500, 3000)};
        r.push_back(rect_region(0, 5000, 4000, 6000)[0]);
        r.push_back(rect_region(0, 6100, 4000, 7000)[0]);
        add("components", r);
    }
    add("tiny_triangle", {{{0, 0}, {6, 0}, {2, 5}}});
    add("tiny_square", rect_region(0, 0, 3, 3));
    add("small_disk", {noisy_circle(rng, 0, 0, 120, 40, 0)});
    add("needle", {{{0, 0}, {10000, 40}, {0, 80}}});
    return shapes;
}

// ---------------------------------------------------------------------------------------------
// Measures.

Paths reference_offset(const Paths& region, double delta) {
    ClipperLib::ClipperOffset off;
    off.ArcTolerance = 0.25;
    off.AddPaths(region, ClipperLib::jtRound, ClipperLib::etClosedPolygon);
    Paths out;
    off.Execute(out, delta);
    return out;
}

double perimeter(const Paths& region) {
    return length(region, true);
}

// Area of a \ b, the measure of "a is not inside b".
double excess(const Paths& a, const Paths& b) {
    return std::abs(area(subtract(a, b)));
}

// a is inside b grown by eps (an independent offset), up to a sliver of rounding.
::testing::AssertionResult inside(const Paths& a, const Paths& b, double eps) {
    const double out = excess(a, eps > 0 ? reference_offset(b, eps) : b);
    const double tolerance = 1.0 + 0.5 * perimeter(a);  // half a unit along the boundary
    if (out <= tolerance) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure()
           << "area outside = " << out << " um^2 (tolerance " << tolerance << ")";
}

double segment_distance(double px, double py, const Point& a, const Point& b) {
    const double dx = double(b.X - a.X), dy = double(b.Y - a.Y);
    const double len2 = dx * dx + dy * dy;
    double t = len2 > 0 ? ((px - a.X) * dx + (py - a.Y) * dy) / len2 : 0;
    t = std::clamp(t, 0.0, 1.0);
    return std::hypot(px - (a.X + t * dx), py - (a.Y + t * dy));
}

// Nearest-segment queries on a region's boundary through a uniform grid of buckets.
class BoundaryIndex {
  public:
    explicit BoundaryIndex(const Paths& region) {
        const BBox2 b = bounds(region);
        x0_ = double(b.min_x);
        y0_ = double(b.min_y);
        size_t segments = 0;
        for (const Path& p : region) segments += p.size();
        const double w = double(b.max_x - b.min_x) + 1, h = double(b.max_y - b.min_y) + 1;
        cell_ = std::max(1.0, std::sqrt(w * h / double(std::max<size_t>(segments, 1))));
        nx_ = int(w / cell_) + 1;
        ny_ = int(h / cell_) + 1;
        buckets_.resize(size_t(nx_) * ny_);
        for (const Path& p : region)
            for (size_t i = 0; i < p.size(); ++i) {
                const Point& a = p[i];
                const Point& c = p[(i + 1) % p.size()];
                segs_.push_back({a, c});
                const int cx0 = cx(std::min(a.X, c.X)), cx1 = cx(std::max(a.X, c.X));
                const int cy0 = cy(std::min(a.Y, c.Y)), cy1 = cy(std::max(a.Y, c.Y));
                for (int gx = cx0; gx <= cx1; ++gx)
                    for (int gy = cy0; gy <= cy1; ++gy)
                        buckets_[size_t(gy) * nx_ + gx].push_back(segs_.size() - 1);
            }
    }

    double distance(double px, double py) const {
        if (segs_.empty()) return std::numeric_limits<double>::infinity();
        const int gx = std::clamp(int((px - x0_) / cell_), 0, nx_ - 1);
        const int gy = std::clamp(int((py - y0_) / cell_), 0, ny_ - 1);
        double best = std::numeric_limits<double>::infinity();
        for (int ring = 0; ring <= std::max(nx_, ny_); ++ring) {
            for (int x = gx - ring; x <= gx + ring; ++x)
                for (int y = gy - ring; y <= gy + ring; ++y) {
                    if (std::max(std::abs(x - gx), std::abs(y - gy)) != ring) continue;
                    if (x < 0 || y < 0 || x >= nx_ || y >= ny_) continue;
                    for (size_t k : buckets_[size_t(y) * nx_ + x])
                        best = std::min(best,
                                        segment_distance(px, py, segs_[k].first, segs_[k].second));
                }
            // Every segment not yet seen lies `ring` cells or more away from the query.
            if (best <= ring * cell_) break;
        }
        return best;
    }

  private:
    int cx(Coord x) const { return std::clamp(int((double(x) - x0_) / cell_), 0, nx_ - 1); }
    int cy(Coord y) const { return std::clamp(int((double(y) - y0_) / cell_), 0, ny_ - 1); }
    double x0_ = 0, y0_ = 0, cell_ = 1;
    int nx_ = 1, ny_ = 1;
    std::vector<std::pair<Point, Point>> segs_;
    std::vector<std::vector<size_t>> buckets_;
};

// Largest distance from a sample of a's boundary (vertices and points every `step` um) to b's
// boundary.
double directed_hausdorff(const Paths& a, const Paths& b, double step) {
    const BoundaryIndex index(b);
    double worst = 0;
    for (const Path& p : a)
        for (size_t i = 0; i < p.size(); ++i) {
            const Point& u = p[i];
            const Point& v = p[(i + 1) % p.size()];
            const double len = std::hypot(double(v.X - u.X), double(v.Y - u.Y));
            const int samples = std::max(1, int(std::ceil(len / step)));
            for (int k = 0; k < samples; ++k) {
                const double t = double(k) / samples;
                worst =
                    std::max(worst, index.distance(u.X + t * (v.X - u.X), u.Y + t * (v.Y - u.Y)));
            }
        }
    return worst;
}

// Symmetric Hausdorff distance between the boundaries of two regions (0 if both are empty).
double hausdorff(const Paths& a, const Paths& b, double step = 25) {
    if (a.empty() && b.empty()) return 0;
    if (a.empty() || b.empty()) return std::numeric_limits<double>::infinity();
    return std::max(directed_hausdorff(a, b, step), directed_hausdorff(b, a, step));
}

size_t vertex_count(const Paths& region) {
    size_t n = 0;
    for (const Path& p : region) n += p.size();
    return n;
}

bool normalised(const Paths& region) {
    // Outers counter-clockwise and holes clockwise means the union leaves it unchanged in area
    // and every contour's orientation agrees with its nesting depth.
    for (const Paths& comp : components(region)) {
        if (area(comp.front()) <= 0) return false;
        for (size_t i = 1; i < comp.size(); ++i)
            if (area(comp[i]) >= 0) return false;
    }
    return std::abs(area(unite(region)) - area(region)) <= 1.0 + 1e-9 * std::abs(area(region));
}

const std::vector<Coord> kRadii{50, 200, 1000};

}  // namespace

// ---------------------------------------------------------------------------------------------
// Helpers of the test itself.

TEST(MorphologyHelpers, HausdorffOfShiftedSquareIsTheShift) {
    Paths a = rect_region(0, 0, 1000, 1000), b = rect_region(7, 0, 1007, 1000);
    EXPECT_NEAR(hausdorff(a, b), 7.0, 1e-9);
    EXPECT_EQ(hausdorff({}, {}), 0.0);
    EXPECT_TRUE(std::isinf(hausdorff(a, {})));
}

TEST(MorphologyHelpers, InsideDetectsAMissingPart) {
    Paths a = rect_region(0, 0, 1000, 1000);
    EXPECT_TRUE(inside(a, a, 0));
    EXPECT_FALSE(inside(rect_region(0, 0, 1000, 1100), a, 0));
    EXPECT_TRUE(inside(rect_region(0, 0, 1000, 1003), a, 5));
}

TEST(MorphologyHelpers, ZooShapesAreValid) {
    for (const Shape& s : zoo()) {
        SCOPED_TRACE(s.name);
        EXPECT_FALSE(s.region.empty());
        EXPECT_GT(area(s.region), 0);
        EXPECT_TRUE(normalised(s.region));
    }
}

// ---------------------------------------------------------------------------------------------
// The structuring element.

TEST(Morphology, DiskIsAConvexCentrallySymmetricIntegerPolygon) {
    for (Coord r : {1, 3, 10, 200, 1000, 123457}) {
        const Path d = disk(r);
        constexpr size_t n = kDiskSides;
        ASSERT_EQ(d.size(), n);
        EXPECT_GT(area(d), 0);  // counter-clockwise
        for (size_t m = 0; m < n; ++m) {
            EXPECT_EQ(d[m].X, -d[(m + n / 2) % n].X);
            EXPECT_EQ(d[m].Y, -d[(m + n / 2) % n].Y);
            const Point& a = d[m];
            const Point& b = d[(m + 1) % n];
            const Point& c = d[(m + 2) % n];
            const double cross =
                double(b.X - a.X) * double(c.Y - b.Y) - double(b.Y - a.Y) * double(c.X - b.X);
            if (r >= 100) {
                EXPECT_GT(cross, 0) << "r=" << r << " m=" << m;
            }
            EXPECT_LE(std::abs(std::hypot(double(a.X), double(a.Y)) - r), 0.71);
        }
        EXPECT_EQ(d[0], Point(r, 0));
        EXPECT_EQ(d[n / 4], Point(0, r));  // on both axes: erode() relies on it
    }
}

// ---------------------------------------------------------------------------------------------
// Analytic values.

TEST(Morphology, DilateSquareAddsBandAndRoundedCorners) {
    const Coord a = 10000, r = 1000;
    Paths d = dilate(rect_region(0, 0, a, a), r);
    double expected = double(a) * a + 4.0 * a * r + area(Paths{disk(r)});
    EXPECT_NEAR(area(d), expected, 2.0);
    EXPECT_TRUE(normalised(d));
}

TEST(Morphology, ErodeSquareShrinksBySharpInset) {
    const Coord a = 10000, r = 1000;
    Paths e = erode(rect_region(0, 0, a, a), r);
    double expected = double(a - 2 * r) * (a - 2 * r);
    EXPECT_NEAR(area(e), expected, 1.0);
    EXPECT_LE(hausdorff(e, rect_region(r, r, a - r, a - r)), 0.01);
}

TEST(Morphology, DiskDilatedByDiskIsTheBiggerDisk) {
    for (auto [a, b] : {std::pair<Coord, Coord>{200, 200}, {1000, 350}, {77, 5000}}) {
        const Paths d = dilate(Paths{disk(a)}, b);
        EXPECT_LE(hausdorff(d, Paths{disk(a + b)}), 1.5) << a << " " << b;
        EXPECT_NEAR(area(d), area(disk(a + b)), 4.0 * (a + b));
        // Rounded vertices make the two elements' edges differ slightly in direction.
        EXPECT_LE(vertex_count(clean(d, 0.5)), 48u);
    }
}

TEST(Morphology, DilatedCircleFollowsSteinerFormula) {
    // For convex K and D: area(K + D) = area(K) + 2 V(K, D) + area(D); with K a disk of radius
    // R the mixed term is R * perimeter(D).
    const double R = 8000;
    const Coord r = 500;
    Path circle;
    const int n = 4000;
    for (int i = 0; i < n; ++i)
        circle.push_back(at(R * std::cos(2 * kPi * i / n), R * std::sin(2 * kPi * i / n)));
    const Path element = disk(r);
    const double expected = area(circle) + R * length(Paths{element}, true) + area(element);
    const double got = area(dilate(Paths{circle}, r));
    EXPECT_NEAR(got, expected, 1e-4 * expected);
    // Erosion lies between the disks of radius R - r and R - r cos(pi / n).
    const double eroded = area(erode(Paths{circle}, r));
    EXPECT_GT(eroded, kPi * (R - r) * (R - r) * 0.999);
    EXPECT_LT(eroded, kPi * (R - r * kCos) * (R - r * kCos) * 1.001);
}

// Width of the element across direction (dx, dy): a segment sweeps width * length.
double element_width(Coord r, double dx, double dy) {
    const double len = std::hypot(dx, dy);
    const double nx = -dy / len, ny = dx / len;
    double lo = 1e300, hi = -1e300;
    for (const Point& q : disk(r)) {
        lo = std::min(lo, nx * q.X + ny * q.Y);
        hi = std::max(hi, nx * q.X + ny * q.Y);
    }
    return hi - lo;
}

TEST(Morphology, DilatedSegmentIsAStadium) {
    const Coord r = 200;
    const double element = area(disk(r));
    for (double angle : {0.0, 7.5, 20.0, 45.0, 91.0, 200.0}) {
        const double L = 10000;
        const double t = angle * kPi / 180;
        Path seg{{0, 0}, at(L * std::cos(t), L * std::sin(t))};
        const double len = std::hypot(double(seg[1].X), double(seg[1].Y));
        const double w = element_width(r, double(seg[1].X), double(seg[1].Y));
        const Paths d = dilate_lines(Paths{seg}, r);
        SCOPED_TRACE(angle);
        ASSERT_EQ(d.size(), 1u);
        // The convolution drops points within a unit of the line through their neighbours
        // (a side of the element in line with the segment, at 7.5 degrees), each changing the
        // area by half the chord at most: half the perimeter in all.
        const double perimeter = 2 * len + 2 * kPi * r;
        EXPECT_NEAR(area(d), w * len + element, 1e-5 * (w * len + element) + 2 + perimeter / 2);
        EXPECT_NEAR(w, 2 * r, 2 * r * (1 - kCos) + 1);
    }
}

TEST(Morphology, DilatedPointIsTheElement) {
    const Paths d = dilate_lines(Paths{Path{{500, -300}}}, 250);
    ASSERT_EQ(d.size(), 1u);
    EXPECT_NEAR(area(d), area(disk(250)), 1e-9);
}

TEST(Morphology, DilatedPolylinesAgreeWithRoundOffset) {
    // An open zig-zag, a closed loop traced as an open line, and a crossing line.
    Paths lines{{{0, 0}, {3000, 2000}, {6000, 0}, {9000, 2000}, {9100, 5000}},
                {{0, 6000}, {4000, 6000}, {4000, 9000}, {0, 9000}, {0, 6000}},
                {{-1000, 7500}, {5000, 7500}}};
    const Coord r = 300;
    ClipperLib::ClipperOffset off;
    off.ArcTolerance = 0.25;
    off.AddPaths(lines, ClipperLib::jtRound, ClipperLib::etOpenRound);
    Paths outer, inner;
    off.Execute(outer, r);
    off.Execute(inner, r * kCos - 1);
    const Paths d = dilate_lines(lines, r);
    EXPECT_TRUE(inside(d, outer, 1));
    EXPECT_TRUE(inside(inner, d, 1));
    // The loop keeps its inside free: a point at its centre is not covered.
    EXPECT_FALSE(point_in_region({2000, 7000}, d));
    EXPECT_TRUE(point_in_region({2000, 7500 + r - 5}, d));
}

// ---------------------------------------------------------------------------------------------
// Properties on the zoo.

TEST(MorphologyProperties, ErodeInsideAndDilateContains) {
    for (const Shape& s : zoo())
        for (Coord a : kRadii) {
            SCOPED_TRACE(s.name + " a=" + std::to_string(a));
            const Paths e = erode(s.region, a);
            const Paths d = dilate(s.region, a);
            EXPECT_TRUE(inside(e, s.region, 0));
            EXPECT_TRUE(inside(s.region, d, 0));
            EXPECT_LE(area(e), area(s.region));
            EXPECT_GT(area(d), area(s.region));
            EXPECT_TRUE(normalised(e));
            EXPECT_TRUE(normalised(d));
        }
}

TEST(MorphologyProperties, MatchesRoundOffsetWithinTheInscribedGap) {
    for (const Shape& s : zoo())
        for (Coord a : kRadii) {
            SCOPED_TRACE(s.name + " a=" + std::to_string(a));
            const Paths d = dilate(s.region, a);
            EXPECT_TRUE(inside(d, reference_offset(s.region, a), 1.5));
            EXPECT_TRUE(inside(reference_offset(s.region, a * kCos), d, 1.5));
            const Paths e = erode(s.region, a);
            EXPECT_TRUE(inside(e, reference_offset(s.region, -a * kCos), 1.5));
            EXPECT_TRUE(inside(reference_offset(s.region, -a), e, 1.5));
        }
}

// The convolution against an independent construction of the same sum: the element swept along
// every contour, united with the region for a dilation, taken from it for an erosion. Only the
// union's rounding separates the two: the corners where translated edges cross are exact, not cut.
TEST(MorphologyProperties, EqualsClipperMinkowskiSumOfTheContours) {
    for (const Shape& s : zoo())
        for (Coord a : kRadii) {
            SCOPED_TRACE(s.name + " a=" + std::to_string(a));
            // Clipper sums the element's boundary with the contour; the element at every vertex
            // fills what that leaves inside (all of it around contours smaller than the element).
            // (The overload for several paths would also fill each contour, holes included.)
            Paths band;
            for (const Path& contour : s.region) {
                Paths piece;
                ClipperLib::MinkowskiSum(disk(a), contour, piece, true);
                for (const Point& v : contour) {
                    piece.push_back(disk(a));
                    for (Point& q : piece.back()) q.X += v.X, q.Y += v.Y;
                }
                band = unite(band, piece);
            }
            // The union of those pieces can round its crossings apart into a speck, a hole of
            // half a square unit (noisy_circle, a=200, in the 7 um of the band nearest the outer
            // boundary): rounding, no part of the sum, so the reference drops contours under one.
            std::erase_if(band, [](const Path& p) { return std::abs(area(p)) < 1.0; });
            EXPECT_LE(hausdorff(dilate(s.region, a), unite(band, s.region), 10), 1.5);
            EXPECT_LE(hausdorff(erode(s.region, a), subtract(s.region, band), 10), 1.5);
        }
}

// How far D(a) + D(b) is from D(a + b): the element's vertices are rounded to integers.
double element_mismatch(std::initializer_list<Coord> parts) {
    Coord total = 0;
    for (Coord c : parts) total += c;
    const Path whole = disk(total);
    double worst = 0;
    for (size_t m = 0; m < size_t(kDiskSides); ++m) {
        double x = -double(whole[m].X), y = -double(whole[m].Y);
        for (Coord c : parts) {
            x += double(disk(c)[m].X);
            y += double(disk(c)[m].Y);
        }
        worst = std::max(worst, std::hypot(x, y));
    }
    return worst;
}

// Sharpest corner of a region, in radians: the interior angle at convex vertices (where an
// erosion puts the intersection of two inset edges) or the exterior angle at reflex vertices
// (the same for a dilation). A support value off by e moves that point by e / sin(angle / 2).
double sharpest_corner(const Paths& region, bool convex) {
    double best = kPi;
    for (const Path& p : region) {
        const size_t n = p.size();
        for (size_t i = 0; i < n; ++i) {
            const Point& a = p[(i + n - 1) % n];
            const Point& b = p[i];
            const Point& c = p[(i + 1) % n];
            const double ux = double(a.X - b.X), uy = double(a.Y - b.Y);
            const double vx = double(c.X - b.X), vy = double(c.Y - b.Y);
            const double cross = vx * uy - vy * ux;  // > 0 at a convex vertex of a CCW outer
            const double angle = std::atan2(std::abs(cross), ux * vx + uy * vy);
            if ((cross > 0) == convex) best = std::min(best, angle);
        }
    }
    return best;
}

TEST(MorphologyProperties, DilationIsASemigroup) {
    // Measured on this zoo: at most 3.2 um for dilations (one vertex of the 16-gon rounded
    // (1, 3) off), and for erosions 3 um except at the sharpest star tips (5.8 um at a
    // 2 x 1.4 um support error amplified by a thin corner).
    for (const Shape& s : zoo())
        for (auto [a, b] : {std::pair<Coord, Coord>{200, 200}, {130, 900}, {1000, 50}}) {
            SCOPED_TRACE(s.name + " a=" + std::to_string(a) + " b=" + std::to_string(b));
            const double e = element_mismatch({a, b}) + 1.5;  // plus one rounding per union
            const double tol_d = 1.0 + e / std::sin(sharpest_corner(s.region, false) / 2);
            const double tol_e = 1.0 + e / std::sin(sharpest_corner(s.region, true) / 2);
            EXPECT_LE(hausdorff(dilate(dilate(s.region, a), b), dilate(s.region, a + b)),
                      std::min(tol_d, 8.0));
            EXPECT_LE(hausdorff(erode(erode(s.region, a), b), erode(s.region, a + b)),
                      std::min(tol_e, 8.0));
            EXPECT_LE(hausdorff(dilate(dilate(s.region, a), b), dilate(s.region, a + b)), 3.5);
        }
}

TEST(MorphologyProperties, ClosingContainsAndOpeningIsInside) {
    for (const Shape& s : zoo())
        for (Coord a : kRadii) {
            SCOPED_TRACE(s.name + " a=" + std::to_string(a));
            const Paths c = close(s.region, a);
            const Paths o = open(s.region, a);
            EXPECT_TRUE(inside(s.region, c, 3));
            EXPECT_TRUE(inside(o, s.region, 3));
            // Idempotence: opening an opened region changes nothing (up to rounding, and a unit
            // for each of the two convolutions, which drop points almost in line).
            EXPECT_LE(hausdorff(open(o, a), o), 5.0);
        }
}

TEST(MorphologyProperties, ErosionIsTheComplementOfTheDilatedComplement) {
    for (const Shape& s : zoo())
        for (Coord a : kRadii) {
            SCOPED_TRACE(s.name + " a=" + std::to_string(a));
            const BBox2 b = bounds(s.region);
            const Coord margin = 3 * a + 1000;
            const Paths box =
                rect_region(b.min_x - margin, b.min_y - margin, b.max_x + margin, b.max_y + margin);
            const Paths complement = subtract(box, s.region);
            const Paths dual = subtract(s.region, dilate(complement, a));
            EXPECT_LE(hausdorff(erode(s.region, a), dual), 2.0);
            // And the other way: dilation is the complement of the eroded complement.
            const Paths dual2 = subtract(erode(box, 2 * a), erode(complement, a));
            EXPECT_LE(hausdorff(intersect(dilate(s.region, a), erode(box, 2 * a)), dual2), 2.0);
        }
}

// ---------------------------------------------------------------------------------------------
// Topology: vanishing shapes and holes.

TEST(Morphology, ErosionThatRemovesEverythingIsEmpty) {
    EXPECT_TRUE(erode(rect_region(0, 0, 1000, 1000), 600).empty());
    EXPECT_TRUE(erode(rect_region(0, 0, 20000, 300), 200).empty());  // strip narrower than 2r
    EXPECT_TRUE(erode(rect_region(0, 0, 20000, 400), 200).empty() ||
                area(erode(rect_region(0, 0, 20000, 400), 200)) < 1.0);  // exactly 2r: degenerate
    EXPECT_TRUE(erode(Paths{disk(500)}, 501).empty());
    EXPECT_TRUE(erode(rect_region(0, 0, 3, 3), 2).empty());
    EXPECT_TRUE(open(rect_region(0, 0, 20000, 300), 200).empty());
    Rng rng(7);
    EXPECT_TRUE(erode(Paths{star(rng, 0, 0, 30, 2000, 3000)}, 3001).empty());
}

TEST(Morphology, EmptyAndZeroRadius) {
    EXPECT_TRUE(dilate({}, 100).empty());
    EXPECT_TRUE(erode({}, 100).empty());
    EXPECT_TRUE(dilate_lines({}, 100).empty());
    const Paths sq = rect_region(0, 0, 1000, 1000);
    EXPECT_EQ(area(dilate(sq, 0)), area(sq));
    EXPECT_EQ(area(erode(sq, 0)), area(sq));
    // A negative radius means the other operation.
    EXPECT_NEAR(area(dilate(sq, -100)), area(erode(sq, 100)), 1e-9);
    EXPECT_NEAR(area(erode(sq, -100)), area(dilate(sq, 100)), 1e-9);
}

TEST(Morphology, HolesGrowUnderErosionAndCloseUnderDilation) {
    const Coord h = 2000, r = 300;
    Paths s = rect_region(0, 0, 10000, 10000);
    s.push_back(reversed(rect_region(4000, 4000, 4000 + h, 4000 + h)[0]));
    const Paths e = erode(s, r);
    ASSERT_EQ(e.size(), 2u);
    const Paths holes = empty_holes(e);
    ASSERT_EQ(holes.size(), 1u);
    EXPECT_NEAR(area(holes), double(h) * h + 4.0 * h * r + area(disk(r)), 2.0);
    EXPECT_NEAR(area(e), double(10000 - 2 * r) * (10000 - 2 * r) - area(holes), 2.0);

    const Paths small = dilate(s, r);
    ASSERT_EQ(small.size(), 2u);  // the hole shrinks to a square of side h - 2r
    EXPECT_NEAR(std::abs(area(empty_holes(small))), double(h - 2 * r) * (h - 2 * r), 2.0);
    const Paths closed = dilate(s, h / 2 + 1);
    EXPECT_EQ(closed.size(), 1u);
    EXPECT_TRUE(empty_holes(closed).empty());
}

TEST(Morphology, NarrowHolesAreTheHolesThatHoldNoDisk) {
    const Coord r = 200;
    Paths s = rect_region(0, 0, 10000, 10000);
    const Path pinhole = rect(1000, 1000, 1300, 1300);     // 0.3 mm: narrow
    const Path slit = rect(3000, 1000, 3390, 6000);        // 0.39 x 5 mm: narrow
    const Path wide = rect(6000, 1000, 6410, 1410);        // holds a disk of 0.2 mm: stays
    const Path ring_outer = rect(1000, 7000, 3300, 9300);  // a 0.3 mm moat round an island
    const Path island = rect(1300, 7300, 3000, 9000);
    for (const Path& h : {pinhole, slit, wide, ring_outer}) s.push_back(reversed(h));
    s.push_back(island);
    const Paths narrow = narrow_holes(s, r);
    // The pinhole, the slit and the moat (less its island), as positive regions; the wide
    // square is not narrow.
    EXPECT_NEAR(area(narrow), 300.0 * 300 + 390.0 * 5000 + 2300.0 * 2300 - 1700.0 * 1700, 1.0);
    EXPECT_EQ(components(narrow).size(), 3u);
    EXPECT_TRUE(erode(narrow, r).empty());
    EXPECT_TRUE(intersect(narrow, s).empty());  // holes of s, not parts of it
    EXPECT_NEAR(area(unite(s, narrow)), area(without_holes(s)) - 410.0 * 410, 1.0);
    // The wide one is narrow for a larger disk; nothing is narrow for no disk or without holes.
    EXPECT_EQ(components(narrow_holes(s, 210)).size(), 4u);
    EXPECT_TRUE(narrow_holes(s, 0).empty());
    EXPECT_TRUE(narrow_holes(rect_region(0, 0, 1000, 1000), r).empty());
}

TEST(Morphology, TouchingComponentsMergeUnderDilation) {
    Paths two{rect_region(0, 0, 1000, 1000)[0], rect_region(1300, 0, 2300, 1000)[0]};
    EXPECT_EQ(components(dilate(two, 149)).size(), 2u);
    EXPECT_EQ(components(dilate(two, 151)).size(), 1u);
    // Erosion separates a dumbbell at its neck.
    Paths bell =
        unite(Paths{rect_region(0, 0, 3000, 3000)[0], rect_region(3000, 1300, 6000, 1700)[0],
                    rect_region(6000, 0, 9000, 3000)[0]});
    EXPECT_EQ(components(erode(bell, 199)).size(), 1u);
    EXPECT_EQ(components(erode(bell, 201)).size(), 2u);
}

TEST(Morphology, SmallHolesCloseUnderLargeDilation) {
    // Regression: with the report's backward walk at reflex vertices, a hole smaller than the
    // element left an inverted loop of winding -1 and the dilation kept a phantom hole.
    const Coord a = 10000;
    Paths s = rect_region(0, 0, a, a);
    s.push_back(reversed(rect_region(4000, 4000, 6000, 6000)[0]));
    for (Coord r : {1001, 1500, 3000, 8000}) {
        SCOPED_TRACE(r);
        const Paths d = dilate(s, r);
        EXPECT_EQ(d.size(), 1u);
        EXPECT_NEAR(area(d), double(a) * a + 4.0 * a * r + area(disk(r)), 4.0);
    }
    // A C-shaped ring whose slot and hole are both swallowed.
    Paths c =
        subtract(rect_region(-3000, -3000, 3000, 3000), rect_region(-1000, -1000, 1000, 1000));
    c = subtract(c, rect_region(-100, 0, 100, 4000));
    for (Coord r : {500, 1500, 2500}) {
        SCOPED_TRACE(r);
        const Paths d = dilate(c, r);
        EXPECT_TRUE(inside(d, reference_offset(c, r), 1.5));
        EXPECT_TRUE(inside(reference_offset(c, r * kCos), d, 1.5));
    }
    EXPECT_EQ(dilate(c, 1500).size(), 1u);
}

TEST(Morphology, ErosionByMoreThanTheInradiusLeavesNoPhantom) {
    // Regression: eroding a convex-ish shape by more than its inradius produced a loop of the
    // wrong orientation, i.e. a phantom region (14 mm^2 for a 3 mm star eroded by 5 mm).
    Rng rng(7);
    const Paths s = unite(Paths{star(rng, 0, 0, 30, 2000, 3000)});
    for (Coord r : {2100, 3001, 5000, 20000}) EXPECT_TRUE(erode(s, r).empty()) << r;
    EXPECT_TRUE(erode(Paths{noisy_circle(rng, 0, 0, 1000, 300, 0)}, 1500).empty());
}

TEST(Morphology, NoisyContourDilationHasNoPhantomHoles) {
    // Regression: every notch of the noise narrower than the element turned into an inverted
    // loop, i.e. a phantom hole. On the benchmark's 5000-vertex noisy circle the report's walk
    // left 13 holes after one dilation by 0.2 mm and 236 after twelve, the area lagging behind
    // (1574.7 mm^2 against 1584.0).
    Rng rng(12345);
    Paths d = unite(Paths{noisy_circle(rng, 0, 0, 20000, 5000, 80)});
    for (int i = 1; i <= 12; ++i) {
        d = dilate(d, 200);
        ASSERT_EQ(d.size(), 1u) << "after " << i << " dilations";
    }
    Paths e = unite(Paths{reversed(noisy_circle(rng, 0, 0, 5000, 2000, 80))});
    e = subtract(Paths{{{-30000, -30000}, {30000, -30000}, {30000, 30000}, {-30000, 30000}}}, e);
    for (int i = 1; i <= 12; ++i) {
        e = erode(e, 200);  // the hole grows; erosion of the noisy hole must not leave islands
        ASSERT_EQ(e.size(), 2u) << "after " << i << " erosions";
    }
}

TEST(Morphology, ClockwiseInputIsNormalised) {
    const Paths sq = rect_region(0, 0, 5000, 5000);
    const Paths cw{reversed(sq[0])};
    EXPECT_NEAR(area(dilate(cw, 200)), area(dilate(sq, 200)), 1e-6);
    EXPECT_NEAR(area(erode(cw, 200)), area(erode(sq, 200)), 1e-6);
    // Overlapping outers under non-zero fill dilate like their union.
    const Paths overlapping{rect_region(0, 0, 5000, 5000)[0], rect_region(3000, 0, 8000, 5000)[0]};
    EXPECT_LE(hausdorff(dilate(overlapping, 300), dilate(unite(overlapping), 300)), 0.01);
}

// ---------------------------------------------------------------------------------------------
// Repeated dilation: the reason for the fixed structuring element (report 5.1).

TEST(Morphology, RepeatedDilationKeepsTheVertexCountBounded) {
    Rng rng(99);
    const Paths start = unite(Paths{noisy_circle(rng, 0, 0, 10000, 500, 80)});
    const Coord r = 200;
    Paths ours = start, theirs = start;
    std::vector<size_t> counts;
    for (int i = 0; i < 50; ++i) {
        ours = dilate(ours, r);
        counts.push_back(vertex_count(ours));
        // ClipperOffset rounds every vertex again at each step, so its count grows; shown here
        // (about 7,650 vertices after 50 steps against about 370 for ours), not asserted.
        theirs = reference_offset(theirs, double(r));
    }
    const size_t once = vertex_count(dilate(start, 50 * r));
    std::cout << "vertices: start " << vertex_count(start) << ", after 1 dilation " << counts[0]
              << ", after 50 dilations by " << r << " um: " << counts.back() << " (one dilation by "
              << 50 * r << " um: " << once << "), ClipperOffset " << vertex_count(theirs) << "\n";
    RecordProperty("vertices_convolution", int(counts.back()));
    RecordProperty("vertices_clipper_offset", int(vertex_count(theirs)));
    // The noise is absorbed: no step has more vertices than the first one, and the end result
    // is about as complex as a single dilation by 50 r.
    EXPECT_EQ(*std::max_element(counts.begin(), counts.end()), counts.front());
    EXPECT_LE(counts.back(), 2 * once);
    // Shapewise the result is the start plus fifty times the integer element, which differs
    // from the element of radius 50 r by the accumulated rounding of its vertices.
    const double drift = element_mismatch(std::initializer_list<Coord>{
        r, r, r, r, r, r, r, r, r, r, r, r, r, r, r, r, r, r, r, r, r, r, r, r, r,
        r, r, r, r, r, r, r, r, r, r, r, r, r, r, r, r, r, r, r, r, r, r, r, r, r});
    std::cout << "drift of 50 x D(200) from D(10000): " << drift << " um\n";
    EXPECT_LE(hausdorff(ours, dilate(start, 50 * r)), drift + 3.0);
    EXPECT_TRUE(inside(ours, reference_offset(start, 50.0 * r), drift + 1.5));
    EXPECT_TRUE(inside(reference_offset(start, 50.0 * r * kCos), ours, drift + 1.5));
}

TEST(Morphology, RepeatedErosionAndDilationStayClose) {
    // The carving sweep dilates slice after slice; rounding must not drift beyond the element's.
    Rng rng(5);
    const Paths start = unite(Paths{star(rng, 0, 0, 40, 6000, 15000)});
    Paths d = start;
    for (int i = 0; i < 20; ++i) d = dilate(d, 100);
    for (int i = 0; i < 20; ++i) d = erode(d, 100);
    const std::initializer_list<Coord> twenty{100, 100, 100, 100, 100, 100, 100, 100, 100, 100,
                                              100, 100, 100, 100, 100, 100, 100, 100, 100, 100};
    const double drift = element_mismatch(twenty);
    const double amplify = 1 / std::sin(sharpest_corner(start, false) / 2);
    EXPECT_LE(hausdorff(d, close(start, 2000)), 2 * drift * amplify + 4.0);
    EXPECT_TRUE(inside(start, d, 3));  // still a closing: contains the start
}

// ---------------------------------------------------------------------------------------------
// Real slices: scanned organic contours with thousands of short edges, thin limbs and holes.

// One test per model, so that a model missing from the shared folder is skipped by name.
struct RealCuts {
    const char* model;
    std::vector<double> z;
};

class MorphologyRealSlices : public ::testing::TestWithParam<RealCuts> {};

TEST_P(MorphologyRealSlices, DilationAndErosionBracketTheReference) {
    CARVE_MODEL(path, GetParam().model);
    MeshReport report;
    const Mesh mesh = load_mesh(path, report);
    for (const double z : GetParam().z) {
        const Paths s = slice_at(mesh, z);
        SCOPED_TRACE(std::string(GetParam().model) + " z=" + std::to_string(z));
        ASSERT_FALSE(s.empty());
        ASSERT_TRUE(normalised(s));
        for (Coord a : {200, 600}) {
            SCOPED_TRACE(a);
            const Paths d = dilate(s, a), e = erode(s, a);
            EXPECT_TRUE(inside(e, s, 0));
            EXPECT_TRUE(inside(s, d, 0));
            EXPECT_TRUE(inside(d, reference_offset(s, a), 1.5));
            EXPECT_TRUE(inside(reference_offset(s, a * kCos), d, 1.5));
            EXPECT_TRUE(inside(e, reference_offset(s, -a * kCos), 1.5));
            EXPECT_TRUE(inside(reference_offset(s, -a), e, 1.5));
            EXPECT_LE(hausdorff(dilate(d, 200), dilate(s, a + 200)), 4.0);
            EXPECT_TRUE(inside(s, close(s, a), 3));
            EXPECT_TRUE(inside(open(s, a), s, 3));
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Models, MorphologyRealSlices,
                         ::testing::Values(RealCuts{"cat.stl", {20.1, 95.1}},
                                           RealCuts{"skull.stl", {40.1, 75.1}},
                                           RealCuts{"man.stl", {60.1}}),
                         [](const auto& info) {
                             const std::string m = info.param.model;
                             return m.substr(0, m.find('.'));
                         });

// The erosion before its union (PositiveRegion) must mean the same region to a boolean that
// reads it with the positive fill rule: the bridge stage subtracts from it directly.
TEST(MorphologyProperties, UnresolvedErosionSubtractsLikeTheErosion) {
    Rng rng(31);
    int nonempty = 0;
    for (const Shape& s : zoo())
        for (Coord a : kRadii) {
            SCOPED_TRACE(s.name + " a=" + std::to_string(a));
            const BBox2 b = bounds(s.region);
            // A cutter across the middle, so that the difference has pieces on both sides.
            const double cx = 0.5 * double(b.min_x + b.max_x), cy = 0.5 * double(b.min_y + b.max_y);
            const Paths cut{rotated_rect(cx, cy, 3.0 * double(b.max_x - b.min_x + 1000),
                                         0.2 * double(b.max_y - b.min_y + 1000),
                                         rng.uniform(0, kPi))};
            const Paths want = subtract(erode(s.region, a), cut);
            const Paths got = subtract(erosion(s.region, a), cut);
            nonempty += !want.empty();
            EXPECT_LE(hausdorff(got, want), 2.0);
            EXPECT_NEAR(area(got), area(want), 1e-4 * std::abs(area(s.region)) + 100.0);
        }
    EXPECT_GT(nonempty, 20);
}

// The sweep reads G = C ⊕ r unresolved, with the seed's region added, under the positive fill
// rule (CarvingSweep::next). That needs the convolution's winding to be positive exactly in the
// sum and never negative outside it, holes and islands included: a winding of -1 left by a
// hole's convolution would cancel the +1 of a seed laid over it.
TEST(MorphologyProperties, UnresolvedDilationReadsLikeTheDilationWithARegionAdded) {
    Rng rng(47);
    int nonempty = 0;
    for (const Shape& s : zoo())
        for (Coord a : kRadii) {
            SCOPED_TRACE(s.name + " a=" + std::to_string(a));
            const Paths region = unite(s.region);  // a cavity is normalised, as dilation() needs
            const BBox2 b = bounds(region);
            const double cx = 0.5 * double(b.min_x + b.max_x), cy = 0.5 * double(b.min_y + b.max_y);
            const double wide = double(b.max_x - b.min_x + 1000),
                         tall = double(b.max_y - b.min_y + 1000);
            // V: a band across the shape; S: a bar across the band, over the shape's holes.
            const Paths v{rotated_rect(cx, cy, 2.0 * wide, 0.4 * tall, rng.uniform(0, kPi))};
            const Paths seed{rotated_rect(cx, cy, 0.1 * wide, 2.0 * tall, rng.uniform(0, kPi))};
            const Paths g = dilate(region, a);
            PositiveRegion raw = dilation(region, a);
            // Compared by the area between them: Clipper's rounding leaves slivers under a unit
            // wide in one or the other, and the convolution drops points within a unit of their
            // neighbours' line, which moves the boundary by a unit at most (the union keeps
            // them). A winding of -1 would lose a whole piece of the seed.
            auto apart = [](const Paths& got, const Paths& want) {
                return std::abs(area(symmetric_difference(got, want))) /
                       (1e-4 * std::abs(area(want)) + length(want, true) + 100.0);
            };
            EXPECT_LE(apart(subtract_positive(v, raw), subtract(v, g)), 1.0);
            raw.contours.insert(raw.contours.end(), seed.begin(), seed.end());
            const Paths want = intersect(v, unite(g, seed));
            const Paths got = intersect_positive(v, raw);
            nonempty += !want.empty();
            EXPECT_LE(apart(got, want), 1.0);
        }
    EXPECT_GT(nonempty, 20);
}

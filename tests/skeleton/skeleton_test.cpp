// Tests of SKEL (report section 5.2): the EDF-pruned medial axis and its thickening.
//
// Pruning semantics under test (see axis_graph.hpp): a point of the axis is kept when
// EDF - R >= prune_threshold, EDF being the burn time of Liu et al.'s extended grassfire. At a
// convex corner of angle 2a the corner branch has EDF - R = t (1 - sin a) at distance t from the
// corner, so for a rectangle the four corner branches keep all but their first
// threshold / (1 - sin 45deg) = 1.366 mm (default threshold 0.4 mm): 5 polylines. Nearly flat
// vertices (noise) have a ~ 90 deg and their spokes vanish completely.
#include "skeleton/skeleton.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"
#include "mesh/mesh.hpp"
#include "skeleton/axis_graph.hpp"
#include "skeleton/skeleton_detail.hpp"
#include "slice/slicer.hpp"
#include "support/models.hpp"
#include "support/shapes.hpp"
#include "support/test_rng.hpp"

using namespace carve;
using carve::test::rect;

namespace {

constexpr double kPi = std::numbers::pi;

using carve::test::Rng;

// Splits every edge into pieces of about `step` and moves every new vertex by up to `jitter`
// units in x and y (corners stay put so the shape's extent is known).
Path subdivide(const Path& p, double step, int jitter, Rng& rng) {
    Path out;
    for (size_t i = 0; i < p.size(); ++i) {
        const Point& a = p[i];
        const Point& b = p[(i + 1) % p.size()];
        const double len = std::hypot(double(b.X - a.X), double(b.Y - a.Y));
        const int n = std::max(1, int(std::round(len / step)));
        out.push_back(a);
        for (int k = 1; k < n; ++k) {
            const double t = double(k) / n;
            // One draw per statement: the order of a call's arguments is unspecified.
            const Coord x = std::llround(a.X + t * (b.X - a.X)) + rng.integer(-jitter, jitter);
            const Coord y = std::llround(a.Y + t * (b.Y - a.Y)) + rng.integer(-jitter, jitter);
            out.emplace_back(x, y);
        }
    }
    return out;
}

Path circle(double cx, double cy, double r, int n, int jitter, Rng& rng, double phase = 0.1) {
    Path p;
    for (int i = 0; i < n; ++i) {
        const double a = phase + 2 * kPi * i / n;
        const Coord x = std::llround(cx + r * std::cos(a)) + rng.integer(-jitter, jitter);
        const Coord y = std::llround(cy + r * std::sin(a)) + rng.integer(-jitter, jitter);
        p.emplace_back(x, y);
    }
    return p;
}

Path reversed(Path p) {
    std::reverse(p.begin(), p.end());
    return p;
}

double dist(const Point& a, const Point& b) {
    return std::hypot(double(a.X - b.X), double(a.Y - b.Y));
}

double polyline_length(const Path& p) {
    double l = 0;
    for (size_t i = 1; i < p.size(); ++i) l += dist(p[i - 1], p[i]);
    return l;
}

double segment_distance(const Point& p, const Point& a, const Point& b) {
    const double dx = double(b.X - a.X), dy = double(b.Y - a.Y);
    const double l2 = dx * dx + dy * dy;
    double t = l2 > 0 ? (double(p.X - a.X) * dx + double(p.Y - a.Y) * dy) / l2 : 0;
    t = std::clamp(t, 0.0, 1.0);
    return std::hypot(double(p.X) - (a.X + t * dx), double(p.Y) - (a.Y + t * dy));
}

double boundary_distance(const Point& p, const Paths& region) {
    double d = 1e300;
    for (const Path& c : region)
        for (size_t i = 0; i < c.size(); ++i)
            d = std::min(d, segment_distance(p, c[i], c[(i + 1) % c.size()]));
    return d;
}

// Every vertex of the axis lies in the region, at least `margin` away from its boundary. Where
// the region pinches to a neck narrower than the contour simplification (max_arc_error) the
// axis may cross the neck up to `slack` outside.
void expect_inside(const Paths& axis, const Paths& region, double margin, double slack = 0) {
    for (const Path& line : axis)
        for (const Point& p : line) {
            if (slack > 0 && !point_in_region(p, region)) {
                ASSERT_LE(boundary_distance(p, region), slack) << p.X << "," << p.Y;
                continue;
            }
            ASSERT_TRUE(point_in_region(p, region)) << p.X << "," << p.Y;
            ASSERT_GE(boundary_distance(p, region), margin) << p.X << "," << p.Y;
        }
}

// Ends of polylines that are not shared with another polyline (the axis' free ends).
std::vector<Point> free_ends(const Paths& axis) {
    std::map<std::pair<Coord, Coord>, int> count;
    for (const Path& line : axis) {
        if (line.size() < 2 || line.front() == line.back()) continue;
        ++count[{line.front().X, line.front().Y}];
        ++count[{line.back().X, line.back().Y}];
    }
    std::vector<Point> ends;
    for (const auto& [k, n] : count)
        if (n == 1) ends.emplace_back(k.first, k.second);
    return ends;
}

double total_length(const Paths& axis) {
    double l = 0;
    for (const Path& p : axis) l += polyline_length(p);
    return l;
}

SkeletonOptions defaults() {
    return SkeletonOptions{};
}

// ---------------------------------------------------------------------------------------------
// The extended grassfire on hand-made graphs.

TEST(Burn, JunctionTakesTheEarliestBranchesAndBurnsIntoTheLast) {
    // A star: leaves at distance 1, 2 and 10 from the junction, all with R = 0.
    skel::AxisGraph g;
    const int j = g.add_node(0, 0, 0.5);
    const int a = g.add_node(1, 0, 0);
    const int b = g.add_node(0, 2, 0);
    const int c = g.add_node(-10, 0, 0);
    skel::AxisSite site;
    g.add_edge(a, j, site);
    g.add_edge(j, b, site);
    g.add_edge(c, j, site);
    skel::Burn st;
    skel::burn(g, st);
    EXPECT_DOUBLE_EQ(st.edf[a], 0);
    EXPECT_DOUBLE_EQ(st.edf[b], 0);
    EXPECT_DOUBLE_EQ(st.edf[c], 0);
    EXPECT_DOUBLE_EQ(st.edf[j], 2);  // the second of the arrivals 1, 2 (10 never arrives)
    // The long branch burns from both ends and the fires meet 4 from the junction at time 6.
    EXPECT_DOUBLE_EQ(st.from_b[2], 2);
    EXPECT_DOUBLE_EQ(st.from_a[2], 0);
    EXPECT_DOUBLE_EQ(skel::edf_along(st, g, 2, 6), 6);
    EXPECT_DOUBLE_EQ(skel::edf_along(st, g, 2, 10), 2);
}

TEST(Burn, LeafStartsAtItsRadius) {
    skel::AxisGraph g;
    const int a = g.add_node(0, 0, 3);
    const int b = g.add_node(4, 0, 1);
    g.add_edge(a, b, skel::AxisSite{});
    skel::Burn st;
    skel::burn(g, st);
    EXPECT_DOUBLE_EQ(st.edf[a], 3);
    EXPECT_DOUBLE_EQ(st.edf[b], 1);
    EXPECT_DOUBLE_EQ(skel::edf_along(st, g, 0, 1), 4);  // fires from both ends meet at s = 1
}

TEST(Burn, CyclesNeverBurn) {
    // A triangle with a pendant branch and a tail hanging off the pendant.
    skel::AxisGraph g;
    const int p = g.add_node(0, 0, 1), q = g.add_node(10, 0, 1), r = g.add_node(5, 8, 1);
    const int leaf = g.add_node(-5, 0, 0);
    skel::AxisSite site;
    g.add_edge(p, q, site);
    g.add_edge(q, r, site);
    g.add_edge(r, p, site);
    g.add_edge(leaf, p, site);
    skel::Burn st;
    skel::burn(g, st);
    EXPECT_DOUBLE_EQ(st.edf[leaf], 0);
    EXPECT_TRUE(std::isinf(st.edf[p]));
    EXPECT_TRUE(std::isinf(st.edf[q]));
    EXPECT_TRUE(std::isinf(skel::edf_along(st, g, 0, 5)));
    EXPECT_DOUBLE_EQ(skel::edf_along(st, g, 3, 5), 5);  // the pendant burns from its leaf
}

TEST(Prune, CutsWhereEdfMinusRCrossesTheThreshold) {
    // One edge from a leaf (R = 0) to a node at R = 0: EDF - R = s on the way, with the site a
    // far point so R stays ~ 0... use a segment site along the edge instead: R = 0 everywhere.
    skel::AxisGraph g;
    const int a = g.add_node(0, 0, 0), b = g.add_node(100, 0, 0), c = g.add_node(300, 0, 0);
    skel::AxisSite on_axis{0, 0, 300, 0, false};
    g.add_edge(a, b, on_axis);
    g.add_edge(b, c, on_axis);
    skel::Burn st;
    skel::burn(g, st);
    std::vector<skel::Polyline> out;
    skel::prune(g, st, 40, out);  // EDF = min(s, 300 - s): kept for s in [40, 260]
    ASSERT_EQ(out.size(), 1u);
    ASSERT_EQ(out[0].size(), 3u);
    const double x0 = std::min(out[0].front().x, out[0].back().x);
    const double x1 = std::max(out[0].front().x, out[0].back().x);
    EXPECT_NEAR(x0, 40, 1e-3);
    EXPECT_NEAR(x1, 260, 1e-3);
    out.clear();
    skel::prune(g, st, 200, out);  // nothing passes: the last burnt point (s = 150) stays
    ASSERT_EQ(out.size(), 1u);
    ASSERT_EQ(out[0].size(), 1u);
    EXPECT_NEAR(out[0][0].x, 150, 1e-9);
}

// ---------------------------------------------------------------------------------------------
// Medial axes of known shapes.

// The rectangle [0, 20] x [0, 10] mm: central segment (5,5)-(15,5) and four corner branches
// keeping their part beyond 1.366 mm from the corner (length 5 sqrt 2 - 1.366 = 5.705 mm).
void check_rectangle(const Paths& axis, double tol) {
    ASSERT_EQ(axis.size(), 5u);
    const double t = 400.0 / (1.0 - std::sqrt(0.5));
    int centrals = 0, branches = 0;
    for (const Path& line : axis) {
        const double l = polyline_length(line);
        if (std::abs(l - 10000) < tol) {
            ++centrals;
            const Point a = line.front().X < line.back().X ? line.front() : line.back();
            const Point b = line.front().X < line.back().X ? line.back() : line.front();
            EXPECT_NEAR(double(a.X), 5000, tol);
            EXPECT_NEAR(double(a.Y), 5000, tol);
            EXPECT_NEAR(double(b.X), 15000, tol);
            EXPECT_NEAR(double(b.Y), 5000, tol);
        } else {
            ++branches;
            EXPECT_NEAR(l, 5000 * std::sqrt(2.0) - t, tol) << "branch length";
        }
    }
    EXPECT_EQ(centrals, 1);
    EXPECT_EQ(branches, 4);
}

TEST(MedialAxis, Rectangle) {
    const Paths region{rect(0, 0, 20000, 10000)};
    const Paths axis = medial_axis(region, defaults());
    check_rectangle(axis, 3);
    expect_inside(axis, region, 300);
    EXPECT_EQ(skel::last_stats().retries, 0);
}

TEST(MedialAxis, RectangleWithJitterKeepsItsTopology) {
    for (uint64_t seed = 1; seed <= 10; ++seed) {
        Rng rng(seed);
        const Paths region{subdivide(rect(0, 0, 20000, 10000), 250, 1, rng)};
        ASSERT_GT(region[0].size(), 100u);
        const Paths axis = medial_axis(region, defaults());
        SCOPED_TRACE(seed);
        check_rectangle(axis, 30);
        expect_inside(axis, region, 300);
    }
}

TEST(MedialAxis, RectangleInRotatedFramesIsTheSame) {
    Rng rng(7);
    const Paths region{subdivide(rect(0, 0, 20000, 10000), 500, 1, rng)};
    for (int frame = 0; frame < skel::frame_count(); ++frame) {
        SCOPED_TRACE(frame);
        const Paths axis = skel::medial_axis(region, defaults(), {frame});
        check_rectangle(axis, 30);
    }
}

TEST(MedialAxis, JitteredCircleGivesAPointNearTheCentre) {
    for (uint64_t seed = 1; seed <= 10; ++seed) {
        Rng rng(seed);
        const Paths region{circle(0, 0, 10000, 720, 1, rng)};
        const Paths axis = medial_axis(region, defaults());
        SCOPED_TRACE(seed);
        ASSERT_GE(axis.size(), 1u);
        EXPECT_LE(axis.size(), 2u);
        EXPECT_LT(total_length(axis), 1000);
        for (const Path& line : axis)
            for (const Point& p : line) EXPECT_LT(dist(p, Point(0, 0)), 500);
    }
}

TEST(MedialAxis, AnnulusGivesOneClosedLoop) {
    Rng rng(3);
    const Paths region{circle(0, 0, 10000, 360, 1, rng), reversed(circle(0, 0, 5000, 180, 1, rng))};
    const Paths axis = medial_axis(region, defaults());
    ASSERT_EQ(axis.size(), 1u);
    const Path& loop = axis[0];
    EXPECT_EQ(loop.front(), loop.back());
    EXPECT_GT(loop.size(), 20u);
    for (const Point& p : loop) EXPECT_NEAR(dist(p, Point(0, 0)), 7500, 30);
    EXPECT_NEAR(polyline_length(loop), 2 * kPi * 7500, 200);
}

// The L [0,20]x[0,5] u [0,5]x[0,20] mm: arms along y = 2.5 and x = 2.5 meeting at the
// junction (2.929, 2.929) equidistant from both outer sides and the reflex corner (5, 5).
Paths l_shape() {
    return {{Point(0, 0), Point(20000, 0), Point(20000, 5000), Point(5000, 5000),
             Point(5000, 20000), Point(0, 20000)}};
}

TEST(MedialAxis, LShapeHasTwoArms) {
    // The outer corner's branch has EDF - R = t (1 - sin 45deg) at distance t from the corner,
    // 1.213 mm where it meets the arms (t = 2.929 sqrt 2 mm); the branches at the arm ends peak
    // at 5 sqrt 2 / 2 - 2.5 = 1.036 mm. Above both, only the arms remain: one polyline from arm
    // end to arm end.
    SkeletonOptions opt;
    opt.prune_threshold = 1300;
    const Paths region = l_shape();
    const Paths axis = medial_axis(region, opt);
    ASSERT_EQ(axis.size(), 1u);
    const Path& line = axis[0];
    const Point a = line.front().X > line.back().X ? line.front() : line.back();
    const Point b = line.front().X > line.back().X ? line.back() : line.front();
    // An arm ends where EDF - R = 1.3 mm: 0.264 mm beyond the end junction at 17.5 mm.
    const double end = 17500 - (1300 - (2500 * std::sqrt(2.0) - 2500));
    EXPECT_NEAR(double(a.X), end, 2);
    EXPECT_NEAR(double(a.Y), 2500, 2);
    EXPECT_NEAR(double(b.X), 2500, 2);
    EXPECT_NEAR(double(b.Y), end, 2);
    // It passes through the junction, and the arms run along the legs' centre lines.
    double best = 1e9;
    const double jx = 5000 * std::sqrt(2.0) / (1 + std::sqrt(2.0));
    for (const Point& p : line)
        best = std::min(best, dist(p, Point(std::llround(jx), std::llround(jx))));
    EXPECT_LT(best, 3);
    for (const Point& p : line) {
        if (p.X > 5500) {
            EXPECT_NEAR(double(p.Y), 2500, 2);
        }
        if (p.Y > 5500) {
            EXPECT_NEAR(double(p.X), 2500, 2);
        }
    }
    expect_inside(axis, region, 2400);
}

TEST(MedialAxis, LShapeWithDefaultThresholdKeepsCornerBranches) {
    // Arms (2), the two corner branches at each arm end (4) and the outer corner's branch (1).
    const Paths region = l_shape();
    const Paths axis = medial_axis(region, defaults());
    EXPECT_EQ(axis.size(), 7u);
    EXPECT_EQ(free_ends(axis).size(), 5u);
    expect_inside(axis, region, 300);
}

TEST(MedialAxis, ThinStripKeepsItsAxis) {
    // 0.3 mm wide, thinner than the nozzle: the axis stays (trimmed at the ends).
    const Paths region{rect(0, 0, 10000, 300)};
    const Paths axis = medial_axis(region, defaults());
    ASSERT_EQ(axis.size(), 1u);
    EXPECT_GT(polyline_length(axis[0]), 9000);
    for (const Point& p : axis[0]) EXPECT_NEAR(double(p.Y), 150, 1);
}

TEST(MedialAxis, ComponentsAndHolesEachGetTheirAxis) {
    Rng rng(11);
    Paths region;
    region.push_back(circle(0, 0, 3000, 200, 1, rng));      // a disk: a point
    region.push_back(rect(10000, 0, 30000, 4000));          // a bar: its axis
    region.push_back(circle(50000, 0, 8000, 300, 1, rng));  // a disk with a hole: a loop
    region.push_back(reversed(circle(50000, 0, 3000, 100, 1, rng)));
    const Paths axis = medial_axis(region, defaults());
    EXPECT_EQ(skel::last_stats().components, 3);
    int points = 0, loops = 0, open = 0;
    for (const Path& line : axis) {
        if (line.size() == 1 || polyline_length(line) < 500)
            ++points;
        else if (line.front() == line.back())
            ++loops;
        else
            ++open;
    }
    EXPECT_EQ(points, 1);
    EXPECT_EQ(loops, 1);
    EXPECT_EQ(open, 5);  // the bar: central segment and four corner branches
    expect_inside(axis, region, 300);
}

// The carving sweep builds the axes of a slice's components ahead and asks later for the
// components its cavity left open: a component equal to one kept in the memo takes the axis
// kept there, the others are built, and the result is what medial_axis() gives alone.
TEST(MedialAxis, MemoLendsTheAxesOfEqualComponents) {
    Rng rng(11);
    const Path disk = circle(0, 0, 3000, 200, 1, rng);
    const Path bar = rect(10000, 0, 30000, 4000);
    const Path ring = circle(50000, 0, 8000, 300, 1, rng);
    const Path ring_hole = reversed(circle(50000, 0, 3000, 100, 1, rng));
    skel::AxisMemo memo;
    const Paths all =
        skel::medial_axis(Paths{disk, bar, ring, ring_hole}, defaults(), nullptr, &memo);
    ASSERT_EQ(memo.components.size(), 3u);
    ASSERT_EQ(memo.axes.size(), 3u);
    Paths joined;
    for (const Paths& axis : memo.axes) joined.insert(joined.end(), axis.begin(), axis.end());
    EXPECT_EQ(joined, all);
    EXPECT_EQ(all, medial_axis(Paths{disk, bar, ring, ring_hole}, defaults()));

    const Paths some{bar, ring, ring_hole};
    const Paths alone = medial_axis(some, defaults());
    const skel::SkeletonStats stats = skel::last_stats();
    EXPECT_EQ(skel::medial_axis(some, defaults(), &memo), alone);
    EXPECT_EQ(skel::last_stats().components, stats.components);
    EXPECT_EQ(skel::last_stats().nodes, stats.nodes);
    EXPECT_EQ(skel::last_stats().edges, stats.edges);

    // What the memo holds is taken as it is: a marked axis shows that it was not rebuilt.
    for (size_t i = 0; i < memo.components.size(); ++i)
        if (const BBox2 b = bounds(memo.components[i]); b.min_x > 9000 && b.max_x < 31000)
            memo.axes[i] = Paths{Path{Point(7, 7)}};
    const Paths lent = skel::medial_axis(some, defaults(), &memo);
    EXPECT_EQ(std::count(lent.begin(), lent.end(), Path{Point(7, 7)}), 1);
    // A component the memo does not hold is built.
    const Path other = rect(10000, 20000, 30000, 24000);
    EXPECT_EQ(skel::medial_axis(Paths{other}, defaults(), &memo),
              medial_axis(Paths{other}, defaults()));
}

TEST(MedialAxis, TinyComponentStillGetsASeed) {
    const Paths region{rect(0, 0, 300, 200)};
    const Paths axis = medial_axis(region, defaults());
    ASSERT_EQ(axis.size(), 1u);
    for (const Point& p : axis[0]) EXPECT_TRUE(point_in_region(p, region));
}

// ---------------------------------------------------------------------------------------------
// Degenerate inputs never crash and give an axis inside the region.

TEST(MedialAxis, DegenerateInputs) {
    const SkeletonOptions opt = defaults();
    EXPECT_TRUE(medial_axis({}, opt).empty());
    EXPECT_TRUE(skeleton({}, opt).empty());
    EXPECT_TRUE(medial_axis({Path{}}, opt).empty());
    // A 3 um triangle, a 1 um sliver, points on a line, repeated points.
    const Paths tiny{{Point(0, 0), Point(3, 0), Point(0, 3)}};
    for (const Path& line : medial_axis(tiny, opt)) EXPECT_LE(line.size(), 2u);
    const Paths sliver{{Point(0, 0), Point(10000, 0), Point(10000, 1), Point(0, 1)}};
    (void)medial_axis(sliver, opt);
    const Paths collinear{{Point(0, 0), Point(1000, 0), Point(2000, 0), Point(3000, 0)}};
    EXPECT_TRUE(medial_axis(collinear, opt).empty());
    const Paths dup{{Point(0, 0), Point(0, 0), Point(10000, 0), Point(10000, 0), Point(10000, 5000),
                     Point(10000, 5000), Point(5000, 5000), Point(0, 5000), Point(0, 5000)}};
    const Paths axis = medial_axis(dup, opt);
    EXPECT_EQ(axis.size(), 5u);
    expect_inside(axis, dup, 300);
    // Self-touching and self-intersecting input (a bow tie), and a spike.
    const Paths bowtie{{Point(0, 0), Point(10000, 10000), Point(10000, 0), Point(0, 10000)}};
    expect_inside(medial_axis(bowtie, opt), bowtie, 100);
    const Paths spike{{Point(0, 0), Point(10000, 0), Point(10000, 5000), Point(5000, 5000),
                       Point(5000, 9000), Point(5000, 5000), Point(0, 5000)}};
    expect_inside(medial_axis(spike, opt), spike, 300);
}

TEST(MedialAxis, TwoSquaresSharingAVertex) {
    const Paths region{rect(0, 0, 10000, 10000), rect(10000, 10000, 20000, 20000)};
    const Paths axis = medial_axis(region, defaults());
    EXPECT_EQ(skel::last_stats().components, 2);
    EXPECT_EQ(axis.size(), 8u);  // an X in each square
    expect_inside(axis, region, 300);
}

TEST(MedialAxis, HoleTouchingTheOuterContour) {
    // A triangular hole whose tip touches the outer contour: contours share a vertex.
    const Paths region{rect(0, 0, 20000, 20000),
                       {Point(0, 10000), Point(8000, 14000), Point(8000, 6000)}};
    const Paths axis = medial_axis(region, defaults());
    EXPECT_EQ(skel::last_stats().abandoned, 0);
    EXPECT_FALSE(axis.empty());
    expect_inside(axis, region, 300);
    // The region is a disk topologically (the hole opens onto the outside): no loop.
    for (const Path& line : axis) EXPECT_TRUE(line.size() < 3 || line.front() != line.back());
}

// ---------------------------------------------------------------------------------------------
// Real slices, and the remainders V^j left by carving them the way the sweep does (without the
// cavity above): V^j = V^{j-1} minus (SKEL(V^{j-1}) dilated by 1.5 mm).

// Real slices come from the product's own loader and slicer.
carve::Mesh read_model(const std::string& path) {
    carve::MeshReport report;
    return carve::load_mesh(path, report);
}

Paths cut(const carve::Mesh& mesh, double z) {
    return carve::slice_at(mesh, z);
}

// One test per model, so that a model missing from the shared folder is skipped by name.
class MedialAxisRealSlices : public ::testing::TestWithParam<const char*> {};

TEST_P(MedialAxisRealSlices, AndTheirRemainders) {
    const char* model = GetParam();
    CARVE_MODEL(path, model);
    int calls = 0, retries = 0;
    {
        const carve::Mesh tris = read_model(path);
        ASSERT_FALSE(tris.triangles.empty()) << model;
        const carve::BBox3 box = carve::bounding_box(tris);
        const double lo = box.min.z, hi = box.max.z;
        for (double f : {0.23, 0.51, 0.77}) {
            Paths v = cut(tris, lo + f * (hi - lo));
            for (int j = 0; j < 6 && !v.empty(); ++j) {
                SCOPED_TRACE(std::string(model) + " at " + std::to_string(f) + " V^" +
                             std::to_string(j));
                const Paths axis = medial_axis(v, defaults());
                ++calls;
                retries += skel::last_stats().retries;
                ASSERT_EQ(skel::last_stats().abandoned, 0);
                ASSERT_GE(axis.size(), size_t(skel::last_stats().components));
                expect_inside(axis, v, 0, defaults().max_arc_error + 1.0);
                const Paths s = skeleton(v, defaults());
                for (const Path& c : s)
                    for (const Point& p : c)
                        if (!point_in_region(p, v)) {
                            ASSERT_LE(boundary_distance(p, v), 1.0);
                        }
                v = subtract(v, dilate(s, 1500));
            }
        }
    }
    std::cout << model << " real slices: " << calls << " calls, " << retries << " retries\n";
}

INSTANTIATE_TEST_SUITE_P(Models, MedialAxisRealSlices,
                         ::testing::Values("elephant.stl", "skull.stl", "man.stl", "cat.stl",
                                           "fandisk.stl"),
                         [](const auto& info) {
                             const std::string m = info.param;
                             return m.substr(0, m.find('.'));
                         });

// ---------------------------------------------------------------------------------------------
// Regression inputs.

// man.stl cut at z = 72.1 mm, one component (an outer contour and holes). The contours touch at
// vertices, whose Voronoi cells collapse to a point inside a cycle of zero-length edges; an early
// guard took that for the builder's failure and gave up on the component in every frame.
const std::vector<std::vector<std::pair<Coord, Coord>>> kManTouching = {
    {{17093, -17939}, {17287, -17933}, {17357, -17901}, {17827, -17756}, {17894, -17716},
     {18221, -17512}, {18331, -17487}, {18517, -17403}, {18605, -17369}, {18743, -17325},
     {18855, -17281}, {18969, -17237}, {19045, -17234}, {19088, -17217}, {19241, -17170},
     {19300, -17145}, {19448, -17091}, {19483, -17053}, {19618, -16935}, {19724, -16860},
     {19793, -16828}, {20152, -16531}, {20169, -16514}, {20175, -16507}, {20182, -16500},
     {20388, -16278}, {20526, -16206}, {20531, -16204}, {20591, -16172}, {20642, -16143},
     {20647, -16140}, {20670, -16119}, {20754, -16032}, {20766, -16020}, {20861, -15922},
     {20885, -15885}, {20955, -15761}, {21029, -15654}, {21107, -15520}, {21184, -15376},
     {21234, -15135}, {21241, -15108}, {21244, -15100}, {21247, -15100}, {21376, -14871},
     {21408, -14718}, {21531, -14443}, {21538, -14395}, {21612, -14240}, {21629, -14188},
     {21684, -14108}, {21706, -14053}, {21755, -13978}, {21776, -13829}, {21851, -13673},
     {21930, -13499}, {21930, -13498}, {21755, -12937}, {21492, -12658}, {21061, -12372},
     {20902, -12275}, {20694, -12065}, {20451, -11957}, {19898, -11729}, {19850, -11743},
     {19756, -11680}, {19626, -11639}, {19497, -11609}, {19371, -11626}, {19087, -11749},
     {18969, -11793}, {18904, -11837}, {18639, -12015}, {18604, -12239}, {18580, -12322},
     {18610, -12389}, {18612, -12437}, {18737, -12614}, {18810, -12820}, {19125, -13032},
     {19242, -13112}, {19305, -13083}, {19324, -13180}, {19303, -13166}, {19347, -13196},
     {19693, -13331}, {19694, -13332}, {19529, -13558}, {19501, -13608}, {19127, -13833},
     {19192, -13824}, {19416, -13747}, {19431, -13730}, {19501, -13608}, {19540, -13584},
     {19547, -13632}, {19622, -13599}, {19675, -13613}, {19671, -13692}, {19659, -13658},
     {19655, -13649}, {19534, -13707}, {19416, -13747}, {19244, -13947}, {19001, -14162},
     {18951, -14207}, {18460, -14628}, {18458, -14630}, {18444, -14636}, {17464, -15037},
     {17423, -15064}, {17045, -15194}, {16832, -15275}, {16822, -15279}, {16459, -15477},
     {16145, -15599}, {16050, -15658}, {15709, -15968}, {15598, -16212}, {15569, -16278},
     {15518, -16345}, {15536, -16582}, {15597, -16925}, {15600, -16938}, {15601, -16939},
     {15854, -17364}, {16039, -17517}, {16264, -17683}, {16473, -17801}, {16627, -17871},
     {16679, -17891}, {16845, -17925}, {16897, -17938}, {16965, -17943}, {16995, -17940},
     {17044, -17944}},
    {{19694, -13332},
     {19923, -13019},
     {20181, -12953},
     {20196, -12952},
     {20114, -13203},
     {20069, -13201},
     {20034, -13258},
     {20041, -13190},
     {19848, -13288},
     {19801, -13381}},
    {{17088, -15289}, {17064, -15265}, {17348, -15170}, {17157, -15444}},
    {{17309, -15554}, {17401, -15229}, {17525, -15529}, {17522, -15582}, {17517, -15633}},
};

// A random walk of 400 steps united with itself (seed 122 of a stress run): after the contour
// simplification, Clipper's strictly simple union left a hole running along its outer contour
// (the same segment twice, in opposite directions). Boost merged the two sites, one segment had
// no cell, and every frame was rejected. Such pairs of edges are now removed (mend_component).
const std::vector<std::vector<std::pair<Coord, Coord>>> kWalkWithWall = {
    {{-3898, -8800}, {-3443, -8426}, {-3339, -8068}, {-3383, -7664}, {-3395, -7231}, {-3452, -6727},
     {-3388, -6262}, {-3240, -6279}, {-2877, -6290}, {-2709, -6320}, {-1953, -6348}, {-1732, -6375},
     {-1392, -6402}, {-1362, -5802}, {-1148, -5444}, {-1041, -5388}, {-907, -4906},  {-881, -4648},
     {-832, -4654},  {-584, -4461},  {-537, -4377},  {-510, -4385},  {-384, -4499},  {-337, -4872},
     {144, -4923},   {391, -4818},   {711, -4754},   {797, -4438},   {1144, -4293},  {1503, -3819},
     {1330, -3547},  {1035, -3068},  {884, -3009},   {859, -2963},   {261, -2941},   {260, -2897},
     {550, -2689},   {324, -2663},   {254, -2652},   {250, -2497},   {-51, -2484},   {-42, -2441},
     {59, -2041},    {52, -2019},    {556, 249},     {377, 332},     {36, 286},      {-228, -45},
     {-478, -174},   {-545, -93},    {-995, 46},     {-1006, -50},   {-1194, -87},   {-1036, -302},
     {-1051, -433},  {-946, -423},   {-1036, -302},  {-1006, -50},   {-981, -45},    {-858, -95},
     {-611, -106},   {-581, -227},   {-893, -388},   {-626, -491},   {-543, -375},   {-448, -752},
     {-241, -923},   {-196, -1296},  {-157, -1368},  {-59, -1391},   {-14, -1812},   {52, -2019},
     {-42, -2441},   {-52, -2483},   {-51, -2484},   {-78, -2607},   {-106, -2603},  {-79, -2590},
     {-52, -2483},   {-263, -2474},  {-272, -2472},  {-223, -2414},  {-43, -2100},   {-70, -1527},
     {-157, -1368},  {-282, -1338},  {-708, -1414},  {-875, -1869},  {-816, -2341},  {-803, -2411},
     {-1114, -2387}, {-1335, -2378}, {-1438, -2100}, {-1630, -2036}, {-2031, -1990}, {-2426, -1986},
     {-2657, -2259}, {-2700, -2210}, {-2987, -2176}, {-3144, -2183}, {-3357, -2191}, {-3498, -2481},
     {-3599, -2469}, {-3804, -2362}, {-4031, -2631}, {-3908, -3153}, {-3601, -3157}, {-3517, -3166},
     {-3473, -3245}, {-3803, -3246}, {-4389, -3254}, {-4601, -3256}, {-4659, -3199}, {-5057, -3188},
     {-5262, -3260}, {-5506, -3261}, {-5519, -3451}, {-5769, -3810}, {-5580, -3949}, {-5610, -4143},
     {-5584, -4403}, {-5648, -4405}, {-5824, -4829}, {-6261, -4977}, {-6297, -5130}, {-6408, -5612},
     {-6274, -6318}, {-6169, -6466}, {-5858, -6579}, {-5835, -6749}, {-5494, -6930}, {-5363, -6972},
     {-5362, -6978}, {-5273, -7591}, {-5208, -8126}, {-5161, -8651}, {-4903, -8674}, {-4752, -8708},
     {-4626, -8780}, {-4341, -8949}},
    {{-436, -2838}, {-338, -2716}, {-280, -2688}, {-400, -2841}},
};

Paths from_pairs(const std::vector<std::vector<std::pair<Coord, Coord>>>& contours) {
    Paths region;
    for (const auto& c : contours) {
        Path p;
        for (const auto& [x, y] : c) p.emplace_back(x, y);
        region.push_back(p);
    }
    return region;
}

TEST(MedialAxis, ZeroWidthWallLeftByClipper) {
    const Paths region = from_pairs(kWalkWithWall);
    const Paths axis = medial_axis(region, defaults());
    EXPECT_EQ(skel::last_stats().rejections.size(), 0u);
    EXPECT_EQ(skel::last_stats().abandoned, 0);
    EXPECT_GE(axis.size(), size_t(skel::last_stats().components));
    expect_inside(axis, region, 0, defaults().max_arc_error + 1.0);
}

// Random walks united with themselves (seeds 1221 and 715 of a stress run). Clipper's strictly
// simple output had a vertex a fraction of a unit across another contour's edge (and in 715 a
// one-unit sliver): the segments crossed, and Boost gave a ray inside the region or vertices off
// the bisectors in every rotated frame. The component is now mended (split where the segments
// meet, spikes dropped).
const std::vector<std::vector<std::pair<Coord, Coord>>> kWalkCrossing = {
    {{-4859, -7764}, {-4542, -7631}, {-4158, -7617}, {-3831, -7263}, {-3808, -6947}, {-3787, -6675},
     {-3936, -6165}, {-3860, -5976}, {-3640, -5553}, {-3354, -5225}, {-3174, -5100}, {-3437, -4483},
     {-3447, -4461}, {-3438, -4452}, {-3449, -4419}, {-3116, -3966}, {-3165, -3708}, {-3233, -3478},
     {-3340, -2941}, {-3351, -2864}, {-3650, -2750}, {-3654, -2677}, {-3719, -2673}, {-3792, -2471},
     {-3988, -2365}, {-4043, -2355}, {-4056, -2078}, {-3967, -1972}, {-3795, -1927}, {-3724, -1928},
     {-3685, -2176}, {-3654, -2677}, {-3601, -2680}, {-3377, -2692}, {-3351, -2864}, {-3152, -2941},
     {-2829, -3153}, {-2716, -2942}, {-2672, -2726}, {-2243, -2739}, {-2247, -2782}, {-3116, -3966},
     {-3112, -3986}, {-3108, -4047}, {-2746, -4263}, {-2247, -4530}, {-2047, -4582}, {-2134, -4754},
     {-2381, -5429}, {-2441, -5923}, {-2162, -6074}, {-2052, -6071}, {-2049, -6078}, {-1981, -6578},
     {-1317, -6580}, {-1309, -6216}, {-916, -5560},  {-1127, -5286}, {-1276, -4588}, {-1311, -4421},
     {-1109, -4561}, {-996, -4556},  {-990, -4622},  {-975, -4619},  {-351, -4608},  {-168, -4605},
     {-336, -4793},  {-269, -4815},  {-23, -4840},   {6, -5272},     {190, -5275},   {533, -5286},
     {746, -4806},   {537, -4696},   {512, -4676},   {484, -4593},   {583, -4593},   {1062, -4594},
     {1253, -4233},  {1384, -3976},  {1411, -3940},  {1587, -3642},  {1683, -3390},  {1517, -2882},
     {1829, -2386},  {1859, -1874},  {1554, -1805},  {1535, -1661},  {1818, -1652},  {1787, -1040},
     {1781, -1009},  {1939, -852},   {1849, -434},   {1748, -133},   {1724, 249},    {1515, 563},
     {990, 616},     {531, 219},     {572, 181},     {540, 145},     {96, 160},      {58, -341},
     {-338, -516},   {-328, -685},   {-468, -686},   {-441, -322},   {-158, 63},     {-306, 194},
     {-491, 650},    {-1136, 492},   {-962, 21},     {-588, -125},   {-414, -59},    {-430, -181},
     {-441, -322},   {-1108, -1231}, {-1274, -1403}, {-1274, -1402}, {-1341, -1254}, {-1432, -1229},
     {-1900, -1213}, {-1919, -1475}, {-2265, -1691}, {-2140, -1956}, {-2640, -1945}, {-3011, -1935},
     {-3135, -1934}, {-3724, -1928}, {-3755, -1729}, {-3346, -1400}, {-3350, -1326}, {-3108, -1108},
     {-2536, -782},  {-2183, -532},  {-1662, -280},  {-1725, -206},  {-1834, 378},   {-1866, 447},
     {-2212, 564},   {-2361, 451},   {-2631, 14},    {-2961, -347},  {-2986, -546},  {-3138, -847},
     {-3364, -1044}, {-3373, -855},  {-3632, -831},  {-4157, -1068}, {-4087, -1427}, {-3748, -1446},
     {-3791, -1500}, {-3755, -1729}, {-3782, -1751}, {-3967, -1972}, {-4060, -1996}, {-4056, -2078},
     {-4224, -2278}, {-4278, -2313}, {-4043, -2355}, {-4030, -2627}, {-4327, -2612}, {-4392, -2736},
     {-4514, -2889}, {-4604, -2886}, {-4622, -2932}, {-4659, -2927}, {-5083, -3502}, {-5037, -3594},
     {-5069, -3648}, {-5066, -3683}, {-5271, -3835}, {-5410, -4284}, {-5802, -4625}, {-5707, -5113},
     {-5033, -5125}, {-4641, -5153}, {-3997, -5166}, {-3832, -4824}, {-3553, -4561}, {-4489, -5836},
     {-5031, -5836}, {-5189, -6188}, {-4912, -6311}, {-4839, -6313}, {-5383, -7054}, {-5315, -7376},
     {-5261, -7770}},
    {{-5404, -2483}, {-5225, -2353}, {-5223, -2362}, {-4549, -2489}, {-4278, -2313},
     {-4499, -2273}, {-4828, -2239}, {-4779, -2010}, {-4898, -1647}, {-4798, -1562},
     {-4423, -1531}, {-4603, -765},  {-4894, -749},  {-5174, -1218}, {-5288, -762},
     {-5300, -759},  {-5318, -545},  {-5434, -82},   {-6152, -67},   {-6253, 30},
     {-6754, -231},  {-7074, -507},  {-7485, -700},  {-7453, -1450}, {-6807, -1567},
     {-6062, -1664}, {-6018, -1673}, {-5995, -1862}, {-5760, -1973}, {-5414, -2136},
     {-5400, -2121}, {-5390, -2150}, {-5463, -2132}, {-5896, -2031}, {-6073, -1986},
     {-6802, -1920}, {-7115, -2064}, {-7100, -2338}, {-7052, -2814}, {-6611, -2859},
     {-6239, -2912}, {-5716, -2954}},
    {{-1266, -1412}, {-1250, -1424}, {-1254, -1429}},
    {{-1955, -2092}, {-1919, -2111}, {-1929, -2136}},
    {{-3731, -3824},
     {-3873, -3373},
     {-3906, -3372},
     {-3883, -3343},
     {-3884, -3341},
     {-3873, -3330},
     {-3777, -3208},
     {-3872, -2664},
     {-3719, -2673},
     {-3711, -2695},
     {-3662, -2845},
     {-3630, -3081},
     {-3873, -3330},
     {-3883, -3343},
     {-3873, -3373},
     {-3695, -3378},
     {-3646, -3829},
     {-3449, -4419},
     {-3459, -4433}},
    {{-986, -4044}, {-847, -4121}, {-887, -4181}},
};
const std::vector<std::vector<std::pair<Coord, Coord>>> kWalkSliver = {
    {{5029, 2593}, {5442, 2799}, {5405, 3354}, {5291, 3413}, {5001, 3421}, {5039, 3544},
     {5475, 3635}, {5811, 4214}, {5894, 4368}, {5991, 4325}, {6440, 4203}, {6946, 4261},
     {7280, 4302}, {7647, 4520}, {7600, 4693}, {7446, 4727}, {7438, 4922}, {7358, 5102},
     {7265, 5293}, {6901, 5824}, {6510, 5822}, {6375, 5820}, {6280, 5768}, {6222, 5883},
     {5856, 6023}, {5797, 6115}, {6116, 6299}, {6065, 6649}, {5505, 6659}, {5187, 6670},
     {5061, 7152}, {5198, 7412}, {5282, 7395}, {6029, 7350}, {6291, 7807}, {6470, 7853},
     {6211, 8479}, {5695, 8490}, {5673, 8524}, {5592, 8526}, {5574, 8535}, {5565, 8527},
     {5508, 8529}, {5258, 8563}, {5067, 8352}, {5191, 8230}, {4836, 8006}, {4589, 7700},
     {4637, 7569}, {4917, 7505}, {5108, 7431}, {5117, 7429}, {5028, 7278}, {5061, 7152},
     {5038, 7109}, {4255, 7135}, {3880, 7138}, {3417, 7140}, {3347, 7169}, {3341, 7259},
     {3188, 7277}, {3114, 7301}, {2928, 7626}, {3318, 7626}, {3341, 7259}, {3562, 7232},
     {3868, 7220}, {4158, 7432}, {4268, 7456}, {4238, 8008}, {3778, 8022}, {3842, 8098},
     {3635, 8647}, {3343, 9002}, {3035, 9327}, {2881, 9329}, {2597, 8886}, {2393, 8568},
     {2645, 8052}, {2726, 7938}, {2106, 7922}, {2046, 7838}, {2364, 7623}, {2807, 7626},
     {2920, 7626}, {2796, 7838}, {2850, 7762}, {2928, 7626}, {2920, 7626}, {3003, 7483},
     {3209, 6952}, {3447, 6665}, {3402, 6610}, {3585, 6398}, {3878, 5790}, {3677, 5472},
     {3798, 4959}, {3856, 4956}, {4183, 5466}, {3895, 5756}, {3878, 5790}, {4045, 6054},
     {4255, 6708}, {4879, 6681}, {5187, 6670}, {5197, 6631}, {5244, 6340}, {5040, 6354},
     {4645, 5774}, {4488, 5226}, {4152, 5114}, {4352, 4642}, {4517, 4458}, {4566, 4258},
     {4453, 4267}, {4365, 4024}, {4095, 3846}, {4025, 3569}, {4195, 3231}, {4201, 3058},
     {4020, 3047}, {4211, 2754}, {4212, 2754}, {4221, 2482}, {4511, 2370}},
    {{780, -1018},  {639, -900},   {649, -904},   {744, -967},   {1109, -386},  {1604, -97},
     {1407, 94},    {1581, 298},   {2025, 208},   {2508, 168},   {2539, 107},   {2718, -422},
     {2977, -426},  {3010, -192},  {2790, 144},   {2508, 168},   {2228, 710},   {2144, 1352},
     {2397, 1793},  {2694, 1708},  {3061, 1676},  {3114, 1474},  {3279, 1428},  {3518, 1542},
     {3330, 1652},  {3061, 1676},  {2950, 2101},  {2670, 2399},  {2552, 2934},  {2482, 3600},
     {2304, 3897},  {2025, 4581},  {1700, 5154},  {1971, 5716},  {2290, 6140},  {2484, 6411},
     {3257, 6433},  {3402, 6610},  {3297, 6732},  {3201, 6737},  {2721, 6742},  {2484, 6411},
     {2473, 6411},  {2039, 6391},  {1341, 6380},  {818, 6368},   {730, 6563},   {1200, 6574},
     {1331, 6871},  {1146, 6883},  {836, 6856},   {665, 6706},   {730, 6563},   {447, 6557},
     {220, 7010},   {173, 7171},   {125, 7229},   {350, 7456},   {337, 7932},   {313, 8069},
     {29, 8016},    {-184, 7609},  {125, 7229},   {117, 7221},   {-250, 7180},  {-511, 7655},
     {-721, 7732},  {-977, 8294},  {-1328, 8682}, {-1430, 8696}, {-1530, 9230}, {-1593, 9195},
     {-1603, 8719}, {-1430, 8696}, {73, 701},     {-114, 574},   {61, 332},     {98, 329},
     {154, 271},    {171, 181},    {171, 180},    {172, 173},    {171, 181},    {61, 332},
     {-434, 373},   {-744, 387},   {-1231, 236},  {-1569, -117}, {-1449, -686}, {-978, -723},
     {-262, -738},  {321, -784},   {448, -830},   {535, -1048},  {726, -1128}},
    {{7654, 1323}, {7811, 1688}, {7873, 1686}, {8062, 1662}, {8158, 2009}, {8285, 2002},
     {8294, 1882}, {8439, 1910}, {8712, 1934}, {8721, 1918}, {8793, 1941}, {8867, 1948},
     {8877, 1969}, {8906, 1978}, {8906, 2027}, {9022, 2267}, {9127, 2282}, {9494, 2445},
     {9436, 2680}, {9278, 3225}, {9132, 3290}, {8907, 3287}, {8788, 3279}, {8588, 3277},
     {8551, 3031}, {8549, 3035}, {8220, 3024}, {8418, 3276}, {8562, 3277}, {8588, 3277},
     {8594, 3315}, {8691, 3546}, {8810, 3612}, {8726, 3630}, {8782, 3763}, {8818, 3909},
     {8735, 4014}, {8892, 4386}, {8916, 4879}, {8472, 4915}, {8662, 4951}, {8969, 5222},
     {8926, 5075}, {8916, 4879}, {9031, 4870}, {9313, 5033}, {9242, 5302}, {9258, 5381},
     {9182, 5642}, {9154, 5957}, {9151, 6618}, {8746, 6676}, {8589, 6605}, {8111, 6135},
     {8166, 5672}, {8226, 5654}, {8257, 5327}, {8281, 5159}, {8341, 4926}, {8472, 4915},
     {8412, 4904}, {8372, 4488}, {8257, 4691}, {8089, 5151}, {8076, 5192}, {8085, 5217},
     {8047, 5754}, {8006, 5785}, {7953, 5932}, {7810, 5623}, {7974, 5529}, {8076, 5192},
     {7902, 4686}, {7822, 4623}, {7647, 4520}, {7721, 4249}, {7651, 3977}, {7710, 3970},
     {7912, 3947}, {7918, 3932}, {7637, 3922}, {7651, 3977}, {7242, 4023}, {7199, 3915},
     {6868, 3909}, {6077, 3885}, {5880, 3487}, {6127, 3244}, {6749, 3247}, {6957, 3251},
     {6928, 3084}, {6655, 3116}, {6427, 3030}, {6729, 2477}, {6589, 2257}, {6552, 1651},
     {6918, 1083}, {7319, 1082}},
    {{9800, 3603},
     {9820, 3668},
     {10324, 3671},
     {10635, 3938},
     {10407, 4206},
     {9970, 4198},
     {9448, 4172},
     {9252, 4144},
     {8863, 4091},
     {8818, 3909},
     {8909, 3794},
     {9075, 3593}},
    {{8060, 3648}, {8006, 3728}, {8004, 3730}, {8002, 3734}, {7903, 3882}, {7972, 3806},
     {8002, 3734}, {8006, 3728}, {8136, 3624}, {8334, 3405}, {8421, 3422}, {8216, 3560},
     {8136, 3624}, {7972, 3806}, {7918, 3932}, {8326, 3946}, {8365, 3966}, {8404, 3970},
     {8423, 3697}, {8726, 3630}, {8691, 3546}, {8494, 3437}, {8421, 3422}, {8494, 3373},
     {8418, 3276}, {7847, 3274}, {7753, 3274}},
    {{517, -242},
     {881, -219},
     {830, -74},
     {1059, 324},
     {1188, 316},
     {1253, 188},
     {1398, 103},
     {1407, 94},
     {1116, -249},
     {672, -469},
     {544, -531}},
    {{383, -155},
     {313, -128},
     {266, 82},
     {263, 88},
     {231, 97},
     {171, 180},
     {156, 269},
     {174, 250},
     {263, 88},
     {384, 52},
     {383, -155},
     {514, -207},
     {517, -242},
     {382, -251}},
};

TEST(MedialAxis, CrossingLeftByClipperIsMended) {
    for (const auto* input : {&kWalkCrossing, &kWalkSliver}) {
        const Paths region = from_pairs(*input);
        const Paths axis = medial_axis(region, defaults());
        EXPECT_EQ(skel::last_stats().abandoned, 0);
        EXPECT_LE(skel::last_stats().retries, 1);
        EXPECT_GE(axis.size(), size_t(skel::last_stats().components));
        expect_inside(axis, region, 0, defaults().max_arc_error + 1.0);
    }
}

// A random walk (seed 2260 of a stress run) whose strictly simple union by Clipper had a material
// triangle, touching the outer contour at its three corners, returned clockwise as a hole
// (winding -1 inside): the axis around it was cut and every frame was rejected with axis ends
// inside the region. The plain union orients it correctly; the preparation no longer asks for
// strictly simple output.
const std::vector<std::vector<std::pair<Coord, Coord>>> kWalkTouchingTriangle = {
    {{2907, -2922}, {3338, -2956}, {3938, -3026}, {4701, -3060}, {5036, -2904}, {4936, -2628},
     {4723, -2283}, {4512, -1877}, {4341, -1588}, {4229, -1584}, {4246, -1392}, {4211, -1052},
     {4091, -905},  {3563, -809},  {3542, -805},  {3519, -312},  {3395, -121},  {3343, 104},
     {3284, 861},   {3205, 996},   {2875, 678},   {2427, 141},   {2438, -78},   {1900, -5},
     {1436, 139},   {715, 181},    {663, 221},    {4377, 1539},  {4671, 1268},  {5001, 1243},
     {5402, 1465},  {5378, 1723},  {5202, 1832},  {5234, 1843},  {4995, 1924},  {4816, 2203},
     {4595, 2376},  {4384, 2400},  {4351, 1878},  {4026, 1879},  {3433, 1902},  {2680, 1911},
     {2209, 1914},  {1773, 1851},  {1558, 1730},  {1545, 1548},  {1321, 1585},  {1735, 2178},
     {1784, 2244},  {1869, 2223},  {1923, 2430},  {2011, 2547},  {2121, 2629},  {2220, 2622},
     {2620, 2541},  {2870, 2768},  {3239, 3278},  {3532, 3754},  {3862, 3829},  {3788, 3947},
     {3576, 4376},  {4004, 4383},  {4280, 4643},  {4529, 4896},  {4604, 5161},  {4184, 5299},
     {3646, 5283},  {3051, 5276},  {2903, 5273},  {2849, 5397},  {2483, 5396},  {2261, 5395},
     {2354, 5262},  {2283, 5261},  {2237, 5201},  {2200, 5341},  {2240, 5395},  {2261, 5395},
     {2251, 5409},  {2286, 5455},  {2014, 5709},  {1969, 5882},  {1550, 5886},  {1437, 5862},
     {1050, 5254},  {789, 4959},   {401, 4303},   {237, 3753},   {175, 3748},   {144, 3758},
     {139, 3746},   {-54, 3731},   {-74, 3701},   {-332, 3534},  {-591, 3319},  {-511, 3206},
     {-295, 3079},  {-217, 2925},  {-223, 2925},  {-366, 3053},  {-773, 3095},  {-1260, 3151},
     {-1380, 2794}, {-1595, 3250}, {-1836, 3435}, {-2613, 3403}, {-2884, 2852}, {-2973, 2583},
     {-2772, 2142}, {-2439, 2041}, {-2671, 1638}, {-2921, 965},  {-2978, 779},  {-3083, 666},
     {-3022, 638},  {-3052, 540},  {-2714, 186},  {-2616, -176}, {-1864, -149}, {-1591, 252},
     {-1505, 237},  {-1475, 187},  {-1453, 186},  {-1466, -108}, {-1317, -106}, {-1350, 179},
     {-1453, 186},  {-1435, 608},  {-1430, 617},  {-1390, 533},  {-1350, 179},  {-1200, 170},
     {-923, 648},   {-845, 649},   {-747, 345},   {-712, -96},   {-1317, -106}, {-1308, -186},
     {-1034, -234}, {-686, -301},  {-534, -165},  {-383, -63},   {-379, -70},   {-291, -683},
     {-203, -911},  {157, -906},   {-225, -1525}, {64, -1706},   {78, -1708},   {449, -1726},
     {809, -1765},  {1298, -1803}, {1300, -1862}, {1350, -2387}, {1417, -2752}, {2121, -2821},
     {2233, -2839}, {2421, -3079}, {2552, -3190}, {2781, -3248}},
    {{2140, 5568}, {2251, 5409}, {2240, 5395}, {2186, 5395}},
    {{-1355, 2259}, {-1489, 2458}, {-1563, 2444}, {-1556, 2497}, {-1405, 2576}, {-1334, 2258}},
    {{557, 302},
     {549, 446},
     {543, 461},
     {633, 546},
     {1049, 892},
     {953, 1065},
     {1042, 1059},
     {1408, 1524},
     {1545, 1544},
     {1515, 1107},
     {1101, 1019},
     {1054, 585},
     {662, 222}},
    {{-697, 152},
     {-730, 353},
     {-511, 524},
     {-508, 477},
     {-429, 477},
     {-332, 223},
     {-196, 218},
     {-456, 83}},
    {{583, -188}, {563, 185}, {660, 219}, {628, 190}, {594, -249}},
    {{-251, 25}, {-214, 50}, {-218, 16}},
};

TEST(MedialAxis, TriangleTouchingAtThreeCorners) {
    const Paths region = from_pairs(kWalkTouchingTriangle);
    const Paths axis = medial_axis(region, defaults());
    EXPECT_EQ(skel::last_stats().rejections.size(), 0u);
    EXPECT_EQ(skel::last_stats().abandoned, 0);
    EXPECT_GE(axis.size(), size_t(skel::last_stats().components));
    expect_inside(axis, region, 0, defaults().max_arc_error + 1.0);
}

// The retry path: a rejected build is redone in the next (rotated) frame, and after the last
// frame the component is given up without an axis.
TEST(MedialAxis, RejectedBuildsAreRetriedThenAbandoned) {
    Rng rng(9);
    const Paths region{subdivide(rect(0, 0, 20000, 10000), 500, 1, rng),
                       rect(30000, 0, 32000, 2000)};
    const Paths axis = skel::medial_axis(region, defaults(), {0, 1});
    EXPECT_EQ(skel::last_stats().retries, 2);  // one per component
    EXPECT_EQ(skel::last_stats().abandoned, 0);
    const Paths rect_only = skel::medial_axis({region[0]}, defaults(), {0, 1});
    check_rectangle(rect_only, 30);
    const Paths none = skel::medial_axis(region, defaults(), {0, skel::frame_count()});
    EXPECT_TRUE(none.empty());
    EXPECT_EQ(skel::last_stats().abandoned, 2);
    EXPECT_EQ(skel::last_stats().retries, 2 * (skel::frame_count() - 1));
    EXPECT_TRUE(skeleton(Paths{}, defaults()).empty());
}

TEST(MedialAxis, RealSliceWithTouchingContours) {
    const Paths region = from_pairs(kManTouching);
    const Paths axis = medial_axis(region, defaults());
    EXPECT_EQ(skel::last_stats().abandoned, 0);
    EXPECT_EQ(skel::last_stats().retries, 0);
    EXPECT_FALSE(axis.empty());
    expect_inside(axis, region, 0, defaults().max_arc_error + 1.0);
}

// ---------------------------------------------------------------------------------------------
// Random regions like the carving produces: unions and differences of polygonal disks (many
// co-circular vertices), with holes and several components.

Paths random_blobs(Rng& rng, int n) {
    Paths region;
    for (int i = 0; i < n; ++i) {
        Paths d{disk(Coord(rng.uniform(500, 6000)))};
        const Coord x = Coord(rng.uniform(0, 40000)), y = Coord(rng.uniform(0, 40000));
        for (Point& p : d[0]) p.X += x, p.Y += y;
        region = (i % 4 == 3) ? subtract(region, d) : unite(region, d);
    }
    return region;
}

TEST(MedialAxis, RandomRegionsStayInside) {
    int abandoned = 0, retries = 0;
    for (uint64_t seed = 1; seed <= 60; ++seed) {
        Rng rng(seed);
        const Paths region = random_blobs(rng, 12);
        const Paths axis = medial_axis(region, defaults());
        abandoned += skel::last_stats().abandoned;
        retries += skel::last_stats().retries;
        SCOPED_TRACE(seed);
        // Every component of the region holds some of the axis.
        EXPECT_GE(axis.size(), size_t(skel::last_stats().components));
        expect_inside(axis, region, 0, defaults().max_arc_error + 1.0);
        // The thickened axis is clipped to the region (up to Clipper's rounding of the
        // intersection points).
        for (const Path& c : skeleton(region, defaults()))
            for (const Point& p : c)
                if (!point_in_region(p, region)) {
                    ASSERT_LE(boundary_distance(p, region), 1.0);
                }
    }
    EXPECT_EQ(abandoned, 0);
    std::cout << "random regions: " << retries << " retries\n";
}

TEST(Skeleton, IsTheThickenedAxisInsideTheRegion) {
    const Paths region{rect(0, 0, 20000, 10000)};
    const SkeletonOptions opt = defaults();
    const Paths s = skeleton(region, opt);
    ASSERT_FALSE(s.empty());
    EXPECT_LT(area(subtract(s, region)), 1.0);
    // About 2 * thickness wide along the axis: area ~ 0.4 mm * axis length (+ caps).
    const double axis_length = total_length(medial_axis(region, opt));
    EXPECT_NEAR(area(s), 2.0 * opt.thickness * axis_length,
                0.15 * 2.0 * opt.thickness * axis_length);
    // A circle's seed is a small disk at the centre.
    Rng rng(5);
    const Paths disk_region{circle(0, 0, 10000, 720, 1, rng)};
    const Paths seed = skeleton(disk_region, opt);
    ASSERT_EQ(seed.size(), 1u);
    EXPECT_TRUE(point_in_region(Point(0, 0), seed));
    EXPECT_LT(area(seed), kPi * 700.0 * 700.0);
}

}  // namespace

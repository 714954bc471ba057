// Toolpath stage on hand-built partitions: walls, cover lines, single and double cavity walls,
// print order and the nearest-neighbour ordering.
#include "toolpath/toolpath.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "carving/carving.hpp"
#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"
#include "support/shapes.hpp"
#include "support/test_rng.hpp"
#include "toolpath/comb.hpp"
#include "toolpath/fill.hpp"
#include "toolpath/islands.hpp"
#include "toolpath/order.hpp"
#include "toolpath/walls.hpp"

using namespace carve;
using carve::test::rect_region;

namespace {

constexpr Coord kMm = 1000;

// A 20 mm square slice centred on the origin, no covers, no shells.
LayerPartition square_layer(const Settings& st) {
    LayerPartition l;
    l.index = 5;
    l.z = 1.1;
    l.outline = rect_region(-10 * kMm, -10 * kMm, 10 * kMm, 10 * kMm);
    l.wall_region = erode(l.outline, st.nozzle_radius());
    l.shell_paths_region = l.wall_region;
    l.carvable = l.wall_region;
    l.remainder = l.carvable;
    return l;
}

// Two cavities: C^1 the left half (touching the outer wall on three sides), C^2 a block inside
// V^1 touching the outer wall on its right side.
LayerPartition two_cavities(const Settings& st) {
    LayerPartition l = square_layer(st);
    l.cavities.push_back(intersect(l.carvable, rect_region(-10 * kMm, -10 * kMm, 0, 10 * kMm)));
    l.cavities.push_back(intersect(l.carvable, rect_region(3 * kMm, -5 * kMm, 10 * kMm, 5 * kMm)));
    l.remainder = subtract(subtract(l.carvable, l.cavities[0]), l.cavities[1]);
    return l;
}

double seg_dist(const Point& p, const Point& a, const Point& b) {
    const double dx = double(b.X - a.X), dy = double(b.Y - a.Y);
    const double len2 = dx * dx + dy * dy;
    double t = len2 > 0 ? ((p.X - a.X) * dx + (p.Y - a.Y) * dy) / len2 : 0.0;
    t = std::clamp(t, 0.0, 1.0);
    return std::hypot(a.X + t * dx - p.X, a.Y + t * dy - p.Y);
}

// Distance from a point to the boundary of a region.
double boundary_dist(const Point& p, const Paths& region) {
    double best = std::numeric_limits<double>::max();
    for (const Path& c : region)
        for (size_t i = 0; i < c.size(); ++i)
            best = std::min(best, seg_dist(p, c[i], c[(i + 1) % c.size()]));
    return best;
}

// Points every `step` along a path, each with its arc length from the start.
std::vector<std::pair<Point, double>> samples(const Extrusion& e, double step) {
    std::vector<std::pair<Point, double>> out;
    Path p = e.points;
    if (e.closed) p.push_back(p.front());
    double at = 0;
    for (size_t i = 1; i < p.size(); ++i) {
        const double d = std::hypot(double(p[i].X - p[i - 1].X), double(p[i].Y - p[i - 1].Y));
        const int n = std::max(1, static_cast<int>(d / step));
        for (int k = 0; k < n; ++k) {
            const double t = double(k) / n;
            out.push_back({Point(std::llround(p[i - 1].X + t * (p[i].X - p[i - 1].X)),
                                 std::llround(p[i - 1].Y + t * (p[i].Y - p[i - 1].Y))),
                           at + t * d});
        }
        at += d;
    }
    out.push_back({p.back(), at});
    return out;
}

double path_length(const Extrusion& e) {
    return length(Paths{e.points}, e.closed);
}

std::vector<const Extrusion*> of_feature(const LayerToolpaths& t, Feature f) {
    std::vector<const Extrusion*> out;
    for (const Extrusion& e : t.extrusions)
        if (e.feature == f) out.push_back(&e);
    return out;
}

}  // namespace

TEST(Toolpath, SquareWithoutCavitiesIsOneOuterLoop) {
    Settings st;
    LayerPartition l = square_layer(st);
    LayerToolpaths t = plan_layer(l, st);
    EXPECT_EQ(t.index, 5);
    EXPECT_NEAR(t.z, 6 * st.layer_height, 1e-12);
    ASSERT_EQ(t.extrusions.size(), 1u);
    const Extrusion& e = t.extrusions[0];
    EXPECT_EQ(e.feature, Feature::OuterWall);
    EXPECT_TRUE(e.closed);
    EXPECT_NEAR(to_mm(Coord(path_length(e))), 4 * 19.6, 0.05);
    for (const Point& p : e.points) EXPECT_LT(boundary_dist(p, l.wall_region), 2.0);
}

TEST(Toolpath, ShellsAreInsetByOneLineWidth) {
    Settings st;
    st.shells = 2;
    LayerPartition l = square_layer(st);
    l.shell_paths_region = erode(l.wall_region, 2 * st.line_width());
    l.carvable = l.shell_paths_region;
    LayerToolpaths t = plan_layer(l, st);
    auto shells = of_feature(t, Feature::Shell);
    ASSERT_EQ(shells.size(), 2u);
    EXPECT_NEAR(path_length(*shells[0]) / kMm, 4 * 18.8, 0.05);
    EXPECT_NEAR(path_length(*shells[1]) / kMm, 4 * 18.0, 0.05);
}

// --ties (issue 49): straight lines at +-45 degrees across the carvable part, the grid's share
// of its area (two families of lines `spacing` apart: 2 A / spacing of length), and a smaller
// carvable part on the layer above gets lines that lie on the layer below's, so they stack.
TEST(Toolpath, TiesAreAFixedGridAtFortyFiveDegreesThatStacks) {
    Settings st;
    st.tie_spacing = 5;
    auto ties = [](const LayerToolpaths& t) { return of_feature(t, Feature::Tie); };
    LayerPartition below = square_layer(st);
    const LayerToolpaths tb = plan_layer(below, st);
    const std::vector<const Extrusion*> lower = ties(tb);
    ASSERT_FALSE(lower.empty());
    // Ties are their own feature (the stats' ties_mm3), not walls of the outer cavity.
    for (const Extrusion* e : of_feature(tb, Feature::CavityWall)) EXPECT_NE(e->cavity, 0);
    double length = 0;
    const Paths reach = dilate(below.carvable, st.nozzle_radius() + 2);
    for (const Extrusion* e : lower) {
        EXPECT_FALSE(e->closed);
        ASSERT_EQ(e->points.size(), 2u);
        const Point a = e->points[0], b = e->points[1];
        EXPECT_NEAR(std::abs(double(b.X - a.X)), std::abs(double(b.Y - a.Y)), 3.0);
        for (const Point& p : e->points) EXPECT_TRUE(point_in_region(p, reach));
        length += std::hypot(double(b.X - a.X), double(b.Y - a.Y));
    }
    const double side = to_mm(
        below.carvable.empty() ? 0 : bounds(below.carvable).max_x - bounds(below.carvable).min_x);
    EXPECT_NEAR(to_mm(Coord(length)), 2 * side * side / 5, 0.08 * 2 * side * side / 5);

    LayerPartition above = square_layer(st);
    above.index = 6;
    above.carvable = rect_region(-6 * kMm, -3 * kMm, 7 * kMm, 8 * kMm);
    above.remainder = above.carvable;
    const LayerToolpaths ta = plan_layer(above, st);
    const std::vector<const Extrusion*> upper = ties(ta);
    ASSERT_FALSE(upper.empty());
    for (const Extrusion* e : upper)
        for (const Point& p : e->points) {
            double nearest = std::numeric_limits<double>::infinity();
            for (const Extrusion* l : lower)
                nearest = std::min(nearest, seg_dist(p, l->points[0], l->points[1]));
            EXPECT_LT(nearest, 3.0);  // micrometres: on a line of the layer below
        }
    // No ties without the option.
    st.tie_spacing = 0;
    EXPECT_TRUE(ties(plan_layer(square_layer(st), st)).empty());
}

TEST(Toolpath, CoverLinesFillTheRegionAtLineSpacingAlternatingByParity) {
    Settings st;
    const double w = double(st.line_width());
    for (int index : {0, 1}) {
        LayerPartition l = square_layer(st);
        l.index = index;
        // A cover with a hole: the carvable middle is left to the cavities.
        l.carvable = rect_region(-4 * kMm, -4 * kMm, 4 * kMm, 4 * kMm);
        l.covers = subtract(l.shell_paths_region, l.carvable);
        LayerToolpaths t = plan_layer(l, st);
        auto covers = of_feature(t, Feature::Cover);
        ASSERT_FALSE(covers.empty());

        // Inside: centres keep ~w from the wall's centreline and stay out of the carvable hole
        // (the lines also keep ~w from the hole's edge).
        const Paths allowed = erode(l.wall_region, st.line_width() - 70);
        const Paths forbidden = erode(l.carvable, 10);
        double deposited = 0;
        std::vector<double> offsets;
        const double angle = (index % 2 == 0 ? 45.0 : -45.0) * std::numbers::pi / 180.0;
        const double nx = -std::sin(angle), ny = std::cos(angle);
        // The edge towards the carvable part: the square hole's boundary, closed.
        auto edge = std::find_if(covers.begin(), covers.end(), [](auto* e) { return e->closed; });
        ASSERT_NE(edge, covers.end());
        EXPECT_NEAR(path_length(**edge) / kMm, 32.0, 0.01);
        for (const Point& p : (*edge)->points) EXPECT_LT(boundary_dist(p, l.carvable), 2.0);
        deposited += path_length(**edge) * w;
        covers.erase(edge);
        for (const Extrusion* e : covers) {
            EXPECT_FALSE(e->closed);
            EXPECT_GT(e->flow, 0.9);
            EXPECT_LE(e->flow, 1.0);
            deposited += path_length(*e) * w * e->flow;
            for (const auto& [p, at] : samples(*e, 100)) {
                EXPECT_TRUE(point_in_region(p, allowed)) << p.X << "," << p.Y;
                EXPECT_FALSE(point_in_region(p, forbidden)) << p.X << "," << p.Y;
                EXPECT_GT(boundary_dist(p, l.carvable), st.line_width() - 70);
            }
            // Long segments run along the layer's direction; record their offsets.
            for (size_t i = 1; i < e->points.size(); ++i) {
                const Point& a = e->points[i - 1];
                const Point& b = e->points[i];
                const double dx = double(b.X - a.X), dy = double(b.Y - a.Y);
                const double len = std::hypot(dx, dy);
                if (len < 2 * kMm) continue;
                EXPECT_LT(std::abs(dx * nx + dy * ny) / len, 1e-3)
                    << "line not at the layer's angle";
                offsets.push_back(nx * a.X + ny * a.Y);
            }
        }
        std::sort(offsets.begin(), offsets.end());
        std::vector<double> lines;
        for (double o : offsets)
            if (lines.empty() || o - lines.back() > 20) lines.push_back(o);
        ASSERT_GT(lines.size(), 20u);
        for (size_t i = 1; i < lines.size(); ++i) {
            const double gap = lines[i] - lines[i - 1];
            // Adjacent long lines, or lines on either side of the hole.
            if (gap > 1.5 * w) continue;
            EXPECT_GE(gap, 0.9 * w);
            EXPECT_LE(gap, w + 2);
        }
        // Deposited footprint: the region of line centres (up to the hole's edge) grown by half a
        // line, within 3 %.
        const Paths centres = intersect(l.covers, erode(l.wall_region, st.line_width() - 60));
        const double expected = area(dilate(centres, st.nozzle_radius()));
        EXPECT_NEAR(deposited / expected, 1.0, 0.03);
    }
}

TEST(Toolpath, SingleFilamentWallsKeepClearOfPrintedWallsExceptExtensions) {
    Settings st;
    st.carving = CarvingScheme::Report;  // the report's 1 mm extension (4.3)
    LayerPartition l = two_cavities(st);
    LayerToolpaths t = plan_layer(l, st);
    auto walls = of_feature(t, Feature::CavityWall);
    const double t_um = double(st.restriction());
    const double ext = st.wall_extension * kMm;
    int per_cavity[3] = {0, 0, 0};
    for (const Extrusion* e : walls) {
        ASSERT_GE(e->cavity, 1);
        ASSERT_LE(e->cavity, 2);
        ++per_cavity[e->cavity];
        const double len = path_length(*e);
        EXPECT_GT(len, 2 * st.line_width());
        // Walls printed before this one: the outer wall, and C^1 for C^2.
        Paths before = l.wall_region;
        if (e->cavity == 2) before = unite(before, l.cavities[0]);
        for (const auto& [p, at] : samples(*e, 50)) {
            const bool in_extension = !e->closed && (at < ext + 20 || at > len - ext - 20);
            if (in_extension) continue;
            EXPECT_GE(boundary_dist(p, l.wall_region), t_um - 10) << p.X << "," << p.Y;
            if (e->cavity == 2) {
                EXPECT_GE(boundary_dist(p, l.cavities[0]), t_um - 10) << p.X << "," << p.Y;
            }
        }
        if (!e->closed) {
            // An open wall ends on the walls already printed: its centre within t of theirs,
            // t < w, so the two beads overlap (and an extension reaches further along them).
            EXPECT_LT(boundary_dist(e->points.front(), before), t_um + 10);
            EXPECT_LT(boundary_dist(e->points.back(), before), t_um + 10);
            EXPECT_LT(t_um, double(st.line_width()));
        }
    }
    EXPECT_EQ(per_cavity[1], 1);
    EXPECT_EQ(per_cavity[2], 1);
    // C^1's wall is the x = 0 side (19.04 mm inside W^0) plus the two extensions.
    for (const Extrusion* e : walls) {
        if (e->cavity == 1) {
            EXPECT_NEAR(path_length(*e) / kMm, 19.6 - 2 * 0.28 + 2 * st.wall_extension, 0.1);
        }
    }
}

// A hand-made layer (no V^{j-1} recorded) is planned exactly as the same layer carrying the
// levels the sweep would record: one way through the cavity walls, whichever made the layer.
TEST(Toolpath, AHandMadeLayerIsPlannedAsOneCarryingItsLevels) {
    Settings st;
    const LayerPartition bare = two_cavities(st);
    const std::vector<Paths> levels = uncarved_levels(bare);
    ASSERT_EQ(levels.size(), 3u);  // V^0, V^1, V^2
    // The levels partition: V^{j-1} = C^j + V^j, area for area.
    for (size_t j = 1; j < levels.size(); ++j)
        EXPECT_NEAR(std::abs(area(levels[j - 1])),
                    std::abs(area(intersect(levels[j - 1], bare.cavities[j - 1]))) +
                        std::abs(area(levels[j])),
                    1e3);
    LayerPartition carried = bare;
    carried.uncarved.assign(levels.begin(), levels.end() - 1);
    carried.remainder = levels.back();
    // s' under the restriction t (the default: only clusters near V^j are opened) and over it.
    for (const double opening : {st.opening_factor, st.restriction_factor + 0.5}) {
        st.opening_factor = opening;
        const auto walls_of = [&](const LayerPartition& l) {
            std::vector<Path> out;
            const LayerToolpaths t = plan_layer(l, st);
            for (const Extrusion* e : of_feature(t, Feature::CavityWall)) out.push_back(e->points);
            return out;
        };
        const auto a = walls_of(bare), b = walls_of(carried);
        EXPECT_FALSE(a.empty()) << opening;
        EXPECT_EQ(a, b) << opening;
    }
}

TEST(Toolpath, SingleFilamentInnerCavityIsAClosedLoop) {
    Settings st;
    LayerPartition l = square_layer(st);
    l.cavities.push_back(rect_region(-3 * kMm, -3 * kMm, 3 * kMm, 3 * kMm));
    LayerToolpaths t = plan_layer(l, st);
    auto walls = of_feature(t, Feature::CavityWall);
    ASSERT_EQ(walls.size(), 1u);
    EXPECT_TRUE(walls[0]->closed);
    // Opened by s': the corners are rounded, the length is just under the square's.
    EXPECT_NEAR(path_length(*walls[0]) / kMm, 24.0 - (8 - 2 * std::numbers::pi) * 0.18, 0.05);
}

TEST(Toolpath, DoubleWallsAreClosedLoopsInsetByHalfAWidth) {
    Settings st;
    st.walls = WallMode::Double;
    LayerPartition l = two_cavities(st);
    LayerToolpaths t = plan_layer(l, st);
    auto walls = of_feature(t, Feature::CavityWall);
    ASSERT_EQ(walls.size(), 2u);
    for (const Extrusion* e : walls) {
        EXPECT_TRUE(e->closed);
        const Paths& cavity = l.cavities[e->cavity - 1];
        for (const Point& p : e->points) {
            EXPECT_TRUE(point_in_region(p, cavity));
            EXPECT_NEAR(boundary_dist(p, cavity), double(st.nozzle_radius()), 60.0);
        }
    }
}

TEST(Toolpath, PrintOrderFollowsTheReport) {
    Settings st;
    st.shells = 1;
    LayerPartition l = square_layer(st);
    l.shell_paths_region = erode(l.wall_region, st.line_width());
    l.carvable = rect_region(-6 * kMm, -6 * kMm, 6 * kMm, 6 * kMm);
    l.covers = subtract(l.shell_paths_region, l.carvable);
    l.cavities.push_back(rect_region(-6 * kMm, -6 * kMm, 0, 6 * kMm));
    l.cavities.push_back(rect_region(1 * kMm, -3 * kMm, 6 * kMm, 3 * kMm));
    l.remainder.clear();  // fully carved: no solid fill after the cavity walls
    Bridge b;
    b.cavity = 2;
    b.lines = {{{2 * kMm, 0}, {5 * kMm, 0}}, {{2 * kMm, 400}, {5 * kMm, 400}}};
    LayerRecord record = l;
    record.bridged.bridges.push_back(b);
    // After the walls it stands beside, before bridges.
    record.ribs.lines = {{{-3 * kMm, 0}, {-2200, 0}}};
    LayerToolpaths t = plan_layer(record, st);
    auto rank = [](const Extrusion& e) {
        switch (e.feature) {
            case Feature::Skirt:
            case Feature::Brim:
                return -10;  // the first layer's, before the part
            case Feature::OuterWall:
                return 0;
            case Feature::Shell:
                return 1;
            case Feature::Cover:
                return 2;
            case Feature::CavityWall:
                return 10 + e.cavity;
            case Feature::Tie:
                return 400;  // after the cavities' walls they tie (none on this layer)
            case Feature::Rib:
                return 500;
            case Feature::Bridge:
                return 1000;
            case Feature::Support:
            case Feature::SupportInterface:
                return 2000;  // after the model's own paths
        }
        return -1;
    };
    std::vector<int> seen;
    for (const Extrusion& e : t.extrusions) seen.push_back(rank(e));
    EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
    for (int r : {0, 1, 2, 11, 12, 500, 1000})
        EXPECT_NE(std::find(seen.begin(), seen.end(), r), seen.end()) << "missing group " << r;
    auto bridges = of_feature(t, Feature::Bridge);
    ASSERT_EQ(bridges.size(), 2u);
    EXPECT_DOUBLE_EQ(bridges[0]->flow, st.bridge_flow);
    // Bridge lines keep their order; the second is entered from the end nearest the first's exit.
    EXPECT_EQ(bridges[0]->points.front().Y, 0);
    EXPECT_EQ(bridges[1]->points.front().X, bridges[0]->points.back().X);
}

TEST(Toolpath, FeatureNamesArePrusaSlicerWords) {
    EXPECT_EQ(feature_name(Feature::OuterWall), "External perimeter");
    EXPECT_EQ(feature_name(Feature::Shell), "Perimeter");
    EXPECT_EQ(feature_name(Feature::Rib), "Internal infill");
    EXPECT_EQ(feature_name(Feature::Cover), "Solid infill");
    EXPECT_EQ(feature_name(Feature::CavityWall), "Internal infill");
    EXPECT_EQ(feature_name(Feature::Bridge), "Bridge infill");
}

TEST(Ordering, GridNearestNeighbourMatchesBruteForce) {
    carve::test::Rng rng(7);
    const auto coord = [](carve::test::Rng& r) { return Coord(r.integer(0, 100 * kMm)); };
    const auto step = [](carve::test::Rng& r) { return Coord(r.integer(-2 * kMm, 2 * kMm)); };
    std::vector<Extrusion> paths;
    for (int i = 0; i < 3000; ++i) {
        Extrusion e;
        Point a(coord(rng), coord(rng));
        e.points = {a, Point(a.X + step(rng), a.Y + step(rng))};
        if (i % 5 == 0) {  // a few closed triangles
            e.points.push_back(Point(a.X + step(rng), a.Y + step(rng)));
            e.closed = true;
        }
        paths.push_back(e);
    }
    auto d = [](const Point& a, const Point& b) {
        return std::hypot(double(a.X - b.X), double(a.Y - b.Y));
    };
    // Brute-force greedy travel.
    double brute = 0;
    {
        std::vector<char> used(paths.size(), 0);
        Point pos(0, 0);
        for (size_t n = 0; n < paths.size(); ++n) {
            double best = 1e300;
            size_t bi = 0, bv = 0;
            for (size_t i = 0; i < paths.size(); ++i) {
                if (used[i]) continue;
                const Path& p = paths[i].points;
                for (size_t v = 0; v < p.size(); ++v) {
                    if (!paths[i].closed && v != 0 && v != p.size() - 1) continue;
                    if (d(pos, p[v]) < best) best = d(pos, p[v]), bi = i, bv = v;
                }
            }
            used[bi] = 1;
            brute += best;
            const Path& p = paths[bi].points;
            pos = paths[bi].closed ? p[bv] : (bv == 0 ? p.back() : p.front());
        }
    }
    std::vector<Extrusion> ordered = paths;
    Point pos(0, 0);
    order_nearest(ordered, pos);
    ASSERT_EQ(ordered.size(), paths.size());
    double travel = 0;
    Point at(0, 0);
    for (const Extrusion& e : ordered) {
        travel += d(at, e.points.front());
        at = e.closed ? e.points.front() : e.points.back();
    }
    EXPECT_NEAR(travel, brute, 1e-6 * brute);
    EXPECT_EQ(at, pos);
}

TEST(Walls, PieceThroughTheLoopStartIsOneCurveWithExtensions) {
    // The loop starts at (0, 0), 1 mm inside the region; a notch reaches to 0.5 mm of its
    // right side, so at depth 0.5 mm a 2 mm stretch of it (y from 4 to 6 mm) is left out.
    const Paths loop = rect_region(0, 0, 10 * kMm, 10 * kMm);
    const Paths region = subtract(rect_region(-kMm, -kMm, 11 * kMm, 11 * kMm),
                                  rect_region(9500, 4500, 12 * kMm, 5500));
    auto pieces = loops_inside_erosion(loop, region, kMm / 2, 1.0 * kMm, 800);
    ASSERT_EQ(pieces.size(), 1u);
    Extrusion e;
    e.points = pieces[0].points;
    // 40 mm minus the 2 mm gap, plus 1 mm at both ends: the extensions close the gap.
    EXPECT_TRUE(pieces[0].closed || path_length(e) > 39.9 * kMm);
    // With 0.5 mm extensions the gap stays open by 1 mm.
    pieces = loops_inside_erosion(loop, region, kMm / 2, 0.5 * kMm, 800);
    ASSERT_EQ(pieces.size(), 1u);
    e.points = pieces[0].points;
    EXPECT_NEAR(path_length(e) / kMm, 39.0, 0.01);
    EXPECT_NEAR(boundary_dist(pieces[0].points.front(), loop), 0, 2);
    EXPECT_NEAR(double(pieces[0].points.front().Y), 5.5 * kMm, 2);  // 6 mm less the extension
    // Without extensions the piece ends where the notch comes within 0.5 mm.
    pieces = loops_inside_erosion(loop, region, kMm / 2, 0, 800);
    ASSERT_EQ(pieces.size(), 1u);
    EXPECT_NEAR(double(pieces[0].points.front().Y), 6.0 * kMm, 2);
    EXPECT_NEAR(double(pieces[0].points.back().Y), 4.0 * kMm, 2);
    // A loop outside the region, however far from it, is left out; one wholly inside is
    // kept closed.
    EXPECT_TRUE(
        loops_inside_erosion(rect_region(20 * kMm, 0, 30 * kMm, 10 * kMm), region, kMm / 2, 0, 0)
            .empty());
    pieces = loops_inside_erosion(rect_region(2 * kMm, 2 * kMm, 8 * kMm, 8 * kMm), region, kMm / 2,
                                  0, 0);
    ASSERT_EQ(pieces.size(), 1u);
    EXPECT_TRUE(pieces[0].closed);
}

TEST(Walls, RestrictedPiecesFollowTheLoopsInsideTheRegion) {
    carve::test::Rng rng(11);
    const auto u = [](carve::test::Rng& r) { return r.uniform(-1, 1); };
    for (int trial = 0; trial < 20; ++trial) {
        // Blobby loops and a blobby region.
        auto blob = [&](double cx, double cy, double r) {
            Path p;
            const int n = 60;
            const double a1 = u(rng), a2 = u(rng), ph = 3 * u(rng);
            for (int i = 0; i < n; ++i) {
                const double t = 2 * std::numbers::pi * i / n;
                const double rr =
                    r * (1 + 0.25 * a1 * std::sin(3 * t + ph) + 0.15 * a2 * std::cos(5 * t));
                p.push_back(Point(std::llround(cx + rr * std::cos(t)),
                                  std::llround(cy + rr * std::sin(t))));
            }
            return p;
        };
        Paths loops =
            unite(Paths{blob(0, 0, 8 * kMm), blob(3 * kMm * u(rng), 3 * kMm * u(rng), 3 * kMm)});
        loops = subtract(loops, Paths{blob(2 * kMm * u(rng), 2 * kMm * u(rng), 1.5 * kMm)});
        const Paths region = Paths{blob(6 * kMm * u(rng), 6 * kMm * u(rng), 7 * kMm)};
        const double ext = 1.0 * kMm;
        const Coord depth = 500;
        auto pieces = loops_inside_erosion(loops, region, depth, ext, 0);
        std::vector<Extrusion> ex;
        for (auto& p : pieces) {
            Extrusion e;
            e.points = p.points;
            e.closed = p.closed;
            ex.push_back(e);
        }
        // Every output point lies on a loop. A stretch outside region ⊖ depth (measured here by
        // brute force) is an extension: at most ext long at a piece's end, at most 2 ext where
        // two extensions met and merged.
        auto in_erosion = [&](const Point& p, double margin) {
            return point_in_region(p, region) && boundary_dist(p, region) > depth + margin;
        };
        for (const Extrusion& e : ex) {
            const double len = path_length(e);
            auto pts = samples(e, 50);
            double run_start = -1;
            for (size_t i = 0; i <= pts.size(); ++i) {
                const bool outside = i < pts.size() && !in_erosion(pts[i].first, -5);
                if (i < pts.size()) {
                    EXPECT_LT(boundary_dist(pts[i].first, loops), 3.0);
                }
                if (outside && run_start < 0) run_start = pts[i].second;
                if (!outside && run_start >= 0) {
                    const double run_end = i < pts.size() ? pts[i].second : len;
                    const bool at_end = !e.closed && (run_start == 0 || run_end >= len);
                    EXPECT_LE(run_end - run_start, (at_end ? 1 : 2) * ext + 120)
                        << "trial " << trial << " run " << run_start << ".." << run_end << " of "
                        << len << (e.closed ? " closed" : " open");
                    run_start = -1;
                }
            }
        }
        // Every loop point well inside region ⊖ depth is covered by an output piece.
        for (const Path& l : loops) {
            Extrusion e;
            e.points = l;
            e.closed = true;
            for (const auto& [p, at] : samples(e, 150)) {
                if (!in_erosion(p, 5)) continue;
                double best = 1e18;
                for (const Extrusion& o : ex) {
                    Path q = o.points;
                    if (o.closed) q.push_back(q.front());
                    for (size_t i = 1; i < q.size(); ++i)
                        best = std::min(best, seg_dist(p, q[i - 1], q[i]));
                }
                EXPECT_LT(best, 3.0) << "trial " << trial << " at " << p.X << "," << p.Y;
            }
        }
    }
}

TEST(Fill, ThinBandAlongTheLinesIsNotLost) {
    // A 0.3 mm wide, 10 mm long band at 45 degrees, filled with 45 degree lines: no scanline
    // runs inside it, only its ends and the boundary connectors can cover it.
    const double c = std::sqrt(0.5);
    auto at = [&](double along, double across) {
        return Point(std::llround((along * c - across * c) * kMm),
                     std::llround((along * c + across * c) * kMm));
    };
    const Paths band = {{at(0, 0), at(10, 0), at(10, 0.3), at(0, 0.3)}};
    auto lines = fill_solid(band, 45.0, 400, Feature::Cover);
    double total = 0;
    for (const Extrusion& e : lines) {
        total += path_length(e);
        for (const Point& p : e.points) EXPECT_LT(boundary_dist(p, band), 2.0);
    }
    EXPECT_GT(total, 9.5 * kMm);
    // Across the lines the same band gets short lines joined into one zig-zag.
    lines = fill_solid(band, -45.0, 400, Feature::Cover);
    ASSERT_EQ(lines.size(), 1u);
    EXPECT_GT(lines[0].flow, 0.99);
}

TEST(Fill, ThinStripGetsOneLineAsWideAsItIs) {
    // A 12 mm strip widening from 0.2 to 0.5 mm, and a second one meeting its narrow end at a
    // point (where a cover line's cap cut a band in two): one line along the middle of each,
    // wider where the strip is, reaching into the pinch, and what it leaves is specks.
    const Paths strip = {{{0, -100}, {12 * kMm, -250}, {12 * kMm, 250}, {0, 100}}};
    const Paths other = {{{-6 * kMm, -150}, {0, 0}, {-6 * kMm, 150}}};
    const Paths region = unite(strip, other);
    const Coord w = 400;
    const auto lines = fill_thin(region, w, 60, 160, Feature::Cover);
    ASSERT_FALSE(lines.empty());
    Paths covered;
    double reach_left = 0, reach_right = 0;
    for (const Extrusion& e : lines) {
        EXPECT_EQ(e.feature, Feature::Cover);
        EXPECT_GT(e.flow, 0.3);
        EXPECT_LT(e.flow, 1.5);
        for (const Point& p : e.points) {
            EXPECT_LT(std::abs(p.Y), 30) << p.X << "," << p.Y;  // the middle
            if (p.X < 0) reach_left = std::max(reach_left, double(p.X));
            if (p.X > 0) reach_right = std::min(reach_right == 0 ? 1e9 : reach_right, double(p.X));
        }
        // Along the strip the width grows: a run's flow matches the strip's width there.
        const double mid_x = 0.5 * double(e.points.front().X + e.points.back().X);
        if (mid_x > 1 * kMm && mid_x < 11 * kMm) {  // not the ends, where the strip's end is near
            const double width = 200 + 300 * mid_x / (12 * kMm);
            EXPECT_NEAR(e.flow * double(w), width + 60, 0.12 * double(w)) << mid_x;
        }
        const Paths bead = dilate_lines(Paths{e.points}, Coord(e.flow * double(w) / 2));
        covered.insert(covered.end(), bead.begin(), bead.end());
    }
    // The lines reach within 0.5 mm of the pinch from both sides.
    EXPECT_GT(reach_left, -500);
    EXPECT_LT(reach_right, 500);
    const Paths left = subtract(region, unite(covered));
    EXPECT_LT(area_mm2(open(left, 100)), 0.02 * area_mm2(region));
}

TEST(Toolpath, ThinCoverBandGetsOneLineAWideOneIsOutlined) {
    // Covers only 0.6 mm wide between the outer wall's centreline and the carvable part: no
    // room for two lines. No edge either (the walls of the layers above and below cover the
    // band's inner side), but what lies between the wall's bead and s from the carvable part,
    // 0.2 mm, gets one line along its middle, as wide as it plus the overlap (issue #35: such
    // strips were left open, 1.5 % of the top skin on the shared models).
    Settings st;
    LayerPartition l = square_layer(st);
    l.carvable = rect_region(-9200, -9200, 9200, 9200);
    l.covers = subtract(l.shell_paths_region, l.carvable);
    {
        const LayerToolpaths t = plan_layer(l, st);
        const auto thin = of_feature(t, Feature::Cover);
        ASSERT_FALSE(thin.empty());
        double total = 0;
        for (const Extrusion* e : thin) {
            EXPECT_FALSE(e->closed);
            total += path_length(*e);
            // Along the sides (the corners are wider: the axis turns along their diagonal).
            bool side = true;
            for (const Point& p : e->points) {
                if (std::min(std::abs(p.X), std::abs(p.Y)) > 9000) {
                    side = false;
                    continue;
                }
                EXPECT_NEAR(std::max(std::abs(p.X), std::abs(p.Y)), 9500, 30) << p.X << "," << p.Y;
            }
            if (side) {
                EXPECT_NEAR(e->flow, (0.2 + 0.15 * st.nozzle) / st.nozzle, 0.05);
            }
            EXPECT_LT(e->flow, 1.0);
        }
        // Round the band, less what the corners' turns leave to the lines' caps.
        EXPECT_GT(total / kMm, 4 * 19.0 - 4 * 1.0);
        EXPECT_LT(total / kMm, 4 * 19.0 + 0.1);
    }
    // 0.5 mm wide: the 0.1 mm between the wall's bead and the carvable part's reach is left.
    l.carvable = rect_region(-9300, -9300, 9300, 9300);
    l.covers = subtract(l.shell_paths_region, l.carvable);
    EXPECT_TRUE(of_feature(plan_layer(l, st), Feature::Cover).empty());

    // 1.8 mm wide: solid lines, and the edge on the carvable part's boundary outlines them.
    l.carvable = rect_region(-8 * kMm, -8 * kMm, 8 * kMm, 8 * kMm);
    l.covers = subtract(l.shell_paths_region, l.carvable);
    const LayerToolpaths t = plan_layer(l, st);
    const auto covers = of_feature(t, Feature::Cover);
    ASSERT_GE(covers.size(), 2u);
    const auto edge = std::find_if(covers.begin(), covers.end(), [](const Extrusion* e) {
        return e->closed && std::abs(path_length(*e) / kMm - 4 * 16.0) < 0.01;
    });
    EXPECT_NE(edge, covers.end()) << "no closed 16 x 16 mm edge";
    double lines_mm = 0;
    for (const Extrusion* e : covers)
        if (!e->closed) lines_mm += path_length(*e) / kMm;
    // The band's area over the line width, less what keeps off the walls.
    EXPECT_GT(lines_mm, 0.5 * area_mm2(l.covers) / st.nozzle);
    EXPECT_LT(lines_mm, 1.2 * area_mm2(l.covers) / st.nozzle);
}

// What the iterations left uncarved (V^k) is solid model: filled with cover lines inside the
// cavity walls that bound it, never left as a void nothing holds the top of.
TEST(Toolpath, UncarvedRemainderIsFilledSolid) {
    Settings st;
    LayerPartition l = two_cavities(st);
    const LayerToolpaths t = plan_layer(l, st);
    const Paths solid = erode(l.remainder, st.line_width() / 2);
    double inside = 0, total = 0;
    for (const Extrusion& e : t.extrusions) {
        if (e.feature != Feature::Cover) continue;
        const double len = length(Paths{e.points}, false);
        total += len;
        if (!clip_lines(Paths{e.points}, solid).empty()) inside += len;
    }
    // Lines at spacing w over the remainder: about its area / w of length.
    EXPECT_NEAR(total / kMm, area_mm2(l.remainder) / st.nozzle,
                0.15 * area_mm2(l.remainder) / st.nozzle);
    EXPECT_NEAR(inside, total, 1e-6 * total);

    l.remainder.clear();  // fully carved: nothing solid inside
    const LayerToolpaths empty = plan_layer(l, st);
    EXPECT_TRUE(std::none_of(empty.extrusions.begin(), empty.extrusions.end(),
                             [](const Extrusion& e) { return e.feature == Feature::Cover; }));
}

// plan_layer opens only the cavity's pieces near V^j and erodes only V^{j-1}'s pieces around
// them (a wall point is within s' of V^j). On slices of scattered pieces, some carved whole and
// some in part, with and without the sweep's V^{j-1}, the walls must be those of the whole
// cavity: boundary of the opened cavity where it lies t inside V^{j-1}.
TEST(Toolpath, CavityWallsOnlyNearWhatTheCavityLeavesAreAllTheWalls) {
    Settings st;
    carve::test::Rng rng(5);
    const auto pos = [](carve::test::Rng& r) { return r.integer(-9, 7); };
    const auto size = [](carve::test::Rng& r) { return r.integer(1, 3); };
    const auto coin = [](carve::test::Rng& r) { return r.integer(0, 2); };
    for (int round = 0; round < 20; ++round) {
        LayerPartition l = square_layer(st);
        Paths pieces;
        for (int k = 0; k < 10; ++k) {
            const Coord x = pos(rng) * kMm, y = pos(rng) * kMm, a = size(rng) * kMm;
            pieces = unite(pieces, rect_region(x, y, x + a, y + a));
        }
        l.carvable = intersect(l.carvable, pieces);
        // C^1 takes some pieces whole and cuts others; C^2 takes part of what is left.
        Paths c1;
        for (const Paths& comp : components(l.carvable)) {
            const int c = coin(rng);
            const BBox2 b = bounds(comp);
            if (c == 0) c1.insert(c1.end(), comp.begin(), comp.end());
            if (c == 1)
                c1 = unite(c1, intersect(comp, rect_region(b.min_x, b.min_y,
                                                           (b.min_x + b.max_x) / 2, b.max_y)));
        }
        const Paths v1 = subtract(l.carvable, c1);
        const Paths c2 = intersect(v1, rect_region(-10 * kMm, -10 * kMm, 10 * kMm, 2 * kMm));
        l.cavities = {c1, c2};
        l.remainder = subtract(v1, c2);
        const bool swept = round % 2 == 0;
        if (swept) l.uncarved = {l.carvable, v1};
        const LayerToolpaths t = plan_layer(l, st);
        const Paths* uncarved[2] = {&l.carvable, &v1};
        for (int j = 0; j < 2; ++j) {
            double want = 0;
            for (const WallPiece& w : loops_inside_erosion(
                     clean(open(l.cavities[j], st.opening()), 5.0), *uncarved[j], st.restriction(),
                     to_units(st.wall_extension_mm()), 2.0 * double(st.line_width())))
                want += length(Paths{w.points}, w.closed);
            double got = 0;
            for (const Extrusion& e : t.extrusions)
                if (e.feature == Feature::CavityWall && e.cavity == j + 1)
                    got += length(Paths{e.points}, e.closed);
            EXPECT_NEAR(got, want, 1e-6 * want + 1) << "round " << round << " cavity " << j + 1;
            if (j == 0) {
                EXPECT_GT(want, 0) << round;
            }
        }
    }
}

TEST(IslandOrder, APlateOfManyPartsIsOrderedNearestFirstWithoutAGapTable) {
    // Issue #38: beyond 64 islands the order is one nearest-gap pass from the first island;
    // it kept a table of every pair's gap (10,000 build items: 800 MB a layer). Now each gap is
    // computed when the pass needs it: the order must be the very same pass.
    carve::test::Rng rng(38);
    Paths shape;
    for (int i = 0; i < 15; ++i)
        for (int j = 0; j < 10; ++j) {
            const Coord x = i * 3 * kMm + Coord(rng.integer(0, 1000));
            const Coord y = j * 3 * kMm + Coord(rng.integer(0, 1000));
            shape.push_back(rect_region(x, y, x + kMm, y + kMm)[0]);
        }
    LayerIslands islands(shape, 400, 0);
    std::vector<Extrusion> walls;
    for (const Path& p : shape) walls.push_back({Feature::OuterWall, p, true});
    islands.distribute(walls, &Island::outer);
    const Point pos(50 * kMm, 40 * kMm);
    const std::vector<size_t> got = islands.print_order(pos);

    const Comber index(shape);
    const size_t k = size_t(index.islands());
    ASSERT_EQ(k, shape.size());
    std::vector<size_t> expected{0};
    std::vector<bool> used(k, false);
    used[0] = true;
    while (expected.size() < k) {
        size_t next = k;
        double best = 0;
        for (size_t j = 0; j < k; ++j) {
            if (used[j]) continue;
            const size_t a = std::min(expected.back(), j), b = std::max(expected.back(), j);
            const double g = index.gap(int(a), int(b));
            if (next == k || g < best) next = j, best = g;
        }
        used[next] = true;
        expected.push_back(next);
    }
    auto entry = [&](size_t i) {
        const Point& q = islands[i].outer.at(0).points.front();
        return std::hypot(double(q.X - pos.X), double(q.Y - pos.Y));
    };
    if (entry(expected.back()) < entry(expected.front()))
        std::reverse(expected.begin(), expected.end());
    EXPECT_EQ(got, expected);
}

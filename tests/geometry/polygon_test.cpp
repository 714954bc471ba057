// Tests of the boolean and measure wrappers (polygon.hpp): orientation of results, nesting of
// components, holes and islands, open-line clipping, and the small-area filter.
#include "geometry/polygon.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "geometry/morphology.hpp"
#include "support/test_rng.hpp"

using namespace carve;

namespace {

Path square(Coord x0, Coord y0, Coord side) {
    return {{x0, y0}, {x0 + side, y0}, {x0 + side, y0 + side}, {x0, y0 + side}};
}

Path reversed(Path p) {
    std::reverse(p.begin(), p.end());
    return p;
}

// A square ring with an island inside its hole: three nesting levels.
Paths ring_with_island() {
    return {square(0, 0, 10000), reversed(square(2000, 2000, 6000)), square(4000, 4000, 2000)};
}

// The reference for the grouped booleans, written out here rather than taken from polygon.cpp:
// one Clipper pass over everything.
Paths one_clipper_pass(ClipperLib::ClipType op, const Paths& a, const Paths* b,
                       ClipperLib::PolyFillType clip_fill = ClipperLib::pftNonZero) {
    using namespace ClipperLib;
    Clipper c;
    c.AddPaths(a, ptSubject, true);
    if (b) c.AddPaths(*b, ptClip, true);
    Paths out;
    c.Execute(op, out, pftNonZero, clip_fill);
    return out;
}

// The same region to the last unit: nothing between them, and as many contours.
bool same_region(const Paths& got, const Paths& want) {
    return std::abs(area(symmetric_difference(got, want))) == 0 && area(got) == area(want) &&
           got.size() == want.size();
}

// Every outer counter-clockwise, every hole clockwise.
bool normalised(const Paths& region) {
    for (const Paths& comp : components(region)) {
        if (area(comp.front()) <= 0) return false;
        for (size_t i = 1; i < comp.size(); ++i)
            if (area(comp[i]) >= 0) return false;
    }
    return true;
}

}  // namespace

TEST(Polygon, SignedArea) {
    EXPECT_DOUBLE_EQ(area(square(0, 0, 1000)), 1e6);
    EXPECT_DOUBLE_EQ(area(reversed(square(0, 0, 1000))), -1e6);
    EXPECT_DOUBLE_EQ(area(ring_with_island()), 1e8 - 36e6 + 4e6);
    EXPECT_DOUBLE_EQ(area_mm2(Paths{square(0, 0, 2000)}), 4.0);
    EXPECT_EQ(area(Paths{}), 0.0);
}

TEST(Polygon, UniteMergesOverlapsAndFixesOrientation) {
    const Paths overlapping{square(0, 0, 1000), square(500, 0, 1000)};
    const Paths u = unite(overlapping);
    ASSERT_EQ(u.size(), 1u);
    EXPECT_DOUBLE_EQ(area(u), 1500.0 * 1000.0);
    // Non-zero fill: a clockwise contour alone is filled too, and comes back counter-clockwise.
    const Paths cw = unite(Paths{reversed(square(0, 0, 1000))});
    ASSERT_EQ(cw.size(), 1u);
    EXPECT_DOUBLE_EQ(area(cw), 1e6);
    // Where a clockwise and a counter-clockwise contour overlap the winding is 0: empty.
    EXPECT_DOUBLE_EQ(area(unite(Paths{square(0, 0, 1000), reversed(square(500, 0, 1000))})), 1e6);
    EXPECT_TRUE(normalised(unite(ring_with_island())));
    EXPECT_DOUBLE_EQ(area(unite(Paths{square(0, 0, 10)}, Paths{square(20, 0, 10)})), 200.0);
}

TEST(Polygon, IntersectSubtractXor) {
    const Paths a{square(0, 0, 1000)}, b{square(500, 500, 1000)};
    EXPECT_DOUBLE_EQ(area(intersect(a, b)), 250000.0);
    EXPECT_DOUBLE_EQ(area(subtract(a, b)), 750000.0);
    EXPECT_DOUBLE_EQ(area(symmetric_difference(a, b)), 1500000.0);
    EXPECT_TRUE(intersect(a, Paths{}).empty());
    EXPECT_TRUE(subtract(Paths{}, a).empty());
    EXPECT_DOUBLE_EQ(area(subtract(a, Paths{})), area(a));
    // Subtracting an inner square makes a hole, returned clockwise.
    const Paths holed = subtract(Paths{square(0, 0, 3000)}, Paths{square(1000, 1000, 1000)});
    ASSERT_EQ(holed.size(), 2u);
    EXPECT_TRUE(normalised(holed));
    EXPECT_DOUBLE_EQ(area(holed), 8e6);
}

TEST(Polygon, UnitePositiveKeepsOnlyPositiveWinding) {
    // A counter-clockwise square and a clockwise one inside it: positive fill keeps the ring,
    // a clockwise square alone is nothing.
    const Paths ring{square(0, 0, 3000), reversed(square(1000, 1000, 1000))};
    EXPECT_DOUBLE_EQ(area(unite_positive(ring)), 8e6);
    EXPECT_TRUE(unite_positive(Paths{reversed(square(0, 0, 1000))}).empty());
    // Winding 2 where two counter-clockwise squares overlap: still inside once.
    EXPECT_DOUBLE_EQ(area(unite_positive(Paths{square(0, 0, 1000), square(500, 0, 1000)})), 1.5e6);
}

TEST(Polygon, ClipLinesKeepsThePartsInside) {
    const Paths region{square(0, 0, 1000)};
    const Paths lines{{{-500, 500}, {1500, 500}}, {{200, -100}, {200, 2000}}};
    const Paths in = clip_lines(lines, region);
    EXPECT_DOUBLE_EQ(length(in, false), 2000.0);
    EXPECT_EQ(in.size(), 2u);
    EXPECT_TRUE(clip_lines(lines, Paths{}).empty());
    // A line across a hole is cut in two.
    const Paths holed = subtract(Paths{square(0, 0, 3000)}, Paths{square(1000, 1000, 1000)});
    const Paths across = clip_lines(Paths{{{-1, 1500}, {3001, 1500}}}, holed);
    EXPECT_EQ(across.size(), 2u);
    EXPECT_DOUBLE_EQ(length(across, false), 2000.0);
}

TEST(Polygon, CleanDropsDuplicateAndCollinearPoints) {
    const Paths messy{{{0, 0}, {500, 0}, {500, 0}, {1000, 0}, {1000, 1000}, {0, 1000}, {0, 1}}};
    const Paths c = clean(messy);
    ASSERT_EQ(c.size(), 1u);
    EXPECT_EQ(c[0].size(), 4u);
    EXPECT_NEAR(area(c), 1e6, 600);
    EXPECT_TRUE(clean(Paths{{{0, 0}, {1, 0}, {1, 1}}}).empty());  // collapses below 3 points
}

TEST(Polygon, BoundsAndLength) {
    const BBox2 b = bounds(ring_with_island());
    EXPECT_FALSE(b.empty);
    EXPECT_EQ(b.min_x, 0);
    EXPECT_EQ(b.max_y, 10000);
    EXPECT_TRUE(bounds(Paths{}).empty);
    EXPECT_DOUBLE_EQ(length(Paths{square(0, 0, 1000)}, true), 4000.0);
    EXPECT_DOUBLE_EQ(length(Paths{square(0, 0, 1000)}, false), 3000.0);
    EXPECT_DOUBLE_EQ(length(Paths{{{0, 0}, {300, 400}}}, false), 500.0);
}

TEST(Polygon, ComponentsSeparateIslandsInHoles) {
    const std::vector<Paths> comps = components(ring_with_island());
    ASSERT_EQ(comps.size(), 2u);
    // One component is the ring (outer + hole), the other the island alone.
    size_t ring = comps[0].size() == 2 ? 0 : 1;
    EXPECT_EQ(comps[ring].size(), 2u);
    EXPECT_EQ(comps[1 - ring].size(), 1u);
    EXPECT_DOUBLE_EQ(area(comps[ring]), 1e8 - 36e6);
    EXPECT_DOUBLE_EQ(area(comps[1 - ring]), 4e6);
    EXPECT_TRUE(components(Paths{}).empty());
}

TEST(Polygon, EmptyHolesAreTheHolesWithoutIslands) {
    // The ring's hole holds the island: not empty. A second hole with nothing in it is.
    Paths r = ring_with_island();
    r.push_back(reversed(square(500, 500, 1000)));
    const Paths holes = empty_holes(r);
    ASSERT_EQ(holes.size(), 1u);
    EXPECT_DOUBLE_EQ(area(holes), 1e6);  // returned counter-clockwise
    EXPECT_TRUE(empty_holes(Paths{square(0, 0, 100)}).empty());
}

TEST(Polygon, EmptyHolesMatchClippersNestingOnRandomRegions) {
    // Rings inside rings, some with islands, some touching, as the booleans leave them; the
    // reference is Clipper's own nesting (PolyTree): holes without children.
    carve::test::Rng rng(17);
    int holes_seen = 0, islands_seen = 0;
    for (int trial = 0; trial < 200; ++trial) {
        Paths region;
        for (int k = 0; k < 6; ++k) {
            const Coord x = rng.integer(0, 20000), y = rng.integer(0, 20000);
            const Coord a = rng.integer(2000, 12000), t = rng.integer(300, a / 3);
            Paths ring = subtract(Paths{square(x, y, a)}, Paths{square(x + t, y + t, a - 2 * t)});
            const Coord inner = a - 2 * t, g = rng.integer(100, std::max<int>(101, inner / 3));
            if (rng.integer(0, 1) == 0 && inner - 2 * g > 100)
                ring = unite(ring, Paths{square(x + t + g, y + t + g, inner - 2 * g)});
            region = rng.integer(0, 3) == 0 ? subtract(region, ring) : unite(region, ring);
        }
        ClipperLib::PolyTree tree;
        ClipperLib::Clipper c;
        c.AddPaths(region, ClipperLib::ptSubject, true);
        c.Execute(ClipperLib::ctUnion, tree, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
        double want = 0;
        int empty = 0;
        for (ClipperLib::PolyNode* n = tree.GetFirst(); n; n = n->GetNext())
            if (n->IsHole()) {
                ++holes_seen;
                if (n->Childs.empty())
                    want += std::abs(area(n->Contour)), ++empty;
                else
                    ++islands_seen;
            }
        const Paths got = empty_holes(region);
        EXPECT_EQ(int(got.size()), empty) << "trial " << trial;
        EXPECT_DOUBLE_EQ(area(got), want) << "trial " << trial;  // counter-clockwise
    }
    EXPECT_GT(holes_seen, 200);
    EXPECT_GT(islands_seen, 50);
}

TEST(Polygon, PointInRegionRespectsHolesAndIslands) {
    const Paths r = ring_with_island();
    EXPECT_TRUE(point_in_region({1000, 1000}, r));   // in the ring
    EXPECT_FALSE(point_in_region({3000, 3000}, r));  // in the hole
    EXPECT_TRUE(point_in_region({5000, 5000}, r));   // on the island
    EXPECT_FALSE(point_in_region({-1, 5000}, r));    // outside
    EXPECT_TRUE(point_in_region({0, 5000}, r));      // on the boundary counts as inside
    EXPECT_FALSE(point_in_region({0, 0}, Paths{}));
}

// The wrappers clip groups of contours whose boxes do not overlap one by one; the result must be
// what one Clipper pass over everything gives, for scattered, touching, overlapping and nested
// pieces, with holes, under every operation.
TEST(Polygon, GroupedBooleansEqualOneClipperPass) {
    using namespace ClipperLib;
    carve::test::Rng rng(7);
    auto scatter = [&rng](int count) {
        Paths out;
        for (int i = 0; i < count; ++i) {
            const Coord x = rng.integer(0, 40) * 500, y = rng.integer(0, 8) * 500;
            const Coord side = rng.integer(1, 6) * 500;  // touching and overlapping neighbours
            out.push_back(square(x, y, side));
            if (side >= 2000 && rng.integer(0, 1))  // sometimes with a hole
                out.push_back(reversed(square(x + 500, y + 500, side - 1000)));
        }
        return unite(out);
    };
    int grouped = 0;
    for (int round = 0; round < 60; ++round) {
        const Paths a = scatter(rng.integer(1, 12)), b = scatter(rng.integer(1, 12));
        Paths both = a;
        both.insert(both.end(), b.begin(), b.end());
        grouped += components(a).size() > 1;
        EXPECT_TRUE(same_region(intersect(a, b), one_clipper_pass(ctIntersection, a, &b))) << round;
        EXPECT_TRUE(same_region(subtract(a, b), one_clipper_pass(ctDifference, a, &b))) << round;
        EXPECT_TRUE(same_region(unite(a, b), one_clipper_pass(ctUnion, a, &b))) << round;
        EXPECT_TRUE(same_region(unite(both), one_clipper_pass(ctUnion, both, nullptr))) << round;
        EXPECT_TRUE(same_region(symmetric_difference(a, b), one_clipper_pass(ctXor, a, &b)))
            << round;
    }
    EXPECT_GT(grouped, 30);  // most rounds have pieces apart, which the grouping splits
}

// components() takes a group of contours with a single outer as one component without Clipper;
// on scattered pieces with holes, islands in holes and touching neighbours the components must
// be those of Clipper's nesting: the same number, each with the same outer area and holes.
TEST(Polygon, ComponentsOfScatteredPiecesMatchClippersNesting) {
    using namespace ClipperLib;
    carve::test::Rng rng(9);
    auto summary = [](const std::vector<Paths>& comps) {
        std::vector<std::pair<double, double>> out;  // (outer area, total area), sorted
        for (const Paths& c : comps) out.emplace_back(area(c.front()), area(c));
        std::sort(out.begin(), out.end());
        return out;
    };
    int shortcut = 0;
    for (int round = 0; round < 40; ++round) {
        Paths raw;
        for (int i = 0; i < rng.integer(1, 10); ++i) {
            const Coord x = rng.integer(0, 30) * 1000, y = rng.integer(0, 6) * 1000;
            const Coord side = rng.integer(1, 5) * 1000;
            raw.push_back(square(x, y, side));
        }
        Paths region = unite(raw);
        if (rng.integer(0, 2) > 0) {  // a ring, apart or not, sometimes with an island
            const Coord x = rng.integer(0, 30) * 1000;
            region =
                unite(region, subtract({square(x, 9000, 5000)}, {square(x + 1000, 10000, 3000)}));
            if (rng.integer(0, 1)) region = unite(region, {square(x + 2000, 11000, 1000)});
        }
        PolyTree tree;
        Clipper c;
        c.AddPaths(region, ptSubject, true);
        c.Execute(ctUnion, tree, pftNonZero, pftNonZero);
        Paths outers;
        for (const Path& p : region)
            if (area(p) > 0) outers.push_back(p);
        const std::vector<Paths> got = components(region);
        size_t want = 0;
        for (PolyNode* n = tree.GetFirst(); n; n = n->GetNext()) want += !n->IsHole();
        EXPECT_EQ(got.size(), want) << round;
        EXPECT_EQ(got.size(), outers.size()) << round;
        // Against the library's nesting, one component at a time: outer first, then its holes.
        std::vector<Paths> ref;
        for (PolyNode* n = tree.GetFirst(); n; n = n->GetNext()) {
            if (n->IsHole()) continue;
            Paths comp{n->Contour};
            for (PolyNode* h : n->Childs) comp.push_back(h->Contour);
            ref.push_back(comp);
        }
        EXPECT_EQ(summary(got), summary(ref)) << round;
        shortcut += clusters(region).size() > 1;
    }
    EXPECT_GT(shortcut, 20);
}

// contours_near() leaves out what a dilation by up to `reach` cannot bring to `other`: outers
// with their holes, and holes (filled). Within `other` the dilation of what it keeps must be
// that of the whole region, and rounds must drop something, outers and holes alike.
TEST(Polygon, ContoursNearKeepTheDilationWithinTheOther) {
    carve::test::Rng rng(11);
    auto holed_squares = [&rng](int count, Coord spread) {
        Paths out;
        for (int i = 0; i < count; ++i) {
            const Coord x = rng.integer(0, 40) * spread, y = rng.integer(0, 10) * spread;
            const Coord side = rng.integer(4, 12) * 500;
            out.push_back(square(x, y, side));
            if (rng.integer(0, 2) > 0) {  // a hole, 300 um inside or further in
                const Coord hx = x + 300 + rng.integer(0, 3) * 400;
                const Coord hy = y + 300 + rng.integer(0, 3) * 400;
                out.push_back(reversed(square(hx, hy, 1500)));
            }
        }
        return unite(out);
    };
    int dropped_outers = 0, dropped_holes = 0;
    for (int round = 0; round < 120; ++round) {
        const Paths region = holed_squares(rng.integer(2, 10), 1000);
        const Paths other = holed_squares(rng.integer(1, 4), 1000);
        const Coord reach = rng.integer(1, 4) * 250;
        const Paths kept = contours_near(region, other, reach);
        for (const Path& p : region)
            if (std::find(kept.begin(), kept.end(), p) == kept.end())
                (area(p) > 0 ? dropped_outers : dropped_holes)++;
        EXPECT_EQ(std::abs(area(symmetric_difference(intersect(dilate(kept, reach), other),
                                                     intersect(dilate(region, reach), other)))),
                  0.0)
            << round;
    }
    EXPECT_GT(dropped_outers, 60);
    EXPECT_GT(dropped_holes, 15);
}

// clip_to_box() keeps the winding number of every point inside the box: united, the cut
// contours are the region's intersection with the box, up to the rounding of the cuts. The
// bridges cut cavities to a window around each minimum with it.
TEST(Polygon, BoxClipUnitedIsTheIntersectionWithTheBox) {
    carve::test::Rng rng(13);
    int cut = 0;
    for (int round = 0; round < 80; ++round) {
        Paths raw;
        for (int i = 0; i < rng.integer(1, 8); ++i) {
            const Coord x = rng.integer(0, 30) * 700, y = rng.integer(0, 30) * 700;
            const Coord side = rng.integer(2, 12) * 600;
            raw.push_back(square(x, y, side));
            if (rng.integer(0, 1)) raw.push_back(reversed(square(x + 500, y + 500, side - 1000)));
        }
        Path tilted;  // a rotated piece, so that cuts fall between integer points
        const double a = rng.uniform(0, 3.14159), cx = rng.integer(0, 20000),
                     cy = rng.integer(0, 20000);
        for (int k = 0; k < 5; ++k) {
            const double t = a + k * 2 * 3.14159 / 5;
            tilted.emplace_back(Coord(cx + 6000 * std::cos(t)), Coord(cy + 6000 * std::sin(t)));
        }
        raw.push_back(tilted);
        const Paths region = unite(raw);
        const Coord x0 = rng.integer(0, 15000), y0 = rng.integer(0, 15000);
        const BBox2 box{x0, y0, x0 + rng.integer(1000, 15000), y0 + rng.integer(1000, 15000),
                        false};
        const Paths want = intersect(region, {{{box.min_x, box.min_y},
                                               {box.max_x, box.min_y},
                                               {box.max_x, box.max_y},
                                               {box.min_x, box.max_y}}});
        const Paths got = unite(clip_to_box(region, box));
        cut += !want.empty() && std::abs(area(want) - area(region)) > 1;
        // um^2: a cut end rounded by half a unit swings its edge by a sliver, at most half a
        // unit wide along the boundary; a lost winding costs a whole piece (square mm).
        EXPECT_LT(std::abs(area(symmetric_difference(got, want))), 0.5 * length(want, true) + 10)
            << round;
    }
    EXPECT_GT(cut, 40);
}

// simplify() drops points almost in line, never two in a row, so no point of the input ends
// further than the tolerance from the result. clean() re-tests each point against the
// neighbours left after the last removal and flattens a finely sampled gentle arc far more.
TEST(Polygon, SimplifyStaysWithinItsTolerance) {
    const double radius = 1e6, step = 20;  // a 1 m circle sampled every 20 um: bends 0.2 um
    Path arc;
    for (int k = 0; k <= 2000; ++k) {
        const double t = k * step / radius;
        arc.emplace_back(std::llround(radius * std::sin(t)), std::llround(radius * std::cos(t)));
    }
    arc.emplace_back(arc.back().X, -100000);  // closed far below the arc
    arc.emplace_back(0, -100000);
    std::reverse(arc.begin(), arc.end());  // counter-clockwise
    auto farthest = [&](const Paths& simplified) {
        double worst = 0;
        for (const Point& p : arc) {
            double best = 1e300;
            const Path& q = simplified.front();
            for (size_t i = 0; i < q.size(); ++i) {
                const Point& a = q[i];
                const Point& b = q[(i + 1) % q.size()];
                const double dx = double(b.X - a.X), dy = double(b.Y - a.Y);
                const double len2 = dx * dx + dy * dy;
                double t = len2 > 0 ? (double(p.X - a.X) * dx + double(p.Y - a.Y) * dy) / len2 : 0;
                t = std::clamp(t, 0.0, 1.0);
                best = std::min(best, std::hypot(double(p.X) - (double(a.X) + t * dx),
                                                 double(p.Y) - (double(a.Y) + t * dy)));
            }
            worst = std::max(worst, best);
        }
        return worst;
    };
    const Paths s = simplify(Paths{arc}, 5.0);
    ASSERT_EQ(s.size(), 1u);
    EXPECT_LT(s.front().size(), arc.size());  // it does drop the points in line
    EXPECT_LE(farthest(s), 5.0);
    EXPECT_GT(farthest(clean(Paths{arc}, 5.0)), 20.0);  // what simplify() is there to avoid
    // Never two in a row: at least half the points stay.
    EXPECT_GE(2 * s.front().size() + 1, arc.size());
}

// A difference or an intersection runs each piece of one operand with the other's contours
// folded to the piece's box (run_within). Folding keeps every edge that reaches the box, so the
// result is not merely close to one Clipper pass over everything: it is the same, crossing for
// crossing, which is what lets the sweep's passes partition a slice exactly. Here a wavy ring
// with many vertices, unresolved dilations included, lies over scattered small squares.
TEST(Polygon, PiecewiseBooleansUnderALargeContourEqualOneClipperPass) {
    using namespace ClipperLib;
    carve::test::Rng rng(23);
    int folded = 0;
    for (int round = 0; round < 30; ++round) {
        Paths pieces;
        for (int i = 0; i < rng.integer(2, 15); ++i) {
            // One draw per declarator, in reading order: the order of a call's arguments and of
            // the operands of + is unspecified (GCC and clang differ), and the shapes must be
            // the same with every compiler.
            const Coord xc = rng.integer(0, 60) * 700, x = xc + rng.integer(0, 99);
            const Coord yc = rng.integer(0, 60) * 700, y = yc + rng.integer(0, 99);
            const Coord sc = rng.integer(2, 9) * 100, side = sc + rng.integer(0, 99);
            pieces.push_back(square(x, y, side));
        }
        pieces = unite(pieces);
        Path ring, hole;
        const double cx = 21000, cy = 21000;
        for (int k = 0; k < 400; ++k) {
            const double t = 2 * 3.141592653589793 * k / 400;
            const double r = 15000 + 6000 * std::sin(7 * t + round) + rng.uniform(-300, 300);
            ring.emplace_back(std::llround(cx + r * std::cos(t)),
                              std::llround(cy + r * std::sin(t)));
            hole.emplace_back(std::llround(cx + 0.4 * r * std::cos(-t)),
                              std::llround(cy + 0.4 * r * std::sin(-t)));
        }
        const Paths big = unite(Paths{ring, hole});
        EXPECT_TRUE(
            same_region(subtract(pieces, big), one_clipper_pass(ctDifference, pieces, &big)))
            << round;
        EXPECT_TRUE(
            same_region(intersect(pieces, big), one_clipper_pass(ctIntersection, pieces, &big)))
            << round;
        const PositiveRegion raw = dilation(big, rng.integer(50, 900));
        EXPECT_TRUE(same_region(subtract_positive(pieces, raw),
                                one_clipper_pass(ctDifference, pieces, &raw.contours, pftPositive)))
            << round;
        EXPECT_TRUE(
            same_region(intersect_positive(pieces, raw),
                        one_clipper_pass(ctIntersection, pieces, &raw.contours, pftPositive)))
            << round;
        folded += clusters(pieces).size() > 1;
    }
    EXPECT_GT(folded, 20);
}

// Travel, retraction and seams (issue #18): combing on hand-made regions, then whole runs of the
// carve executable on small synthetic models, judged from the G-code they write.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "gcode/spill.hpp"
#include "geometry/polygon.hpp"
#include "support/carve_run.hpp"
#include "support/stl_boxes.hpp"
#include "toolpath/comb.hpp"
#include "toolpath/order.hpp"
#include "toolpath/seam.hpp"

using namespace carve;
using namespace carve::test;
namespace fs = std::filesystem;

namespace {

constexpr Coord kMm = 1000;

// Parts of open polylines outside a region: what of a travel leaves the part.
Paths clip_lines_outside(const Paths& lines, const Paths& region) {
    if (lines.empty() || region.empty()) return lines;
    ClipperLib::Clipper c;
    c.AddPaths(lines, ClipperLib::ptSubject, false);
    c.AddPaths(region, ClipperLib::ptClip, true);
    ClipperLib::PolyTree tree;
    c.Execute(ClipperLib::ctDifference, tree, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
    Paths out;
    ClipperLib::OpenPathsFromPolyTree(tree, out);
    return out;
}

Paths rect(Coord x0, Coord y0, Coord x1, Coord y1) {
    return {{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}};
}

// A C open to the right: 30 x 30 mm, bars 6 mm thick, the mouth 18 mm tall.
Paths c_shape() {
    return unite(unite(rect(0, 0, 6 * kMm, 30 * kMm), rect(0, 0, 30 * kMm, 6 * kMm)),
                 rect(0, 24 * kMm, 30 * kMm, 30 * kMm));
}

double dist(const Point& a, const Point& b) {
    return std::hypot(double(a.X - b.X), double(a.Y - b.Y));
}

// Length of the travel from -> via -> to that lies outside `region`.
double outside_length(const Point& from, const Path& via, const Point& to, const Paths& region) {
    Path line{from};
    line.insert(line.end(), via.begin(), via.end());
    line.push_back(to);
    double len = 0;
    for (const Path& p : clip_lines_outside(Paths{line}, region)) len += length(Paths{p}, false);
    return len;
}

double path_length(const Point& from, const Path& via, const Point& to) {
    double len = 0;
    Point at = from;
    for (const Point& p : via) len += dist(at, p), at = p;
    return len + dist(at, to);
}

TEST(Comb, StraightTravelInsideStaysStraight) {
    const Paths region = rect(0, 0, 20 * kMm, 20 * kMm);
    const Comber comber(region);
    EXPECT_EQ(comber.islands(), 1);
    const TravelPlan t = plan_travel(comber, {1 * kMm, 1 * kMm}, {19 * kMm, 18 * kMm}, {});
    EXPECT_FALSE(t.leaves);
    EXPECT_TRUE(t.via.empty());
}

TEST(Comb, CShapeTravelGoesRoundInsideInsteadOfAcrossTheMouth) {
    const Paths region = c_shape();
    const Comber comber(region);
    // From the tip of the lower arm to the tip of the upper arm: the straight line crosses the
    // mouth, 18 mm outside the part.
    const Point from(28 * kMm, 3 * kMm), to(28 * kMm, 27 * kMm);
    ASSERT_GT(outside_length(from, {}, to, region), 17.0 * kMm);
    const TravelPlan t = plan_travel(comber, from, to, {});
    EXPECT_FALSE(t.leaves);
    ASSERT_FALSE(t.via.empty());
    EXPECT_LT(outside_length(from, t.via, to, region), 1.0);
    // Round the inner corners of the C, pulled tight: close to the shortest path inside, which
    // goes from the lower tip to (6, 6), up to (6, 24) and out to the upper tip: 22 + 18 + 22.
    const double shortest = 2 * std::hypot(22.0, 3.0) + 18.0;
    EXPECT_LT(path_length(from, t.via, to) / kMm, shortest * 1.05);
    EXPECT_GT(path_length(from, t.via, to) / kMm, shortest * 0.99);
}

TEST(Comb, HoleThroughThePartIsAnObstacle) {
    Paths region = rect(0, 0, 30 * kMm, 30 * kMm);
    Path hole = rect(10 * kMm, 10 * kMm, 20 * kMm, 20 * kMm)[0];
    std::reverse(hole.begin(), hole.end());
    region.push_back(hole);
    const Comber comber(region);
    EXPECT_EQ(comber.islands(), 1);
    EXPECT_LT(comber.island_of({15 * kMm, 15 * kMm}), 0);
    const Point from(5 * kMm, 15 * kMm), to(25 * kMm, 15 * kMm);
    const TravelPlan t = plan_travel(comber, from, to, {});
    EXPECT_FALSE(t.leaves);
    EXPECT_LT(outside_length(from, t.via, to, region), 1.0);
    EXPECT_GT(path_length(from, t.via, to), 20.0 * kMm);
}

TEST(Comb, TravelBetweenIslandsLeavesOnceAcrossTheGap) {
    // Two 10 mm squares 20 mm apart; the travel starts at the far side of the left one.
    const Paths region =
        unite(rect(0, 0, 10 * kMm, 10 * kMm), rect(30 * kMm, 0, 40 * kMm, 10 * kMm));
    const Comber comber(region);
    ASSERT_EQ(comber.islands(), 2);
    const Point from(1 * kMm, 9 * kMm), to(39 * kMm, 1 * kMm);
    EXPECT_NE(comber.island_of(from), comber.island_of(to));
    const TravelPlan t = plan_travel(comber, from, to, {});
    EXPECT_TRUE(t.leaves);
    // Outside only across the 20 mm gap, straight from one island to the other.
    EXPECT_NEAR(outside_length(from, t.via, to, region) / kMm, 20.0, 0.5);
    TravelOptions straight;
    straight.avoid_crossing = false;
    const TravelPlan s = plan_travel(comber, from, to, straight);
    EXPECT_TRUE(s.leaves);
    EXPECT_TRUE(s.via.empty());
}

// Two squares placed corner to corner: the gap between them is between the facing corners, so
// a travel from one to the other must cross there. The point of the left square nearest the
// right one used to be the far end of the edge found first (its bottom-right corner, 10 mm
// away), and such a travel crossed from there.
TEST(Comb, NearestPointOfASquareIsItsNearCorner) {
    const Paths region =
        unite(rect(0, 0, 10 * kMm, 10 * kMm), rect(14 * kMm, 14 * kMm, 24 * kMm, 24 * kMm));
    const Comber comber(region);
    ASSERT_EQ(comber.islands(), 2);
    const Point far(20 * kMm, 20 * kMm);
    const int left = comber.island_of(Point(5 * kMm, 5 * kMm));
    const auto q = comber.nearest_in(far, left);
    ASSERT_TRUE(q);
    EXPECT_LT(dist(*q, Point(10 * kMm, 10 * kMm)), 0.1 * kMm);
    EXPECT_NEAR(comber.gap(0, 1) / kMm, std::hypot(4.0, 4.0), 0.01);
    // A travel from the far corner of one to the far corner of the other leaves only across the
    // gap between the near corners.
    const Point from(1 * kMm, 1 * kMm), to(23 * kMm, 23 * kMm);
    const TravelPlan t = plan_travel(comber, from, to, {});
    EXPECT_NEAR(outside_length(from, t.via, to, region) / kMm, std::hypot(4.0, 4.0), 0.2);
}

// Two squares 20 mm apart with a bar above the gap between them, 2 mm off each square
// diagonally: a travel from one square to the other steps through the bar, crossing two gaps
// of 2.8 mm instead of the 20 mm one (before: straight across it).
TEST(Comb, TravelStepsThroughAnIslandAcrossAWideGap) {
    const Paths region =
        unite(unite(rect(0, 0, 10 * kMm, 10 * kMm), rect(30 * kMm, 0, 40 * kMm, 10 * kMm)),
              rect(12 * kMm, 12 * kMm, 28 * kMm, 20 * kMm));
    const Comber comber(region);
    ASSERT_EQ(comber.islands(), 3);
    const Point from(1 * kMm, 1 * kMm), to(39 * kMm, 1 * kMm);
    const int a = comber.island_of(from), c = comber.island_of(to);
    const int b = comber.island_of(Point(20 * kMm, 16 * kMm));
    EXPECT_EQ(comber.stepping_stones(a, c), (std::vector<int>{a, b, c}));
    const TravelPlan t = plan_travel(comber, from, to, {});
    EXPECT_TRUE(t.leaves);
    EXPECT_NEAR(outside_length(from, t.via, to, region) / kMm, 2 * std::hypot(2.0, 2.0), 0.3);
}

// Two bars too thin for the comb region (it holds only a square far away): a travel from one
// to the other used to go straight, 12 mm of it outside; the region inside the outer wall's
// centreline holds both ends, so it crosses where the bars are closest, 2 mm.
TEST(Comb, EndsTooThinForTheCombRegionLeaveAcrossTheNarrowestGap) {
    const Paths thin_region =
        unite(rect(0, 0, 20 * kMm, 1 * kMm), rect(0, 3 * kMm, 20 * kMm, 4 * kMm));
    const Comber comber(rect(50 * kMm, 50 * kMm, 60 * kMm, 60 * kMm));
    const Comber thin(thin_region);
    const Point from(1 * kMm, kMm / 2), to(19 * kMm, 3 * kMm + kMm / 2);
    const TravelPlan t = plan_travel(comber, from, to, {}, &thin);
    EXPECT_TRUE(t.leaves);
    EXPECT_NEAR(outside_length(from, t.via, to, thin_region) / kMm, 2.0, 0.2);
}

TEST(Comb, WallPointsJustOutsideTheRegionAreReached) {
    const Paths region = rect(1 * kMm, 1 * kMm, 19 * kMm, 19 * kMm);
    const Comber comber(region);
    // A point on the outer wall, 0.2 mm outside the comb region.
    const auto l = comber.locate({800, 10 * kMm}, 500);
    ASSERT_TRUE(l.has_value());
    EXPECT_EQ(l->island, 0);
    EXPECT_LT(dist(l->p, {1 * kMm, 10 * kMm}), 50.0);
    EXPECT_FALSE(comber.locate({-2 * kMm, 10 * kMm}, 500).has_value());
    // Outer wall corners, diagonally off the region's corners: the travel from each to the
    // centre stays inside (a corner moved along one edge's normal lies on the other edge, and
    // a travel from a point on the boundary touches it).
    TravelOptions options;
    options.reach = 500;
    for (const Point& corner :
         {Point(800, 800), Point(19200, 800), Point(19200, 19200), Point(800, 19200)}) {
        const TravelPlan t = plan_travel(comber, corner, {10 * kMm, 10 * kMm}, options);
        EXPECT_FALSE(t.leaves) << corner.X << " " << corner.Y;
    }
}

TEST(Seam, AlignedPrefersAConcaveCornerThenAConvexOne) {
    // An L (counter-clockwise): its one concave corner is at (10, 10).
    const Path l_shape{{0, 0},
                       {20 * kMm, 0},
                       {20 * kMm, 10 * kMm},
                       {10 * kMm, 10 * kMm},
                       {10 * kMm, 20 * kMm},
                       {0, 20 * kMm}};
    EXPECT_EQ(seam_vertex(l_shape, SeamMode::Aligned, 3, 0, {0, 0}), 3u);
    // A square: a corner, the one towards the rear right.
    const Path square = rect(0, 0, 10 * kMm, 10 * kMm)[0];
    EXPECT_EQ(seam_vertex(square, SeamMode::Aligned, 3, 0, {0, 0}), 2u);
    EXPECT_EQ(seam_vertex(square, SeamMode::Nearest, 3, 0, {kMm, -kMm}), 0u);
    // Rear: the highest Y, the right end of a flat back edge.
    EXPECT_EQ(seam_vertex(square, SeamMode::Rear, 3, 0, {0, 0}), 2u);
}

TEST(Spill, KeepsTravelsAndTheCombRegion) {
    LayerToolpaths layer;
    layer.index = 3;
    layer.z = 0.8;
    for (int i = 0; i < 3; ++i) {
        Extrusion e;
        e.points = {{i * kMm, 0}, {i * kMm, 5 * kMm}};
        layer.extrusions.push_back(e);
    }
    layer.travels.resize(3);
    layer.travels[1] = {{{-7, 12}, {4 * kMm, -3}}, TravelKind::Inside};
    layer.travels[2] = {{}, TravelKind::Leaves};
    layer.comb_region = c_shape();
    const LayerToolpaths back = decode_layer(encode_layer(layer));
    ASSERT_EQ(back.travels.size(), 3u);
    EXPECT_EQ(back.travels[0].kind, TravelKind::Unplanned);
    EXPECT_EQ(back.travels[1].kind, TravelKind::Inside);
    EXPECT_EQ(back.travels[1].via, layer.travels[1].via);
    EXPECT_EQ(back.travels[2].kind, TravelKind::Leaves);
    EXPECT_EQ(back.comb_region, layer.comb_region);
    layer.travels.clear();  // none planned (combing off)
    EXPECT_TRUE(decode_layer(encode_layer(layer)).travels.empty());
    layer.island_starts = {0, 1, 3};
    layer.thin_region = rect(0, 0, 3 * kMm, 3 * kMm);
    const LayerToolpaths islands = decode_layer(encode_layer(layer));
    EXPECT_EQ(islands.island_starts, layer.island_starts);
    EXPECT_EQ(islands.thin_region, layer.thin_region);
}

// The G-code stage may print a layer's islands last to first: the paths of each island keep
// their order and their travels, the travel into each island (and into the supports after them)
// is left for it to plan from where the nozzle is.
TEST(Islands, ReversedKeepsEachIslandsPathsAndUnplansTheTravelsIntoThem) {
    LayerToolpaths layer;
    layer.index = 2;
    for (int i = 0; i < 6; ++i) {
        Extrusion e;
        e.points = {{i * kMm, 0}, {i * kMm, 5 * kMm}};
        e.feature = i == 5 ? Feature::Support : Feature::OuterWall;
        layer.extrusions.push_back(e);
        layer.travels.push_back({{{i * kMm, -kMm}}, TravelKind::Inside});
    }
    layer.travels[0] = {};
    layer.island_starts = {0, 2, 3, 5};  // islands {0, 1}, {2}, {3, 4}; then a support
    const LayerToolpaths r = with_islands_reversed(layer);
    ASSERT_EQ(r.extrusions.size(), 6u);
    ASSERT_EQ(r.travels.size(), 6u);
    const int order[] = {3, 4, 2, 0, 1, 5};
    for (size_t k = 0; k < 6; ++k) {
        EXPECT_EQ(r.extrusions[k].points.front().X, order[k] * kMm) << k;
        const bool first_of_island =
            order[k] == 3 || order[k] == 2 || order[k] == 0 || order[k] == 5;
        if (first_of_island)
            EXPECT_EQ(r.travels[k].kind, TravelKind::Unplanned) << k;
        else
            EXPECT_EQ(r.travels[k].via, layer.travels[size_t(order[k])].via) << k;
    }
    EXPECT_TRUE(r.island_starts.empty());
}

double order_travel(const std::vector<Extrusion>& paths, Point at) {
    double travel = 0;
    for (const Extrusion& e : paths) {
        travel += dist(at, e.points.front());
        at = e.closed ? e.points.front() : e.points.back();
    }
    return travel;
}

TEST(Order, TwoOptShortensGreedyOrdersAndNeverLengthens) {
    // Random loops and lines: never longer than greedy, and shorter overall.
    std::uint64_t seed = 7;
    auto next = [&] {
        seed = seed * 6364136223846793005ull + 1442695040888963407ull;
        return Coord((seed >> 33) % 50000);
    };
    double greedy_total = 0, improved_total = 0;
    for (int round = 0; round < 20; ++round) {
        std::vector<Extrusion> set;
        for (int k = 0; k < 80; ++k) {
            Extrusion e;
            e.closed = k % 3 == 0;
            for (int v = 0; v < (e.closed ? 5 : 2); ++v) e.points.push_back({next(), next()});
            set.push_back(e);
        }
        Point p(0, 0);
        order_nearest(set, p);
        const double before = order_travel(set, {0, 0});
        Point end;
        improve_order(set, {0, 0}, end);
        const double after = order_travel(set, {0, 0});
        EXPECT_LE(after, before + 1e-6);
        greedy_total += before, improved_total += after;
        const Extrusion& last = set.back();
        EXPECT_EQ(end, last.closed ? last.points.front() : last.points.back());
    }
    EXPECT_LT(improved_total, 0.97 * greedy_total);
}

// --- Whole runs on synthetic models.

using Triangle = StlTriangle;

// What the tests read from a G-code file, per layer: every travel (the moves between two
// extrusions, bed coordinates in um) with whether it retracted, and where the outer wall's
// loops start.
struct Move {
    Path points;  // from the end of the last extrusion through every G0 to the next start
    bool retracted = false;
};
struct LayerMoves {
    std::vector<Move> travels;
    std::vector<Point> seams;
};

std::map<int, LayerMoves> read_moves(const fs::path& gcode) {
    std::map<int, LayerMoves> layers;
    std::ifstream in(gcode);
    std::string line, type;
    int layer = -1;
    double x = 0, y = 0, e = 0;
    Move cur;
    bool want_seam = false, in_travel = false;
    auto pt = [](double a, double b) {
        return Point(std::llround(a * 1000), std::llround(b * 1000));
    };
    while (std::getline(in, line)) {
        if (line.rfind(";LAYER:", 0) == 0) layer = std::stoi(line.substr(7));
        if (line.rfind(";TYPE:", 0) == 0) {
            type = line.substr(6);
            want_seam = type == "External perimeter";
        }
        if (line.rfind("G92 E0", 0) == 0) e = 0;  // each layer's end
        if (line.rfind("G0 ", 0) != 0 && line.rfind("G1 ", 0) != 0) continue;
        std::istringstream ss(line.substr(0, line.find(';')).substr(3));
        std::string w;
        double nx = x, ny = y, ne = e;
        bool has_xy = false, has_e = false;
        while (ss >> w) {
            const double v = std::stod(w.substr(1));
            if (w[0] == 'X') nx = v, has_xy = true;
            if (w[0] == 'Y') ny = v, has_xy = true;
            if (w[0] == 'E') ne = v, has_e = true;
        }
        if (has_e && !has_xy && ne < e) {  // a retraction
            if (!in_travel) cur = Move{{pt(x, y)}, false}, in_travel = true;
            cur.retracted = true;
        } else if (has_xy && has_e && ne > e) {  // an extrusion: the travel before it ends
            if (in_travel && cur.points.size() > 1 && layer >= 0)
                layers[layer].travels.push_back(cur);
            in_travel = false;
            if (want_seam && layer >= 0) layers[layer].seams.push_back(pt(x, y));
            want_seam = false;
        } else if (has_xy && !has_e) {
            if (!in_travel) cur = Move{{pt(x, y)}, false}, in_travel = true;
            cur.points.push_back(pt(nx, ny));
        }
        x = nx, y = ny;
        if (has_e) e = ne;
    }
    return layers;
}

std::string slice(const fs::path& stl, const std::string& name, const std::string& options) {
    const fs::path gcode = scratch() / name;
    const CarveRun r =
        run_carve("slice " + stl.string() + " -o " + gcode.string() + " -q " + options);
    EXPECT_EQ(r.status, 0) << r.err;
    return gcode.string();
}

// The model's footprint in bed coordinates: carve centres the model's box on the 250 x 210 bed.
Paths footprint(const Paths& model, const BBox2& box) {
    const Coord dx = 125 * kMm - (box.min_x + box.max_x) / 2;
    const Coord dy = 105 * kMm - (box.min_y + box.max_y) / 2;
    Paths out = model;
    for (Path& p : out)
        for (Point& q : p) q.X += dx, q.Y += dy;
    return out;
}

// The skirt lies outside the part by design, and the travel from it into the part leaves it
// retracted: the runs that count the part's own travels print none.
constexpr const char* kNoSkirt = " --skirts 0";

TEST(TravelRun, CShapeCombsInsideAndNeverRetracts) {
    std::vector<Triangle> t;
    add_box(t, 0, 0, 0, 6, 30, 10);
    add_box(t, 0, 0, 0, 30, 6, 10);
    add_box(t, 0, 24, 0, 30, 30, 10);
    const fs::path stl = write_stl("c.stl", t);
    const Paths part = footprint(c_shape(), bounds(c_shape()));
    for (const char* mode : {"all", "off"}) {
        const auto layers = read_moves(slice(stl, std::string("c_") + mode + ".gcode",
                                             std::string("--combing ") + mode + kNoSkirt));
        ASSERT_GT(layers.size(), 40u);
        int retracted = 0;
        double outside = 0;
        for (const auto& [index, l] : layers)
            for (const Move& m : l.travels) {
                if (index == 0 && &m == &l.travels.front()) continue;  // from the home position
                retracted += m.retracted;
                for (const Path& p : clip_lines_outside(Paths{m.points}, part))
                    outside += length(Paths{p}, false) / kMm;
            }
        if (std::string(mode) == "all") {
            // One island per layer: nothing ever needs to leave it.
            EXPECT_EQ(retracted, 0);
            EXPECT_LT(outside, 0.01);
        } else {
            // Straight travels cross the mouth of the C, retracted: what combing removes.
            EXPECT_GT(retracted, 20);
            EXPECT_GT(outside, 100.0);
        }
    }
}

// A part narrowing upwards in steps: where a layer below ended outside the next layer's comb
// region, on what is now the top of the part, the travel into the next layer moves in over that
// top and combs; nothing retracts, one island per layer.
TEST(TravelRun, StepsInwardsEnterTheNextLayerWithoutRetracting) {
    std::vector<Triangle> t;
    for (int k = 0; k < 4; ++k) {
        const double in = 1.8 * k;
        add_box(t, in, in, 3.0 * k, 24 - in, 24 - in, 3.0 * (k + 1) + (k < 3 ? 0.1 : 0));
    }
    const fs::path stl = write_stl("steps.stl", t);
    const auto layers = read_moves(slice(stl, "steps.gcode", kNoSkirt));
    ASSERT_GT(layers.size(), 50u);
    int retracted = 0, entries = 0;
    for (const auto& [index, l] : layers)
        for (const Move& m : l.travels) {
            if (index == 0 && &m == &l.travels.front()) continue;  // from the home position
            retracted += m.retracted;
            entries += &m == &l.travels.front();
        }
    EXPECT_GT(entries, 20);
    EXPECT_EQ(retracted, 0);
}

TEST(TravelRun, TwoIslandsRetractOnlyToLeaveAnIsland) {
    std::vector<Triangle> t;
    add_box(t, 0, 0, 0, 12, 12, 8);
    add_box(t, 32, 0, 0, 44, 12, 8);
    const fs::path stl = write_stl("two.stl", t);
    const Paths model =
        unite(rect(0, 0, 12 * kMm, 12 * kMm), rect(32 * kMm, 0, 44 * kMm, 12 * kMm));
    const Paths part = footprint(model, bounds(model));
    const auto layers = read_moves(slice(stl, "two.gcode", kNoSkirt));
    ASSERT_GT(layers.size(), 30u);
    for (const auto& [index, l] : layers) {
        int leaving = 0;
        for (const Move& m : l.travels) {
            if (index == 0 && &m == &l.travels.front()) continue;
            double outside = 0;
            for (const Path& p : clip_lines_outside(Paths{m.points}, part))
                outside += length(Paths{p}, false) / kMm;
            if (m.retracted) {
                ++leaving;
                // Leaves once, across the 20 mm gap only.
                EXPECT_LT(outside, 20.5) << "layer " << index;
            } else {
                EXPECT_LT(outside, 0.01) << "layer " << index;  // an unretracted travel is inside
            }
        }
        // Each island printed whole before the other: one crossing, and at most one more into
        // the layer.
        EXPECT_GE(leaving, 1) << "layer " << index;
        EXPECT_LE(leaving, 2) << "layer " << index;
    }
}

// Islands whose facing sides are close while the order that a nearest-start rule gives, or the
// layer's corner, leads across a wide gap (issue #18): a bar with a post above each end (gaps
// 5 mm, the posts 30 mm apart), and four squares in an L whose narrowest gaps are 4, 4 and
// 7.2 mm, corner to corner. Each layer crosses only the narrowest gaps, once each, and starts in
// the island where the layer below ended, so the travel into it stays inside. Before, bar: up
// to 34 mm outside a layer and 922 mm over the layers above the first; L: 39 and 1,091.
TEST(TravelRun, IslandsAreJoinedAcrossTheirNarrowestGaps) {
    struct Case {
        const char* name;
        std::vector<std::array<float, 4>> boxes;  // x0, y0, x1, y1 (mm), 8 mm tall
        double gaps_mm;                           // the shortest way through all of them
    };
    const Case cases[] = {
        {"bar", {{0, 0, 40, 5}, {0, 10, 5, 15}, {35, 10, 40, 15}}, 10.0},
        {"ell",
         {{0, 0, 10, 10}, {14, 0, 24, 10}, {14, 14, 24, 24}, {0, 30, 10, 40}},
         8.0 + std::hypot(4.0, 6.0)},
    };
    for (const Case& c : cases) {
        std::vector<Triangle> t;
        Paths model;
        for (const auto& b : c.boxes) {
            add_box(t, b[0], b[1], 0, b[2], b[3], 8);
            model = unite(model, rect(Coord(b[0] * kMm), Coord(b[1] * kMm), Coord(b[2] * kMm),
                                      Coord(b[3] * kMm)));
        }
        const fs::path stl = write_stl(std::string(c.name) + ".stl", t);
        const Paths part = footprint(model, bounds(model));
        const auto layers = read_moves(slice(stl, std::string(c.name) + ".gcode", ""));
        ASSERT_GT(layers.size(), 30u) << c.name;
        for (const auto& [index, l] : layers) {
            if (index == 0) continue;  // from the home position
            double outside = 0;
            int leaving = 0;
            for (const Move& m : l.travels) {
                for (const Path& p : clip_lines_outside(Paths{m.points}, part))
                    outside += length(Paths{p}, false) / kMm;
                leaving += m.retracted;
            }
            EXPECT_LT(outside, c.gaps_mm + 0.5) << c.name << " layer " << index;
            // One crossing per gap, none into the layer.
            EXPECT_EQ(leaving, int(c.boxes.size()) - 1) << c.name << " layer " << index;
        }
    }
}

// Largest distance between two seams of the outer wall over the layers.
double seam_spread(const std::map<int, LayerMoves>& layers) {
    std::vector<Point> seams;
    for (const auto& [index, l] : layers)
        if (!l.seams.empty()) seams.push_back(l.seams.front());
    double spread = 0;
    for (const Point& a : seams)
        for (const Point& b : seams) spread = std::max(spread, dist(a, b));
    return spread / kMm;
}

TEST(TravelRun, AlignedSeamsFormOneLineOnACylinderAndABox) {
    std::vector<Triangle> cyl, box;
    add_cylinder(cyl, 10, 8, 96);
    add_box(box, 0, 0, 0, 20, 14, 8);
    for (const auto& [name, tri] : {std::pair{"cyl", &cyl}, std::pair{"box", &box}}) {
        const fs::path stl = write_stl(std::string(name) + ".stl", *tri);
        const auto aligned = read_moves(slice(stl, std::string(name) + "_a.gcode", ""));
        ASSERT_GT(aligned.size(), 30u);
        // Within a line width from layer to layer.
        EXPECT_LT(seam_spread(aligned), 0.4) << name;
        const auto random = read_moves(slice(stl, std::string(name) + "_r.gcode", "--seam random"));
        EXPECT_GT(seam_spread(random), 5.0) << name;
    }
}

}  // namespace

namespace {

double header_number(const std::string& gcode, const std::string& key) {
    const size_t at = gcode.find("; " + key + " = ");
    return at == std::string::npos ? -1 : std::stod(gcode.substr(at + key.size() + 5));
}

TEST(TravelRun, HeaderCountsTheTravelWrittenAndEveryRetraction) {
    std::vector<Triangle> t;
    add_box(t, 0, 0, 0, 12, 12, 6);
    add_box(t, 32, 0, 0, 44, 12, 6);
    const fs::path stl = write_stl("two_h.stl", t);
    for (const char* options : {"", " --wipe", " --firmware-retraction", " --combing off"}) {
        const std::string g = read(slice(stl, "two_h.gcode", options));
        // Every G0 (and wipe) move, summed, is the travel the header states.
        double travel = 0, x = 0, y = 0, e = 0;
        int e_retractions = 0, g10 = 0, g11 = 0, wipes = 0;
        bool in_wipe = false, wipe_retracted = false;
        std::istringstream in(g);
        std::string line;
        while (std::getline(in, line)) {
            if (line == ";WIPE_START") in_wipe = true, wipe_retracted = false, ++wipes;
            if (line == ";WIPE_END") {
                in_wipe = false;
                if (wipe_retracted) ++e_retractions;
            }
            if (line.rfind("G10", 0) == 0) ++g10;
            if (line.rfind("G11", 0) == 0) ++g11;
            if (line.rfind("G92 E0", 0) == 0) e = 0;  // each layer's end
            if (line.rfind("G0 ", 0) != 0 && line.rfind("G1 ", 0) != 0) continue;
            std::istringstream ss(line.substr(0, line.find(';')).substr(3));
            std::string w;
            double nx = x, ny = y, ne = e;
            bool has_e = false;
            while (ss >> w) {
                const double v = std::stod(w.substr(1));
                if (w[0] == 'X') nx = v;
                if (w[0] == 'Y') ny = v;
                if (w[0] == 'E') ne = v, has_e = true;
            }
            const bool moves = nx != x || ny != y;
            if (moves && (!has_e || ne < e)) travel += std::hypot(nx - x, ny - y);
            if (has_e && ne < e) {
                if (in_wipe)
                    wipe_retracted = true;
                else
                    ++e_retractions;
            }
            x = nx, y = ny;
            if (has_e) e = ne;
        }
        const int retractions = int(header_number(g, "retractions"));
        EXPECT_NEAR(travel, header_number(g, "travel [mm]"), 0.1 + 1e-4 * travel) << options;
        EXPECT_GT(retractions, 0) << options;
        if (std::string(options) == " --firmware-retraction") {
            EXPECT_EQ(g10, retractions);
            EXPECT_EQ(g11, retractions - 1);  // the last one, at the end, is not undone
            EXPECT_EQ(e_retractions, 0);
        } else {
            EXPECT_EQ(g10, 0);
            EXPECT_EQ(e_retractions, retractions) << options;
        }
        if (std::string(options) == " --wipe") {
            // The first retraction, before the travel to the first line, has nothing printed
            // behind it to wipe over.
            EXPECT_EQ(wipes, retractions - 1);
        }
        if (std::string(options) == " --combing off") {
            // Without combing every travel over 2 mm retracts: many more than one per island.
            EXPECT_GT(retractions, 60);
        } else {
            EXPECT_LE(retractions, 2 * 30 + 1);  // 30 layers: at most two leavings each
        }
    }
}

}  // namespace

// Ribs under what would hang (supports/ribs.hpp): on constructed slices (a flat ceiling over a
// cavity too wide to bridge), and end to end through the carve executable, judged by the
// G-code check.
#include "supports/ribs.hpp"

#include <gtest/gtest.h>

#include <array>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"
#include "support/carve_run.hpp"
#include "support/models.hpp"
#include "support/shapes.hpp"
#include "support/stl_boxes.hpp"

using namespace carve;
using carve::test::rect_region;

namespace {

constexpr Coord kMm = 1000;

RibOptions options() {
    RibOptions o;
    o.line_width = 400;
    o.lean = 200;
    o.reach = 1600;
    o.spacing = 2600;
    o.piece = 800;
    o.attract = 3 * o.spacing;
    o.vaults.enabled = false;  // the ribs alone; the vaults' tests turn them on
    return o;
}

RibOptions with_vaults() {
    RibOptions o = options();
    o.vaults.enabled = true;
    o.vaults.line_width = o.line_width;
    o.vaults.lean = o.lean;
    o.vaults.hold = 1838;  // the lattice cell's half diagonal
    o.vaults.wide = 1300;
    o.vaults.rib_spacing = o.spacing;
    o.vaults.rib_piece = o.piece;
    return o;
}

// A 30 mm box: solid bottom layers 0 and 1, a 28 mm cavity from layer 2 to `top` - 1, and a
// solid ceiling at `top`.
LayerRecord box_layer(int i, int top) {
    LayerPartition l;
    l.index = i;
    l.outline = rect_region(0, 0, 30 * kMm, 30 * kMm);
    if (i >= 2 && i < top) l.cavities = {rect_region(kMm, kMm, 29 * kMm, 29 * kMm)};
    return l;
}

// What a layer prints: everything but its cavities less half a line width, plus its ribs.
Paths printed(const LayerRecord& l) {
    Paths empty;
    for (const Paths& c : l.bridged.cavities) empty = unite(empty, erode(c, 200));
    Paths p = subtract(l.partition().outline, empty);
    if (!l.ribs.lines.empty()) p = unite(p, dilate_lines(l.ribs.lines, 200));
    if (!l.ribs.vaults.empty()) p = unite(p, dilate_lines(l.ribs.vaults, 200));
    return p;
}

// Zero inside the region, else the distance to its boundary.
double distance_to(const Point& q, const Paths& region) {
    return point_in_region(q, region) ? 0 : test::distance_to_boundary(q, region);
}

Point middle(const Path& l) {
    return Point((l.front().X + l.back().X) / 2, (l.front().Y + l.back().Y) / 2);
}

// Points every `step` along a segment, from its first point to (within a step of) its last.
std::vector<Point> along(const Path& segment, double step) {
    std::vector<Point> out;
    const double len = distance(segment.front(), segment.back());
    for (double s = 0; s <= len; s += step) {
        const double f = len > 0 ? s / len : 0;
        out.emplace_back(
            segment.front().X + Coord(f * double(segment.back().X - segment.front().X)),
            segment.front().Y + Coord(f * double(segment.back().Y - segment.front().Y)));
    }
    return out;
}

// How many points of a 0.25 mm grid over the 30 mm box lie more than 2 mm from `below`.
int far_from(const Paths& below) {
    int far = 0;
    for (Coord y = 0; y <= 30 * kMm; y += 250)
        for (Coord x = 0; x <= 30 * kMm; x += 250)
            if (distance_to(Point(x, y), below) > 2.0 * kMm) ++far;
    return far;
}

std::vector<LayerRecord> planned_box(int top, const RibOptions& o) {
    std::vector<LayerRecord> layers;
    for (int i = 0; i <= top; ++i) layers.push_back(box_layer(i, top));
    RibPlanner planner(o);
    for (int i = top; i >= 0; --i) layers[size_t(i)].ribs = planner.add(layers[size_t(i)]);
    return layers;
}

}  // namespace

TEST(Ribs, WideCeilingIsHeldWithinTwoMillimetres) {
    const int top = 60;
    const std::vector<LayerRecord> layers = planned_box(top, options());
    ASSERT_FALSE(layers[top - 1].ribs.lines.empty());
    // Every point of the ceiling lies within 2 mm of what the layer below prints.
    const Paths below = printed(layers[top - 1]);
    EXPECT_EQ(far_from(below), 0);
    // Without ribs the middle of the ceiling is 14 mm from the walls.
    RibOptions off = options();
    off.enabled = false;
    const std::vector<LayerRecord> bare = planned_box(top, off);
    EXPECT_TRUE(bare[top - 1].ribs.lines.empty());
    EXPECT_GT(distance_to(Point(15 * kMm, 15 * kMm), printed(bare[top - 1])), 10.0 * kMm);
}

TEST(Ribs, EachPieceStandsWithinTheLeanOfTheLayerBelow) {
    const int top = 60;
    const RibOptions o = options();
    const std::vector<LayerRecord> layers = planned_box(top, o);
    int pieces = 0;
    for (int i = top - 1; i >= 1; --i) {
        const LayerRecord& here = layers[size_t(i)];
        const LayerRecord& below = layers[size_t(i - 1)];
        Paths solid_below = subtract(below.partition().outline, [&] {
            Paths e;
            for (const Paths& c : below.bridged.cavities) e = unite(e, erode(c, 200));
            return e;
        }());
        for (const Path& piece : here.ribs.lines) {
            ++pieces;
            EXPECT_GE(length(Paths{piece}, false), double(o.line_width));
            // The rib's point on this layer: within r of its point on the layer below, or of
            // what that layer prints solid.
            const Point m = middle(piece);
            double best = distance_to(m, solid_below);
            for (const Path& p : below.ribs.lines) best = std::min(best, distance(m, middle(p)));
            EXPECT_LE(best, double(o.lean) + 2.0) << "layer " << i;
            // Where it stands on the solid below, the whole piece does, not its middle alone.
            if (distance_to(m, solid_below) <= double(o.lean) + 2.0) {
                EXPECT_LE(distance_to(piece.front(), solid_below), double(o.lean) + 2.0);
                EXPECT_LE(distance_to(piece.back(), solid_below), double(o.lean) + 2.0);
            }
        }
    }
    EXPECT_GT(pieces, 0);
    // Every rib stands on something: nothing is left on the bottom cover's layers.
    EXPECT_TRUE(layers[1].ribs.lines.empty());
    EXPECT_TRUE(layers[0].ribs.lines.empty());
}

// Issue #23: the ribs under a wide flat ceiling merge in pairs going down, as lightning
// infill's trees do. Each leaning towards its nearest other, the lattice's ties made them chase
// one another in rows and never meet: the flat box printed some 22,000 pieces.
TEST(Ribs, LatticeUnderAFlatCeilingMergesGoingDown) {
    const int top = 60;
    const std::vector<LayerRecord> layers = planned_box(top, options());
    const size_t first = layers[top - 1].ribs.lines.size();
    ASSERT_GT(first, 50u);
    // Two ribs 2.6 mm apart meet in some 6 layers: after 20, two halvings at least.
    EXPECT_LE(layers[top - 21].ribs.lines.size() * 4, first)
        << first << " -> " << layers[top - 21].ribs.lines.size();
    for (int i = top - 2; i >= 0; --i)
        EXPECT_LE(layers[size_t(i)].ribs.lines.size(), layers[size_t(i + 1)].ribs.lines.size())
            << i;
}

TEST(Ribs, UnheldCeilingIsCountedHeldByRibs) {
    const int top = 30;
    std::vector<LayerRecord> layers;
    for (int i = 0; i <= top; ++i) layers.push_back(box_layer(i, top));
    layers[top].bridged.unheld.push_back({rect_region(kMm, kMm, 29 * kMm, 29 * kMm), true});
    RibPlanner planner(options());
    for (int i = top; i >= 0; --i) layers[size_t(i)].ribs = planner.add(layers[size_t(i)]);
    EXPECT_EQ(layers[top - 1].ribs.minima_held, 1);
    EXPECT_EQ(layers[top - 1].ribs.ceilings_held, 1);
}

// End to end: a flat 40 x 40 x 10 mm box carved whole under its top, whose ceiling no bridge
// of 10 mm spans. The G-code check finds nothing hanging inside, and no minimum is left
// unsupported; without ribs the middle of the ceiling hangs.
TEST(Ribs, FlatBoxCeilingHeldEndToEnd) {
    std::vector<test::StlTriangle> t;
    test::add_box(t, 0, 0, 0, 40, 40, 10);
    const auto stl = test::write_stl("flat_box.stl", t);
    auto run = [&](const std::string& extra) {
        const auto gcode = test::scratch() / "flat_box.gcode";
        const auto stats = test::scratch() / "flat_box.json";
        const test::CarveRun r = test::run_carve(
            "slice " + stl.string() + " -o " + gcode.string() + " --stats " + stats.string() +
            " --stats-check --whole-width 40 --whole-width-max 40 " + extra);
        EXPECT_EQ(r.status, 0) << r.err;
        return nlohmann::json::parse(test::read(stats));
    };
    const nlohmann::json with = run("");
    EXPECT_LT(with["check"]["hanging_inside_mm2"].get<double>(), 1.0);
    EXPECT_EQ(with["minima_unsupported"].get<int>(), 0);
    EXPECT_GT(with["material_by_feature"]["ribs_mm3"].get<double>(), 0);
    const nlohmann::json without = run("--rib-reach 0");
    EXPECT_GT(without["check"]["hanging_inside_mm2"].get<double>(), 10.0);
    EXPECT_GT(without["minima_unsupported"].get<int>(), 0);
    EXPECT_EQ(without["material_by_feature"]["ribs_mm3"].get<double>(), 0);
}

// Issue 48: a void that starts as a pinhole inside the hollow (an inverted pyramid, apex at
// z 15, in a 40 mm box) prints its first wall loops on the covers under it, not over the
// cavity: 0.69 mm2 hung inside before the interior beside a hole narrower than a line was
// left to the covers.
TEST(Ribs, AVoidStartingAsAPinholeStandsOnItsCovers) {
    std::vector<test::StlTriangle> t;
    test::add_box(t, 0, 0, 0, 40, 40, 30);
    const std::array<float, 3> apex{20, 20, 15};
    const std::array<std::array<float, 3>, 4> top{
        {{16, 16, 25}, {24, 16, 25}, {24, 24, 25}, {16, 24, 25}}};
    // Facing into the void (away from the material round it).
    for (size_t i = 0; i < 4; ++i) t.push_back({apex, top[i], top[(i + 1) % 4]});
    t.push_back({top[0], top[2], top[1]});
    t.push_back({top[0], top[3], top[2]});
    const auto stl = test::write_stl("pinhole_void.stl", t);
    const auto gcode = test::scratch() / "pinhole_void.gcode";
    const auto stats = test::scratch() / "pinhole_void.json";
    const test::CarveRun r = test::run_carve("slice " + stl.string() + " -o " + gcode.string() +
                                             " --stats " + stats.string() + " --stats-check");
    ASSERT_EQ(r.status, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(test::read(stats));
    EXPECT_LT(j["check"]["hanging_inside_mm2"].get<double>(), 0.05);
}

// End to end on the report's figure-3 cube (its indented top makes the report's tear run fast):
// at the defaults nothing hangs, inside or out, and no minimum is left unsupported.
TEST(Ribs, FigureThreeCubeHeldEndToEnd) {
    CARVE_NEED_MODEL("synthetic/fig3_cube_indent.stl");
    const auto gcode = test::scratch() / "fig3.gcode";
    const auto stats = test::scratch() / "fig3.json";
    const test::CarveRun r =
        test::run_carve("slice " + test::any_model("synthetic/fig3_cube_indent.stl") + " -o " +
                        gcode.string() + " --stats " + stats.string() + " --stats-check");
    ASSERT_EQ(r.status, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(test::read(stats));
    EXPECT_LT(j["check"]["hanging_inside_mm2"].get<double>(), 0.01);
    EXPECT_LT(j["check"]["far_unsupported_area_mm2"].get<double>(), 0.01);
    EXPECT_EQ(j["minima_unsupported"].get<int>(), 0);
}

// Issue #35: no rib is a free-standing strand. On every layer each rib's piece is joined to the
// wall by its tie, directly or through the ties of ribs nearer the wall: what the ribs print,
// united with the layer's solid part, has no piece of its own.
TEST(Ribs, EveryRibIsJoinedToTheWallInEveryLayer) {
    const int top = 60;
    const RibOptions o = options();
    const std::vector<LayerRecord> layers = planned_box(top, o);
    auto outers = [](const Paths& region) {
        int n = 0;
        for (const Path& p : region) n += area(p) > 0;
        return n;
    };
    int tied = 0;
    for (int i = top - 1; i >= 2; --i) {
        const LayerRecord& l = layers[size_t(i)];
        Paths lines = l.ribs.lines;
        lines.insert(lines.end(), l.ribs.ties.begin(), l.ribs.ties.end());
        if (lines.empty()) continue;
        tied += static_cast<int>(l.ribs.ties.size());
        Paths empty;
        for (const Paths& c : l.bridged.cavities) empty = unite(empty, erode(c, o.line_width / 2));
        const Paths solid = subtract(l.partition().outline, empty);
        const Paths all = unite(solid, dilate_lines(lines, o.line_width / 2 + 1));
        EXPECT_EQ(outers(all), outers(solid)) << "layer " << i << ": a rib stands alone";
    }
    EXPECT_GT(tied, 100);
}

// And every tie stands on the layer below: no point of it further than 2 mm (what `carve check`
// counts as hanging) from what that layer prints, ribs and ties included.
TEST(Ribs, EveryTieStandsOnTheLayerBelow) {
    const int top = 60;
    const RibOptions o = options();
    const std::vector<LayerRecord> layers = planned_box(top, o);
    for (int i = top - 1; i >= 3; --i) {
        const LayerRecord& here = layers[size_t(i)];
        const LayerRecord& below = layers[size_t(i - 1)];
        Paths below_lines = below.ribs.lines;
        below_lines.insert(below_lines.end(), below.ribs.ties.begin(), below.ribs.ties.end());
        Paths held = printed(below);
        if (!below_lines.empty()) held = unite(held, dilate_lines(below_lines, o.line_width / 2));
        for (const Path& t : here.ribs.ties) {
            for (const Point& q : along(t, 200))
                EXPECT_LE(distance_to(q, held), 2.0 * kMm) << "layer " << i;
        }
    }
}

// Issue #35, end to end on the shapes it names: a wide flat ceiling, a dome and a tall box with
// a shelf high inside print with no thin interior column over 5 mm, skins closed and nothing
// hanging inside, as `carve check --mesh` (through --stats-check) measures the G-code.
TEST(Ribs, SyntheticShapesPrintTheFirstTime) {
    struct Shape {
        const char* name;
        std::vector<test::StlTriangle> t;
    };
    std::vector<Shape> shapes(3);
    shapes[0].name = "flat_ceiling";
    test::add_box(shapes[0].t, 0, 0, 0, 60, 60, 12);
    shapes[1].name = "dome";
    test::add_cut_ball(shapes[1].t, 25, 0, 24, 48);
    // A 30 mm box 40 mm tall with a 20 mm pocket from the top whose floor, 30 mm up, is the
    // ceiling of the interior: four walls overlapping the base (non-zero fill unites them).
    shapes[2].name = "tall_shelf";
    test::add_box(shapes[2].t, 0, 0, 0, 30, 30, 30.5f);
    test::add_box(shapes[2].t, 0, 0, 30, 5, 30, 40);
    test::add_box(shapes[2].t, 25, 0, 30, 30, 30, 40);
    test::add_box(shapes[2].t, 4, 0, 30, 26, 5, 40);
    test::add_box(shapes[2].t, 4, 25, 30, 26, 30, 40);
    for (const Shape& s : shapes) {
        const auto stl = test::write_stl(std::string(s.name) + ".stl", s.t);
        const auto gcode = test::scratch() / (std::string(s.name) + ".gcode");
        const auto stats = test::scratch() / (std::string(s.name) + ".json");
        const test::CarveRun r =
            test::run_carve("slice " + stl.string() + " -o " + gcode.string() + " --stats " +
                            stats.string() + " --stats-check -q");
        ASSERT_EQ(r.status, 0) << s.name << ": " << r.err;
        const nlohmann::json p = nlohmann::json::parse(test::read(stats))["check"]["printability"];
        EXPECT_EQ(p["columns"]["over_5mm"].get<int>(), 0)
            << s.name << ": tallest " << p["columns"]["tallest"].dump();
        EXPECT_LE(p["top_skin"]["open_percent"].get<double>(), 0.25) << s.name;
        EXPECT_LE(p["bottom_skin"]["open_percent"].get<double>(), 0.25) << s.name;
        EXPECT_EQ(p["top_skin"]["holes_1mm2"].get<int>(), 0) << s.name;
        EXPECT_EQ(p["bottom_skin"]["holes_1mm2"].get<int>(), 0) << s.name;
        EXPECT_LE(p["hanging_inside_mm2"].get<double>(), 1.0) << s.name;
        EXPECT_TRUE(p["passes"].get<bool>()) << s.name << ": " << p["failed_rules"].dump();
    }
}

// Issue #38: under a wide ceiling the pairing thins the lattice until its ribs stand further
// apart than tie() looked (two spacings); each then printed a tie to the wall on every layer,
// across the cavity and the ribs between (a 1000 mm cube ran past 300 s). Far from the walls
// a rib is tied to the nearest rib nearer the wall however far: the ties stay short, every rib
// is still joined to the wall through them, and each tie stands on the layer below.
TEST(Ribs, TiesStayShortUnderAWideCeiling) {
    const int top = 60;
    const RibOptions o = options();
    const Coord size = 100 * kMm;
    std::vector<LayerRecord> layers;
    for (int i = 0; i <= top; ++i) {
        LayerPartition l;
        l.index = i;
        l.outline = rect_region(0, 0, size, size);
        if (i >= 2 && i < top) l.cavities = {rect_region(kMm, kMm, size - kMm, size - kMm)};
        layers.push_back(l);
    }
    RibPlanner planner(o);
    for (int i = top; i >= 0; --i) layers[size_t(i)].ribs = planner.add(layers[size_t(i)]);
    double longest = 0;
    int ties = 0;
    for (int i = top - 1; i >= 2; --i) {
        const LayerRecord& l = layers[size_t(i)];
        for (const Path& t : l.ribs.ties)
            longest = std::max(longest, distance(t.front(), t.back()));
        ties += static_cast<int>(l.ribs.ties.size());
        Paths lines = l.ribs.lines;
        lines.insert(lines.end(), l.ribs.ties.begin(), l.ribs.ties.end());
        if (lines.empty() || i % 6 != 0) continue;  // every sixth layer: the test stays quick
        Paths empty;
        for (const Paths& c : l.bridged.cavities) empty = unite(empty, erode(c, o.line_width / 2));
        const Paths solid = subtract(l.partition().outline, empty);
        const Paths all = unite(solid, dilate_lines(lines, o.line_width / 2 + 1));
        int outers = 0;
        for (const Path& p : all) outers += area(p) > 0;
        EXPECT_EQ(outers, 1) << "layer " << i << ": a rib stands alone";
        if (i < 3) continue;
        const LayerRecord& below = layers[size_t(i - 1)];
        Paths below_lines = below.ribs.lines;
        below_lines.insert(below_lines.end(), below.ribs.ties.begin(), below.ribs.ties.end());
        Paths held = printed(below);
        if (!below_lines.empty()) held = unite(held, dilate_lines(below_lines, o.line_width / 2));
        for (const Path& t : l.ribs.ties) {
            for (const Point& q : along(t, 400))
                EXPECT_LE(distance_to(q, held), 2.0 * kMm) << "layer " << i;
        }
    }
    EXPECT_GT(ties, 500);
    // Within four cells of two spacings of a wall a rib is tied to it, as before: 21 mm.
    EXPECT_LT(longest, 25.0 * kMm);
}

namespace {

// What a layer prints solid: its outline less its cavities less half a line.
Paths solid_of(const LayerRecord& l, Coord w) {
    Paths empty;
    for (const Paths& c : l.bridged.cavities) empty = unite(empty, erode(c, w / 2));
    return subtract(l.partition().outline, empty);
}

// All the ribs print over the layers, mm: their pieces, ties and vault lines.
double printed_length(const std::vector<LayerRecord>& layers) {
    double total = 0;
    for (const LayerRecord& l : layers)
        total +=
            length(l.ribs.lines, false) + length(l.ribs.ties, false) + length(l.ribs.vaults, false);
    return total / kMm;
}

}  // namespace

// Under the flat box's 28 mm ceiling the planner prints vault lines: every point of the ceiling
// is within 2 mm of what the layer below prints, and the ribs' lattice of pieces and ties is
// replaced by less line (0.77 of it here, 5.7 against 7.4 m).
TEST(Vaults, HoldAWideCeilingWithLessThanTheRibs) {
    const int top = 60;
    const std::vector<LayerRecord> layers = planned_box(top, with_vaults());
    ASSERT_FALSE(layers[top - 1].ribs.vaults.empty());
    const Paths below = printed(layers[top - 1]);
    EXPECT_EQ(far_from(below), 0);
    const double vaults = printed_length(layers);
    const double ribs = printed_length(planned_box(top, options()));
    EXPECT_LT(vaults, 0.8 * ribs) << vaults << " mm against the ribs' " << ribs;
}

// No vault line is a free-standing strand: on every layer both its ends lie half a line deep in
// what the layer prints solid (the cavity's wall), and every point of it lies within the lean of a
// vault line of the layer below or of that layer's solid.
TEST(Vaults, EveryLineRunsWallToWallAndStandsOnTheLayerBelow) {
    const int top = 60;
    const RibOptions o = with_vaults();
    const std::vector<LayerRecord> layers = planned_box(top, o);
    int lines = 0;
    for (int i = top - 1; i >= 2; --i) {
        const LayerRecord& here = layers[size_t(i)];
        const LayerRecord& below = layers[size_t(i - 1)];
        const Paths solid = solid_of(here, o.line_width);
        const Paths solid_below = solid_of(below, o.line_width);
        for (const Path& v : here.ribs.vaults) {
            ++lines;
            ASSERT_GE(v.size(), 2u);
            // Carried half a line into the wall, so that the two fuse.
            for (const Point& end : {v.front(), v.back()}) {
                EXPECT_TRUE(point_in_region(end, solid)) << "layer " << i;
                EXPECT_GE(test::distance_to_boundary(end, solid), o.line_width / 2 - 2.0)
                    << "layer " << i;
            }
            for (const Point& q : along(v, 500)) {
                const double d = std::min(distance_to(q, solid_below),
                                          test::distance_to_lines(q, below.ribs.vaults));
                EXPECT_LE(d, double(o.lean) + 2.0) << "layer " << i;
            }
        }
    }
    EXPECT_GT(lines, 20);
}

// Going down the lines lean together and merge in pairs: never more lines than the layer
// above, and after 30 layers at most half of those under the ceiling.
TEST(Vaults, LinesMergeGoingDown) {
    const int top = 60;
    const std::vector<LayerRecord> layers = planned_box(top, with_vaults());
    const size_t first = layers[top - 1].ribs.vaults.size();
    ASSERT_GE(first, 6u);
    for (int i = top - 2; i >= 0; --i)
        EXPECT_LE(layers[size_t(i)].ribs.vaults.size(), layers[size_t(i + 1)].ribs.vaults.size())
            << i;
    EXPECT_LE(layers[top - 31].ribs.vaults.size() * 2, first)
        << first << " -> " << layers[top - 31].ribs.vaults.size();
}

// Off (--vault-width 0), the planner prints the ribs alone.
TEST(Vaults, OffMeansRibsAlone) {
    const std::vector<LayerRecord> layers = planned_box(30, options());
    size_t ribs = 0;
    for (const LayerRecord& l : layers) {
        EXPECT_TRUE(l.ribs.vaults.empty());
        ribs += l.ribs.lines.size();
    }
    EXPECT_GT(ribs, 0u);
}

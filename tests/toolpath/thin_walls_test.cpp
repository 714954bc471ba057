// Thin walls (issue #47): every part of a slice at least 0.2 mm wide is printed, as one bead
// along its middle as wide as the part where two lines do not fit; what is narrower than
// --min-feature-size is reported. thin_walls() on slices built here, then whole runs of carve
// on fins, a thin vase and lettering, judged from the G-code by `carve check --mesh`.
#include "toolpath/thin_walls.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"
#include "support/carve_run.hpp"
#include "support/stl_boxes.hpp"

namespace carve {
namespace {

Path rect(double x0, double y0, double x1, double y1) {
    return Path{Point(to_units(x0), to_units(y0)), Point(to_units(x1), to_units(y0)),
                Point(to_units(x1), to_units(y1)), Point(to_units(x0), to_units(y1))};
}

// A 20 x 10 mm body with a fin `width` wide standing 20 mm out of its top edge.
Paths body_with_fin(double width) {
    return unite(Paths{rect(0, 0, 20, 10), rect(10 - width / 2, 9.9, 10 + width / 2, 30)});
}

struct FinFigures {
    double covered = 0;  // share of the fin's length (y 10 to 30) along its beads
    double width = 0;    // the beads' mean width there, mm
};

FinFigures fin_figures(const ThinWalls& thin, const Settings& settings, double fin_width) {
    std::vector<std::pair<double, double>> spans;
    double sum = 0, len = 0;
    for (const Extrusion& e : thin.beads) {
        const double bead = settings.width_mm() * e.flow;
        for (size_t i = 0; i + 1 < e.points.size(); ++i) {
            const Point a = e.points[i], b = e.points[i + 1];
            if (std::abs(to_mm(a.X) - 10) > fin_width / 2 ||
                std::abs(to_mm(b.X) - 10) > fin_width / 2)
                continue;
            double y0 = std::clamp(to_mm(std::min(a.Y, b.Y)), 10.0, 30.0);
            double y1 = std::clamp(to_mm(std::max(a.Y, b.Y)), 10.0, 30.0);
            if (y1 <= y0) continue;
            spans.push_back({y0, y1});
            sum += bead * (y1 - y0);
            len += y1 - y0;
        }
    }
    std::sort(spans.begin(), spans.end());
    double covered = 0, end = -1;
    for (auto [a, b] : spans)
        if (b > end) covered += b - std::max(a, end), end = b;
    return {covered / 20.0, len > 0 ? sum / len : 0};
}

TEST(ThinWalls, FinsFrom0_2To0_8MmAreOneBeadAsWideAsTheFin) {
    Settings settings;
    for (double width : {0.2, 0.25, 0.3, 0.35, 0.45, 0.6, 0.7, 0.8}) {
        const Paths outline = body_with_fin(width);
        const ThinWalls thin =
            thin_walls(outline, erode(outline, settings.nozzle_radius()), settings);
        const FinFigures f = fin_figures(thin, settings, width);
        EXPECT_GE(f.covered, 0.9) << width << " mm fin";
        // Narrower than the narrowest bead: widened to it.
        const double expected = std::max(width, settings.min_bead_mm());
        EXPECT_NEAR(f.width, expected, 0.05) << width << " mm fin";
        EXPECT_DOUBLE_EQ(thin.unprinted_mm2, 0) << width << " mm fin";
        // The fin is no longer in the outer wall's loop: no line doubles back up it.
        for (const Path& p : thin.wall_region)
            for (const Point& q : p) EXPECT_LT(to_mm(q.Y), 10.25) << width << " mm fin";
    }
}

TEST(ThinWalls, PartsWideEnoughForTwoLinesKeepTheWallLoop) {
    Settings settings;
    for (double width : {1.0, 1.5}) {
        const Paths outline = body_with_fin(width);
        const Paths wall = erode(outline, settings.nozzle_radius());
        const ThinWalls thin = thin_walls(outline, wall, settings);
        EXPECT_TRUE(thin.beads.empty()) << width;
        EXPECT_NEAR(area(thin.wall_region), area(wall), 1.0) << width;
    }
    // A plain rectangle and a disk: nothing thin, the wall's region untouched.
    for (const Paths& outline :
         {Paths{rect(0, 0, 30, 20)}, dilate(Paths{Path{Point(0, 0)}}, to_units(10))}) {
        const Paths wall = erode(outline, settings.nozzle_radius());
        const ThinWalls thin = thin_walls(outline, wall, settings);
        EXPECT_TRUE(thin.beads.empty());
        EXPECT_EQ(thin.wall_region, wall);
    }
}

TEST(ThinWalls, AThinRingIsOneClosedBead) {
    Settings settings;
    const Paths ring = subtract(dilate(Paths{Path{Point(0, 0)}}, to_units(15)),
                                dilate(Paths{Path{Point(0, 0)}}, to_units(14.7)));
    const ThinWalls thin = thin_walls(ring, erode(ring, settings.nozzle_radius()), settings);
    ASSERT_FALSE(thin.beads.empty());
    double len = 0;
    for (const Extrusion& e : thin.beads) len += to_mm(Coord(length(Paths{e.points}, e.closed)));
    EXPECT_NEAR(len, 2 * 3.14159265 * 14.85, 0.05 * 2 * 3.14159265 * 14.85);
    EXPECT_TRUE(thin.wall_region.empty());
}

TEST(ThinWalls, PartsNarrowerThanTheSmallestFeatureAreReportedNotPrinted) {
    Settings settings;
    settings.min_feature_size = 0.3;
    const Paths outline = body_with_fin(0.25);
    const ThinWalls thin = thin_walls(outline, erode(outline, settings.nozzle_radius()), settings);
    EXPECT_LT(fin_figures(thin, settings, 0.25).covered, 0.1);
    EXPECT_NEAR(thin.unprinted_mm2, 0.25 * 20, 0.5);
    settings.thin_walls = 0;
    EXPECT_TRUE(
        thin_walls(outline, erode(outline, settings.nozzle_radius()), settings).beads.empty());
}

TEST(UnprintedTally, WarnsWithTheAreaAndTheLayers) {
    Settings settings;
    settings.min_feature_size = 0.1;
    UnprintedTally tally;
    tally.add(10, 2.2, 0);
    EXPECT_EQ(tally.warning(settings), "");
    tally.add(11, 2.4, 1.5);
    tally.add(20, 4.2, 1.5);
    EXPECT_DOUBLE_EQ(tally.area_mm2(), 3.0);
    EXPECT_EQ(tally.layers(), 2);
    const std::string w = tally.warning(settings);
    EXPECT_NE(w.find("3.00 mm2"), std::string::npos) << w;
    EXPECT_NE(w.find("narrower than 0.1 mm"), std::string::npos) << w;
    EXPECT_NE(w.find("layer 12 and 21"), std::string::npos) << w;
    EXPECT_NE(w.find("--min-feature-size"), std::string::npos) << w;
    // Without thin walls the wall loop decides: what is narrower than the nozzle is lost.
    settings.thin_walls = 0;
    const std::string off = tally.warning(settings);
    EXPECT_NE(off.find("narrower than 0.4 mm"), std::string::npos) << off;
    EXPECT_NE(off.find("--no-thin-walls"), std::string::npos) << off;
}

TEST(ThinWalls, WithoutThemWhatNoWallLoopReachesIsReported) {
    // A 0.3 mm fin 20 mm long on a block: no wall loop fits in it, so all of it is lost.
    Settings settings;
    settings.thin_walls = 0;
    const Paths outline = body_with_fin(0.3);
    const ThinWalls thin = thin_walls(outline, erode(outline, settings.nozzle_radius()), settings);
    EXPECT_TRUE(thin.beads.empty());
    EXPECT_NEAR(thin.unprinted_mm2, 0.3 * 20, 0.6);
    // With them the fin is printed and nothing is lost.
    settings.thin_walls = 1;
    EXPECT_DOUBLE_EQ(
        thin_walls(outline, erode(outline, settings.nozzle_radius()), settings).unprinted_mm2, 0);
}

// Whole runs: the G-code read back by `carve check --mesh`, as any slicer's is.
struct Checked {
    int status = -1;
    std::string err;
    nlohmann::json check, stats;
};

Checked slice_and_check(const std::vector<test::StlTriangle>& tris, const std::string& name,
                        const std::string& options = "") {
    const auto stl = test::write_stl(name + ".stl", tris);
    const auto gcode = test::scratch() / (name + ".gcode");
    const auto stats = test::scratch() / (name + ".json");
    Checked c;
    const test::CarveRun slice = test::run_carve("slice " + stl.string() + " -o " + gcode.string() +
                                                 " --stats " + stats.string() + " " + options);
    c.status = slice.status;
    c.err = slice.err;
    if (slice.status != 0) return c;
    c.stats = nlohmann::json::parse(test::read(stats), nullptr, false);
    const test::CarveRun check =
        test::run_carve("check " + gcode.string() + " --mesh " + stl.string() + " --json");
    c.check = nlohmann::json::parse(check.out, nullptr, false);
    return c;
}

std::vector<test::StlTriangle> fins() {
    std::vector<test::StlTriangle> t;
    test::add_box(t, 0, 0, 0, 70, 24, 2);
    const float widths[] = {0.2f, 0.25f, 0.3f, 0.35f, 0.45f, 0.6f, 0.8f, 1.0f};
    for (int k = 0; k < 8; ++k) {
        const float x = 5 + 8 * k, h = widths[k] / 2;
        test::add_box(t, x - h, 2, 1.9f, x + h, 22, 12);
    }
    return t;
}

TEST(ThinWallsRun, EveryFinIsPrintedAndCheckFindsNothingLeftOut) {
    const Checked c = slice_and_check(fins(), "fins");
    ASSERT_EQ(c.status, 0) << c.err;
    ASSERT_TRUE(c.check.contains("uncovered_mm2")) << c.check.dump().substr(0, 300);
    // Before thin walls: 296 mm2, the 0.25-0.35 mm fins on every layer.
    EXPECT_LT(c.check["uncovered_mm2"].get<double>(), 5.0);
    EXPECT_EQ(c.check["uncovered"]["wide_pieces"].get<int>(), 0);
    EXPECT_DOUBLE_EQ(c.stats["unprinted_mm2"].get<double>(), 0);
    EXPECT_EQ(c.err.find("not printed"), std::string::npos) << c.err;
}

TEST(ThinWallsRun, AThinVaseAndLetteringArePrinted) {
    std::vector<test::StlTriangle> vase;
    test::add_cylinder(vase, 15, 1, 180);
    std::vector<test::StlTriangle> inner;
    // A tube: the 0.3 mm wall of a 15 mm cylinder, as two boxes' worth of facets would not be.
    const int n = 180;
    auto at = [&](float r, int i, float z) {
        const double a = 2 * 3.14159265358979 * (i % n) / n;
        return std::array<float, 3>{float(r * std::cos(a)), float(r * std::sin(a)), z};
    };
    for (int i = 0; i < n; ++i) {
        const float ro = 15, ri = 14.7f, z0 = 0.9f, z1 = 21;
        vase.push_back({at(ro, i, z0), at(ro, i + 1, z0), at(ro, i + 1, z1)});
        vase.push_back({at(ro, i, z0), at(ro, i + 1, z1), at(ro, i, z1)});
        vase.push_back({at(ri, i, z0), at(ri, i + 1, z1), at(ri, i + 1, z0)});
        vase.push_back({at(ri, i, z0), at(ri, i, z1), at(ri, i + 1, z1)});
        vase.push_back({at(ro, i, z1), at(ro, i + 1, z1), at(ri, i + 1, z1)});
        vase.push_back({at(ro, i, z1), at(ri, i + 1, z1), at(ri, i, z1)});
        vase.push_back({at(ro, i, z0), at(ri, i + 1, z0), at(ro, i + 1, z0)});
        vase.push_back({at(ro, i, z0), at(ri, i, z0), at(ri, i + 1, z0)});
    }
    const Checked v = slice_and_check(vase, "vase");
    ASSERT_EQ(v.status, 0) << v.err;
    // Before: the wall not printed at all, 931 mm2 (21 %) uncovered.
    EXPECT_LT(v.check["uncovered_mm2"].get<double>(), 10.0);
    EXPECT_EQ(v.check.value("uncovered", nlohmann::json::object()).value("layers_above_print", 0),
              0);

    std::vector<test::StlTriangle> letters;
    test::add_box(letters, 0, 0, 0, 40, 20, 4);
    for (const auto& s : std::vector<std::array<float, 4>>{
             {8, 6, 8.3f, 14}, {12, 6, 12.3f, 14}, {8, 9.85f, 12.3f, 10.15f}, {18, 6, 18.3f, 14}})
        test::add_box(letters, s[0], s[1], 3.9f, s[2], s[3], 4.6f);
    const Checked l = slice_and_check(letters, "lettering");
    ASSERT_EQ(l.status, 0) << l.err;
    // Before: 12 mm2, the strokes' three layers not printed.
    EXPECT_LT(l.check["uncovered_mm2"].get<double>(), 1.0);
}

// A bead leaves the nozzle at a fin's tip, where the outer wall's region does not reach: the
// travel back to the body runs along the bead, not retracted through the air (fandisk went from
// 4 to 6 retractions before the beads were corridors for travel).
TEST(ThinWallsRun, TravelOffAFinStaysOnItsBeadWithoutRetracting) {
    std::vector<test::StlTriangle> t;
    test::add_box(t, 0, 0, 0, 20, 10, 6);
    test::add_box(t, 9.85f, 9.9f, 0, 10.15f, 20, 6);  // 0.3 mm, only a bead prints it
    const Checked on = slice_and_check(t, "fin_travel");
    const Checked off = slice_and_check(t, "fin_travel_off", "--no-thin-walls");
    ASSERT_EQ(on.status, 0) << on.err;
    ASSERT_EQ(off.status, 0) << off.err;
    EXPECT_LT(on.check["uncovered_mm2"].get<double>(), 1.0);
    EXPECT_GT(off.check["uncovered_mm2"].get<double>(), 50.0);  // the fin, 0.3 x 10 x 30 layers
    // One island a layer: nothing to retract for, with the bead or without it.
    EXPECT_LE(on.check["retractions"].get<int>(), off.check["retractions"].get<int>());
}

TEST(ThinWallsRun, SliceWarnsOfWhatIsTooThinToPrint) {
    const Checked c = slice_and_check(fins(), "fins_min_feature", "--min-feature-size 0.3");
    ASSERT_EQ(c.status, 0) << c.err;
    EXPECT_NE(c.err.find("narrower than 0.3 mm and is not printed"), std::string::npos) << c.err;
    // The 0.2, 0.25 and 0.3 mm fins (20 mm long) on the 50 layers between z 2 and 12.
    EXPECT_NEAR(c.stats["unprinted_mm2"].get<double>(), (0.2 + 0.25 + 0.3) * 20 * 50, 40);
    EXPECT_EQ(c.stats["unprinted_layers"].get<int>(), 50);
    // The same from a PrusaSlicer profile, its keys and its percentages of the nozzle.
    const auto ini = test::scratch() / "thin.ini";
    std::ofstream(ini) << "min_feature_size = 75%\nmin_bead_width = 85%\n";
    const Checked p = slice_and_check(fins(), "fins_profile", "--load " + ini.string());
    ASSERT_EQ(p.status, 0) << p.err;
    EXPECT_NE(p.err.find("narrower than 0.3 mm and is not printed"), std::string::npos) << p.err;
    EXPECT_DOUBLE_EQ(p.stats["unprinted_mm2"].get<double>(),
                     c.stats["unprinted_mm2"].get<double>());
}

}  // namespace
}  // namespace carve

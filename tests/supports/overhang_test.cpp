// The model's own overhang: measured per slice against the slice below, summed into the stats
// and named in a warning, end to end through the carve executable.
#include "supports/overhang.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"
#include "support/carve_run.hpp"
#include "support/shapes.hpp"
#include "support/stl_boxes.hpp"

using namespace carve;
using carve::test::rect_region;

namespace {

constexpr Coord kMm = 1000;

// A slice 20 x 10 mm over one 10 x 10 mm: the right half sticks out 10 mm.
TEST(Overhang, BeyondTheReachAndBeyondTwoMillimetres) {
    const Paths below = rect_region(0, 0, 10 * kMm, 10 * kMm);
    const Paths here = rect_region(0, 0, 20 * kMm, 10 * kMm);
    const LayerOverhang o = measure_overhang(here, &below, 200, 2 * kMm);
    EXPECT_NEAR(o.area_mm2, 9.8 * 10, 0.05);
    EXPECT_NEAR(o.far_area_mm2, 8.0 * 10, 0.05);
    // The region itself: the strip beyond x = 10.2 mm, inside the slice.
    const Paths beyond = external_overhang(here, &below, 200);
    EXPECT_NEAR(area_mm2(subtract(beyond, rect_region(10200, 0, 20 * kMm, 10 * kMm))), 0, 1e-3);
}

TEST(Overhang, BottomSliceStandsOnTheBedAndAnIslandInTheAirHangsWhole) {
    const Paths here = rect_region(0, 0, 20 * kMm, 10 * kMm);
    const LayerOverhang bed = measure_overhang(here, nullptr, 200, 2 * kMm);
    EXPECT_EQ(bed.area_mm2, 0);
    EXPECT_EQ(bed.far_area_mm2, 0);
    const Paths nothing;
    const LayerOverhang air = measure_overhang(here, &nothing, 200, 2 * kMm);
    EXPECT_NEAR(air.area_mm2, 200, 1e-6);
    EXPECT_NEAR(air.far_area_mm2, 200, 1e-6);
}

// A slope within the printer's overhang (0.15 mm per layer at 45 degrees and 0.2 mm layers) is
// no overhang, however large the slice.
TEST(Overhang, SlopeWithinTheReachIsHeld) {
    const Paths below = rect_region(0, 0, 50 * kMm, 50 * kMm);
    const LayerOverhang o = measure_overhang(dilate(below, 150), &below, 200, 2 * kMm);
    EXPECT_LT(o.area_mm2, 0.01);
    EXPECT_EQ(o.far_area_mm2, 0);
}

TEST(OverhangTally, WarnsOnlyAboveTheThresholdAndNamesTheLayers) {
    OverhangTally small(5.0);
    small.add(9, 2.0, {3.0, 3.0});
    EXPECT_DOUBLE_EQ(small.far_area_mm2(), 3.0);
    EXPECT_TRUE(small.warning().empty());

    OverhangTally tally(5.0);
    // Top down, as the pipeline delivers them: layers 12..10 hang, then one far away.
    tally.add(12, 2.6, {4.0, 3.0});
    tally.add(11, 2.4, {4.0, 3.0});
    tally.add(10, 2.2, {4.0, 3.0});
    tally.add(2, 0.6, {1.0, 0.5});
    EXPECT_DOUBLE_EQ(tally.area_mm2(), 13.0);
    EXPECT_DOUBLE_EQ(tally.far_area_mm2(), 9.5);
    const std::string w = tally.warning();
    EXPECT_NE(w.find("will hang"), std::string::npos) << w;
    EXPECT_NE(w.find("--support auto"), std::string::npos) << w;  // and what holds it
    EXPECT_NE(w.find("9.0 mm2 at layers 11-13 (z 2.20-2.60 mm)"), std::string::npos) << w;
    EXPECT_NE(w.find("0.5 mm2 at layer 3 (z 0.60 mm)"), std::string::npos) << w;
}

nlohmann::json stats_of(const std::string& path) {
    std::ifstream in(path);
    return nlohmann::json::parse(in);
}

// A mushroom: a 10 x 10 mm stem under a 30 x 30 mm cap. The cap's underside is 900 - 14 x 14 =
// 704 mm2 more than 2 mm beyond the stem (the rounded corners of the 2 mm reach add a little).
TEST(OverhangCli, MushroomCapIsMeasuredAndNamedABoxIsQuiet) {
    const auto dir = carve::test::scratch();
    std::vector<carve::test::StlTriangle> t;
    carve::test::add_box(t, 10, 10, 0, 20, 20, 10.1f);
    carve::test::add_box(t, 0, 0, 10, 30, 30, 14);
    const std::string mushroom = carve::test::write_stl("mushroom.stl", t).string();
    const std::string gcode = (dir / "mushroom.gcode").string();
    const std::string stats = (dir / "mushroom.json").string();
    auto r = carve::test::run_carve("slice " + mushroom + " -o " + gcode + " --stats " + stats);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("will hang"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("at layer 51 (z 10.20 mm)"), std::string::npos) << r.err;
    auto j = stats_of(stats);
    EXPECT_NEAR(j["far_external_overhang_mm2"].get<double>(), 704, 5);
    EXPECT_GT(j["external_overhang_mm2"].get<double>(),
              j["far_external_overhang_mm2"].get<double>());
    EXPECT_DOUBLE_EQ(j["settings"]["support_angle_deg"].get<double>(), 45.0);

    // A steeper threshold reaches further beyond the stem; the far part stays.
    r = carve::test::run_carve("slice " + mushroom + " -o " + gcode + " --stats " + stats +
                               " --support-angle 80 -q");
    ASSERT_EQ(r.status, 0) << r.err;
    auto steep = stats_of(stats);
    EXPECT_LT(steep["external_overhang_mm2"].get<double>(),
              j["external_overhang_mm2"].get<double>());
    EXPECT_NEAR(steep["far_external_overhang_mm2"].get<double>(),
                j["far_external_overhang_mm2"].get<double>(), 1e-6);

    t.clear();
    carve::test::add_box(t, 0, 0, 0, 20, 20, 10);
    const std::string box = carve::test::write_stl("box.stl", t).string();
    r = carve::test::run_carve("slice " + box + " -o " + gcode + " --stats " + stats);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.err.find("will hang"), std::string::npos) << r.err;
    EXPECT_EQ(stats_of(stats)["far_external_overhang_mm2"].get<double>(), 0);

    r = carve::test::run_carve("slice " + box + " -o " + gcode + " --support-angle 90");
    EXPECT_NE(r.status, 0);
}

}  // namespace

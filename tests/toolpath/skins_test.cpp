// Closed skins (issue #35): every up- and down-facing surface gets its covers, on slopes too.
// Whole runs of the carve executable on synthetic shapes with slopes, judged by `carve check
// --mesh` as any slicer's G-code is: the top and bottom skin left open (the region minus the
// printed footprint, opened by 0.1 mm) at most 0.25 % of the region, no hole of 1 mm2.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "support/carve_run.hpp"
#include "support/stl_boxes.hpp"

using namespace carve::test;

namespace {

struct Skins {
    double top_percent = -1, bottom_percent = -1;
    long long top_holes = -1, bottom_holes = -1;
    double material_mm3 = 0;
};

// Slices `stl` at the defaults and checks the G-code against it.
Skins sliced_skins(const std::filesystem::path& stl) {
    const auto gcode = scratch() / (stl.stem().string() + ".gcode");
    const CarveRun slice = run_carve("slice " + stl.string() + " -o " + gcode.string());
    EXPECT_EQ(slice.status, 0) << slice.err;
    const CarveRun check =
        run_carve("check " + gcode.string() + " --mesh " + stl.string() + " --json");
    EXPECT_EQ(check.status, 0) << check.err;
    Skins s;
    const nlohmann::json j = nlohmann::json::parse(check.out, nullptr, false);
    if (j.is_discarded() || !j.contains("printability")) {
        ADD_FAILURE() << "no printability figures in: " << check.out.substr(0, 400);
        return s;
    }
    const auto& p = j["printability"];
    s.top_percent = p["top_skin"]["open_percent"].get<double>();
    s.bottom_percent = p["bottom_skin"]["open_percent"].get<double>();
    s.top_holes = p["top_skin"]["holes_1mm2"].get<long long>();
    s.bottom_holes = p["bottom_skin"]["holes_1mm2"].get<long long>();
    s.material_mm3 = j["extruded_volume_mm3"].get<double>();
    return s;
}

void expect_closed(const Skins& s) {
    EXPECT_LE(s.top_percent, 0.25);
    EXPECT_LE(s.bottom_percent, 0.25);
    EXPECT_EQ(s.top_holes, 0);
    EXPECT_EQ(s.bottom_holes, 0);
}

}  // namespace

// A 31 degree cone: over two layers its side moves 0.67 mm, a band between the outer wall and
// the carvable part too thin for two lines of fill (1.7 line widths) and too wide for the wall
// alone. Before such bands got a line of their own: top left open 33.6 %, 55 holes of 1 mm2.
TEST(Skins, ShallowConeIsClosed) {
    std::vector<StlTriangle> t;
    add_cone(t, 20, 20 * std::tan(31 * std::numbers::pi / 180), 128);
    expect_closed(sliced_skins(write_stl("cone31.stl", t)));
}

// A dome over a belly: every slope from flat to vertical, up and down. Before: top 2.42 %, 6
// holes (the largest 11 mm2).
TEST(Skins, BallCutFlatIsClosedOnTopAndBelow) {
    std::vector<StlTriangle> t;
    add_cut_ball(t, 15, 12, 48, 128);
    expect_closed(sliced_skins(write_stl("ball.stl", t)));
}

// A tall box with a shelf high up its side, the shelf's underside rising at 32 degrees from
// the wall (a corbel): a down-facing slope, then the shelf's flat top and the box's. Before:
// bottom 11.2 %, 28 holes.
TEST(Skins, TallBoxWithAShelfIsClosed) {
    std::vector<StlTriangle> t;
    add_box(t, 0, 0, 0, 20, 20, 40);
    const float rise = 10 * std::tan(32 * std::numbers::pi / 180);
    add_prism_xz(t, {{19.5f, 28 - rise}, {30, 28}, {30, 31}, {19.5f, 31}}, 0, 20);
    expect_closed(sliced_skins(write_stl("shelf.stl", t)));
}

// Arc fitting: fit_arc on sampled circles, lines and corners, and a whole file with
// --arc-fitting measured back by carve check's reader.
#include "gcode/arcs.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "check/gcode_analysis.hpp"
#include "support/carve_run.hpp"
#include "support/models.hpp"

using namespace carve;
using carve::test::repo_model;

namespace {

std::vector<Point> circle_points(double cx, double cy, double r, int n, double from, double to) {
    std::vector<Point> pts;
    for (int i = 0; i <= n; ++i) {
        const double a = from + (to - from) * i / n;
        pts.push_back(
            Point(std::llround(cx + r * std::cos(a)), std::llround(cy + r * std::sin(a))));
    }
    return pts;
}

}  // namespace

TEST(Arcs, SampledCircleBecomesOneArcWithItsCentreAndLength) {
    const double r = 20000;  // 20 mm
    const auto pts = circle_points(1000, -2000, r, 60, 0, std::numbers::pi);
    const auto arc = fit_arc(pts, 0, 20);
    ASSERT_TRUE(arc);
    EXPECT_EQ(arc->last, pts.size() - 1);
    EXPECT_TRUE(arc->counter_clockwise);
    EXPECT_NEAR(arc->cx, 1000, 5);
    EXPECT_NEAR(arc->cy, -2000, 5);
    EXPECT_NEAR(arc->length, std::numbers::pi * r, 0.001 * std::numbers::pi * r);

    std::vector<Point> reversed(pts.rbegin(), pts.rend());
    const auto back = fit_arc(reversed, 0, 20);
    ASSERT_TRUE(back);
    EXPECT_FALSE(back->counter_clockwise);
}

TEST(Arcs, LinesCornersAndCoarseChordsAreNotArcs) {
    // Points in line: no circle.
    std::vector<Point> line;
    for (int i = 0; i < 10; ++i) line.push_back(Point(i * 1000, 0));
    EXPECT_FALSE(fit_arc(line, 0, 20));
    // A circle up to a corner: the arc stops before the corner.
    auto pts = circle_points(0, 0, 10000, 20, 0, std::numbers::pi / 2);
    const size_t corner = pts.size() - 1;
    pts.push_back(Point(-20000, 10000));
    const auto arc = fit_arc(pts, 0, 20);
    ASSERT_TRUE(arc);
    EXPECT_EQ(arc->last, corner);
    // Four points a quarter circle apart: each chord bulges far more than the tolerance.
    EXPECT_FALSE(fit_arc(circle_points(0, 0, 10000, 3, 0, 1.5 * std::numbers::pi), 0, 20));
}

TEST(Arcs, ArcFittingKeepsTheMaterialAndShortensTheFile) {
    namespace fs = std::filesystem;
    const fs::path dir = carve::test::scratch();
    const std::string model = repo_model("fandisk.stl");
    const fs::path plain = dir / "plain.gcode", arcs = dir / "arcs.gcode";
    ASSERT_EQ(
        carve::test::run_carve("slice " + model + " -q --scale 0.5 -o " + plain.string()).status,
        0);
    ASSERT_EQ(carve::test::run_carve("slice " + model + " -q --scale 0.5 --arc-fitting -o " +
                                     arcs.string())
                  .status,
              0);
    GcodeAnalysisOptions options;
    options.keep_layers = false;
    const GcodeAnalysis a = analyse_gcode(plain.string(), options);
    const GcodeAnalysis b = analyse_gcode(arcs.string(), options);
    EXPECT_EQ(a.arcs, 0);
    EXPECT_GT(b.arcs, 100);
    EXPECT_LT(fs::file_size(arcs), 0.9 * fs::file_size(plain));
    // The arcs lie within 0.02 mm of the chords they replace: the same material and footprint.
    EXPECT_NEAR(b.extruded_volume_mm3, a.extruded_volume_mm3, 0.002 * a.extruded_volume_mm3);
    EXPECT_NEAR(b.far_unsupported_area_mm2, a.far_unsupported_area_mm2,
                0.05 * a.far_unsupported_area_mm2 + 0.5);
}

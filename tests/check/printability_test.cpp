// carve check's printability figures (issue 35) on G-code written here to have, or not to have,
// a free-standing column, a hole in a skin, a bridge; and the exit status of --strict.
#include "check/printability.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "check/gcode_analysis.hpp"
#include "mesh/mesh.hpp"
#include "report/stats.hpp"
#include "support/carve_run.hpp"
#include "support/stl_boxes.hpp"

namespace carve {
namespace {

constexpr double kW = 0.45, kH = 0.2;

// G-code with absolute E, beads of width kW and height kH by the rounded bead model.
class Program {
  public:
    Program() { out_ << "G21\nG90\nM82\nG92 E0\n"; }
    void travel(double x, double y, double z) {
        out_ << "G0 X" << x << " Y" << y << " Z" << z << " F9000\n";
        x_ = x, y_ = y;
    }
    void extrude_to(double x, double y) {
        const double section = (kW - kH) * kH + std::numbers::pi * kH * kH / 4;
        const double area = std::numbers::pi * 1.75 * 1.75 / 4;
        e_ += section * std::hypot(x - x_, y - y_) / area;
        out_ << "G1 X" << x << " Y" << y << " E" << e_ << " F1800\n";
        x_ = x, y_ = y;
    }
    void line(double x0, double y0, double x1, double y1, double z) {
        travel(x0, y0, z);
        extrude_to(x1, y1);
    }
    // The outer wall of a side x side box from the origin: bead centres half a width in.
    void wall(double side, double z) {
        const double a = kW / 2, b = side - kW / 2;
        travel(a, a, z);
        extrude_to(b, a);
        extrude_to(b, b);
        extrude_to(a, b);
        extrude_to(a, a);
    }
    std::string str() const { return out_.str(); }

  private:
    std::ostringstream out_;
    double x_ = 0, y_ = 0, e_ = 0;
};

std::filesystem::path write(const std::string& name, const std::string& text) {
    const auto p = test::scratch() / name;
    std::ofstream(p) << text;
    return p;
}

std::filesystem::path write_box_stl(const std::string& name, float side, float height) {
    std::vector<test::StlTriangle> t;
    test::add_box(t, 0, 0, 0, side, side, height);
    return test::write_stl(name, t);
}

Mesh box_mesh(double side, double height) {
    Mesh m;
    for (int k = 0; k < 8; ++k)
        m.vertices.push_back({k & 1 ? side : 0, k & 2 ? side : 0, k & 4 ? height : 0});
    const uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                  {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
        m.triangles.push_back({q[0], q[1], q[2]});
        m.triangles.push_back({q[0], q[2], q[3]});
    }
    return m;
}

// A 20 mm box 12 mm tall printed as its wall, with a 0.8 mm bead standing in its middle from
// z 2 to z 10 (40 layers); `joined`: each layer's bead runs from the wall.
std::string column_gcode(bool joined) {
    Program p;
    for (int layer = 1; layer <= 60; ++layer) {
        const double z = layer * kH;
        p.wall(20, z);
        if (layer > 10 && layer <= 50) p.line(joined ? kW / 2 : 9.6, 10, 10.4, 10, z);
    }
    return p.str();
}

// A 20 mm box 2 mm tall (10 layers), every layer filled by lines 0.4 mm apart inside its wall;
// `hole`: the last layer leaves out 2 x 2 mm in the middle.
std::string slab_gcode(bool hole) {
    Program p;
    for (int layer = 1; layer <= 10; ++layer) {
        const double z = layer * kH;
        p.wall(20, z);
        for (double y = 0.6; y < 19.5; y += 0.4) {
            if (hole && layer == 10 && y + kW / 2 > 9 && y - kW / 2 < 11) {
                p.line(0.4, y, 9 - kW / 2, y, z);
                p.line(11 + kW / 2, y, 19.6, y, z);
            } else {
                p.line(0.4, y, 19.6, y, z);
            }
        }
    }
    return p.str();
}

GcodeAnalysis check(const std::string& name, const std::string& gcode, const Mesh& mesh) {
    return analyse_gcode_on_mesh(write(name, gcode).string(), mesh, {}, Vec3{0, 0, 0});
}

TEST(Printability, FreeStandingColumnIsFoundWithItsHeight) {
    const GcodeAnalysis a = check("column.gcode", column_gcode(false), box_mesh(20, 12));
    const ColumnFigures& c = a.printability.columns;
    EXPECT_EQ(c.thin_interior, 1);
    EXPECT_EQ(c.over_5mm, 1);
    EXPECT_EQ(c.over_10mm, 0);
    EXPECT_EQ(c.tallest_layers, 40);
    EXPECT_NEAR(c.tallest_mm, 8.0, 1e-6);
    EXPECT_NEAR(c.tallest_z_from_mm, 2.0, 1e-6);
    EXPECT_NEAR(c.tallest_z_to_mm, 10.0, 1e-6);
    EXPECT_NEAR(c.tallest_x_mm, 10, 0.01);
    EXPECT_NEAR(c.tallest_y_mm, 10, 0.01);
    EXPECT_NEAR(c.tallest_width_mm, kW, 0.01);
    const std::vector<std::string> failed = failed_rules(a);
    ASSERT_FALSE(failed.empty());
    EXPECT_NE(failed.front().find("free-standing thin columns: 1 taller than 5 mm"),
              std::string::npos);
}

TEST(Printability, ColumnJoinedToTheWallInEveryLayerIsNone) {
    const GcodeAnalysis a = check("joined.gcode", column_gcode(true), box_mesh(20, 12));
    EXPECT_EQ(a.printability.columns.thin_interior, 0);
    EXPECT_EQ(a.printability.columns.over_5mm, 0);
}

TEST(Printability, HoleInTheTopSkinIsFound) {
    const GcodeAnalysis a = check("hole.gcode", slab_gcode(true), box_mesh(20, 2));
    const SkinFigures& top = a.printability.top;
    // Top: the last two layers, 400 mm2 each.
    EXPECT_NEAR(top.region_mm2, 800, 1);
    EXPECT_EQ(top.holes_1mm2, 1);
    EXPECT_GT(top.largest_hole_mm2, 4);
    EXPECT_LT(top.largest_hole_mm2, 6);
    EXPECT_NEAR(top.largest_hole_z_mm, 2.0, 1e-6);
    EXPECT_GT(top.open_percent(), 0.25);
    EXPECT_NEAR(top.open_mm2, top.largest_hole_mm2, 0.01);
    EXPECT_EQ(a.printability.bottom.holes_1mm2, 0);
    EXPECT_LT(a.printability.bottom.open_percent(), 0.01);
    EXPECT_EQ(a.printability.columns.thin_interior, 0);
}

TEST(Printability, ClosedSkinsLeaveNothingOpen) {
    const GcodeAnalysis a = check("closed.gcode", slab_gcode(false), box_mesh(20, 2));
    EXPECT_NEAR(a.printability.top.region_mm2, 800, 1);
    EXPECT_NEAR(a.printability.bottom.region_mm2, 800, 1);
    EXPECT_LT(a.printability.top.open_mm2, 0.01);
    EXPECT_LT(a.printability.bottom.open_mm2, 0.01);
    EXPECT_EQ(a.printability.top.holes_1mm2, 0);
    EXPECT_TRUE(failed_rules(a).empty());
}

TEST(Printability, LongestBridgeIsTheSpanBetweenItsSupports) {
    // Layer 1: two lines 14 mm apart; layer 2: one line across both, running out past them.
    Program p;
    p.line(2, 0, 2, 4, kH);
    p.line(16, 0, 16, 4, kH);
    p.line(0, 2, 18, 2, 2 * kH);
    const GcodeAnalysis a = analyse_gcode(write("bridge.gcode", p.str()).string());
    // Held where the layer below grown by r = 0.2 mm begins: 2 + 0.225 + 0.2 .. 16 - 0.425.
    EXPECT_NEAR(a.longest_bridge_mm, 14 - 2 * (kW / 2 + 0.2), 0.01);
    EXPECT_NEAR(a.longest_bridge_z_mm, 0.4, 1e-9);
    EXPECT_NEAR(a.longest_bridge_x_mm, 9, 0.01);
}

TEST(Printability, NarrowSideOfTheMinimumRectangle) {
    // A 10 x 1 rectangle turned by 30 degrees: its own rectangle, narrow side 1.
    Path r;
    const double c = std::cos(std::numbers::pi / 6), s = std::sin(std::numbers::pi / 6);
    for (auto [x, y] : {std::pair{0.0, 0.0}, {10.0, 0.0}, {10.0, 1.0}, {0.0, 1.0}})
        r.push_back(Point(to_units(x * c - y * s), to_units(x * s + y * c)));
    EXPECT_NEAR(check::narrow_side(r) / kUnitsPerMm, 1.0, 0.002);
}

TEST(Printability, StrictExitsFiveWhenARuleFails) {
    const auto stl = write_box_stl("slab.stl", 20, 2);
    const auto closed = write("strict_closed.gcode", slab_gcode(false));
    const auto hole = write("strict_hole.gcode", slab_gcode(true));
    test::CarveRun r = test::run_carve("check " + closed.string() + " --mesh " + stl.string() +
                                       " --mesh-offset 0,0 --strict");
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("verdict          passes"), std::string::npos) << r.out;
    r = test::run_carve("check " + hole.string() + " --mesh " + stl.string() +
                        " --mesh-offset 0,0 --strict");
    EXPECT_EQ(r.status, 5);
    EXPECT_NE(r.err.find("carve: check: fails: top skin left open"), std::string::npos) << r.err;
    // Without --strict the same file is measured and passes as a command.
    r = test::run_carve("check " + hole.string() + " --mesh " + stl.string() +
                        " --mesh-offset 0,0 --json");
    EXPECT_EQ(r.status, 0);
    EXPECT_NE(r.out.find("\"failed_rules\""), std::string::npos);
    // The rules need the model.
    r = test::run_carve("check " + hole.string() + " --strict");
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("--strict needs --mesh"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace carve

// Tests of the G-code analyser on small synthetic programs whose footprints can be computed by
// hand or by brute-force sampling of the distance definition.
#include "check/gcode_analysis.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "base/error.hpp"
#include "mesh/mesh.hpp"
#include "report/stats.hpp"

namespace carve {
namespace {

constexpr double kFilamentArea = std::numbers::pi * 1.75 * 1.75 / 4;

struct XY {
    double x, y;
};

// Filament that lays a bead of width w and height h over a length, by the default (rounded) model.
double filament_for(double length, double w, double h) {
    double section = (w - h) * h + std::numbers::pi * h * h / 4;
    return section * length / kFilamentArea;
}

// Writes G-code to a temporary file removed when the object dies.
class TempGcode {
  public:
    explicit TempGcode(const std::string& text) {
        static int counter = 0;
        path_ = (std::filesystem::temp_directory_path() /
                 ("carve_gcode_test_" + std::to_string(::getpid()) + "_" +
                  std::to_string(counter++) + ".gcode"))
                    .string();
        std::ofstream(path_) << text;
    }
    ~TempGcode() { std::filesystem::remove(path_); }
    const std::string& path() const { return path_; }

  private:
    std::string path_;
};

// A program builder that tracks absolute or relative E.
class Program {
  public:
    explicit Program(bool relative_e = false) : relative_(relative_e) {
        out_ << "G21\nG90\n" << (relative_ ? "M83\n" : "M82\n") << "G92 E0\n";
    }
    void travel(XY p, double z) {
        out_ << "G0 X" << p.x << " Y" << p.y << " Z" << z << " F9000\n";
        at_ = p;
    }
    void extrude_to(XY p, double w, double h) {
        double e = filament_for(std::hypot(p.x - at_.x, p.y - at_.y), w, h);
        e_ += e;
        out_ << "G1 X" << p.x << " Y" << p.y << " E" << (relative_ ? e : e_) << " F1800\n";
        at_ = p;
    }
    // Closed loop through the corners, starting with a travel to the first one.
    void loop(const std::vector<XY>& corners, double z, double w, double h) {
        travel(corners.front(), z);
        for (size_t i = 1; i <= corners.size(); ++i) extrude_to(corners[i % corners.size()], w, h);
    }
    void raw(const std::string& line) { out_ << line << "\n"; }
    void reset_e() {
        out_ << "G92 E0\n";
        e_ = 0;
    }
    double filament() const { return e_; }
    std::string str() const {
        out_.flush();
        return out_.str();
    }

  private:
    bool relative_;
    mutable std::ostringstream out_;
    XY at_{0, 0};
    double e_ = 0;  // absolute E register as written (since the last reset)
};

std::vector<XY> square(double x0, double y0, double side) {
    return {{x0, y0}, {x0 + side, y0}, {x0 + side, y0 + side}, {x0, y0 + side}};
}

double distance_to_loop(XY p, const std::vector<XY>& loop) {
    double best = 1e300;
    for (size_t i = 0; i < loop.size(); ++i) {
        XY a = loop[i], b = loop[(i + 1) % loop.size()];
        double dx = b.x - a.x, dy = b.y - a.y;
        double t = std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / (dx * dx + dy * dy), 0., 1.);
        best = std::min(best, std::hypot(p.x - a.x - t * dx, p.y - a.y - t * dy));
    }
    return best;
}

// Area of {p : d(p, upper) <= w/2 and d(p, lower) > radius + w/2} by midpoint sampling: the
// definition of unsupported extrusion with round-capped beads, computed without polygons.
double sampled_unsupported(const std::vector<XY>& upper, const std::vector<XY>& lower, double w,
                           double radius) {
    const double step = 0.005;
    // Only the boxes around the upper loop's edges can hold its footprint; a sample point is
    // counted in the first box that holds it.
    struct Box {
        double x0, y0, x1, y1;
        bool holds(double x, double y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
    };
    std::vector<Box> boxes;
    for (size_t i = 0; i < upper.size(); ++i) {
        XY a = upper[i], b = upper[(i + 1) % upper.size()];
        boxes.push_back({std::min(a.x, b.x) - w, std::min(a.y, b.y) - w, std::max(a.x, b.x) + w,
                         std::max(a.y, b.y) + w});
    }
    double area = 0;
    for (size_t k = 0; k < boxes.size(); ++k) {
        const Box& bx = boxes[k];
        for (double x = std::floor(bx.x0 / step) * step + step / 2; x < bx.x1; x += step) {
            for (double y = std::floor(bx.y0 / step) * step + step / 2; y < bx.y1; y += step) {
                bool earlier = false;
                for (size_t j = 0; j < k && !earlier; ++j) earlier = boxes[j].holds(x, y);
                if (earlier || !bx.holds(x, y)) continue;
                if (distance_to_loop({x, y}, upper) <= w / 2 &&
                    distance_to_loop({x, y}, lower) > radius + w / 2)
                    area += step * step;
            }
        }
    }
    return area;
}

TEST(GcodeAnalysis, SquareLoopFootprintIsPerimeterTimesWidth) {
    const double w = 0.45, h = 0.2, side = 20;
    Program prog;
    prog.loop(square(0, 0, side), h, w, h);
    TempGcode file(prog.str());
    GcodeAnalysis a = analyse_gcode(file.path());
    EXPECT_EQ(a.layers, 1);
    EXPECT_EQ(a.extruding_moves, 4);
    // Outer square with rounded corners minus the inner square: 4 * side * w - (4 - pi) w^2 / 4.
    double expected = 4 * side * w - (4 - std::numbers::pi) * w * w / 4;
    EXPECT_NEAR(a.footprint_area_mm2, expected, 0.002 * expected);
    EXPECT_NEAR(a.mean_line_width_mm, w, 1e-3);
    EXPECT_NEAR(a.filament_length_mm, prog.filament(), 1e-4);
    EXPECT_NEAR(a.extruded_volume_mm3, prog.filament() * kFilamentArea, 1e-3);
    // The first layer lies on the bed: nothing is unsupported.
    EXPECT_EQ(a.unsupported_area_mm2, 0);
    EXPECT_EQ(a.far_unsupported_area_mm2, 0);
}

TEST(GcodeAnalysis, RectangleBeadModelGivesNarrowerLines) {
    const double w = 0.45, h = 0.2;
    Program prog;
    prog.loop(square(0, 0, 20), h, w, h);
    TempGcode file(prog.str());
    GcodeAnalysisOptions options;
    options.bead = BeadModel::kRectangle;
    GcodeAnalysis a = analyse_gcode(file.path(), options);
    EXPECT_NEAR(a.mean_line_width_mm, w - h * (1 - std::numbers::pi / 4), 1e-3);
    EXPECT_EQ(a.bead_model, "rectangle");
}

TEST(GcodeAnalysis, ShiftedSecondLayerMatchesSampledDefinition) {
    const double w = 0.45, h = 0.2;
    const auto lower = square(0, 0, 20), upper = square(5, 0, 20);
    Program prog;
    prog.loop(lower, 0.2, w, h);
    prog.loop(upper, 0.4, w, h);
    TempGcode file(prog.str());
    GcodeAnalysis a = analyse_gcode(file.path());
    ASSERT_EQ(a.layers, 2);
    ASSERT_EQ(a.per_layer.size(), 2u);
    EXPECT_NEAR(a.per_layer[1].z_mm, 0.4, 1e-9);
    EXPECT_NEAR(a.per_layer[1].height_mm, 0.2, 1e-9);

    double far = sampled_unsupported(upper, lower, w, 2.0);
    double near = sampled_unsupported(upper, lower, w, 0.2);
    // By hand: the right wall (20.45 x 0.45) is far, plus the ends of the top and bottom walls.
    EXPECT_GT(far, 20.45 * 0.45);
    EXPECT_NEAR(a.far_unsupported_area_mm2, far, 0.01 * far);
    EXPECT_NEAR(a.unsupported_area_mm2, near, 0.01 * near);
    EXPECT_NEAR(a.far_unsupported_fraction, far / a.footprint_area_mm2, 1e-3);
    EXPECT_EQ(a.per_layer[0].far_unsupported_area_mm2, 0);
}

TEST(GcodeAnalysis, FarRadiusIsAnOption) {
    const double w = 0.45, h = 0.2;
    const auto lower = square(0, 0, 20), upper = square(5, 0, 20);
    Program prog;
    prog.loop(lower, 0.2, w, h);
    prog.loop(upper, 0.4, w, h);
    TempGcode file(prog.str());
    GcodeAnalysisOptions options;
    options.far_radius_mm = 1.0;
    options.support_radius_mm = 0.5;
    GcodeAnalysis a = analyse_gcode(file.path(), options);
    double far = sampled_unsupported(upper, lower, w, 1.0);
    double near = sampled_unsupported(upper, lower, w, 0.5);
    EXPECT_NEAR(a.far_unsupported_area_mm2, far, 0.01 * far);
    EXPECT_NEAR(a.unsupported_area_mm2, near, 0.01 * near);
}

// A support's top holds what lies over it across the usual one-layer gap: a 20 mm line over a
// support line two layers down is held with the default gap and hangs without it. The
// support's own extrusion is reported apart.
TEST(GcodeAnalysis, SupportTopAcrossTheGapHoldsTheLayerAbove) {
    const double w = 0.45, h = 0.2;
    auto program = [&] {
        Program prog;
        prog.loop(square(0, 0, 4), 0.2, w, h);  // the model's first layer, apart
        prog.raw(";TYPE:Support material interface");
        prog.travel({10, 10}, 0.2);
        prog.extrude_to({30, 10}, w, h);
        prog.raw(";TYPE:External perimeter");
        prog.loop(square(0, 0, 4), 0.4, w, h);  // the gap layer: nothing over the support
        prog.travel({10, 10}, 0.6);
        prog.extrude_to({30, 10}, w, h);  // the overhang, over the support
        prog.loop(square(0, 0, 4), 0.6, w, h);
        return prog.str();
    };
    TempGcode file(program());
    GcodeAnalysis held = analyse_gcode(file.path());
    EXPECT_NEAR(held.per_layer[2].far_unsupported_area_mm2, 0, 1e-6);
    EXPECT_GT(held.support_volume_mm3, 0);
    GcodeAnalysisOptions no_gap;
    no_gap.support_gap_mm = 0;
    GcodeAnalysis hangs = analyse_gcode(file.path(), no_gap);
    EXPECT_GT(hangs.per_layer[2].far_unsupported_area_mm2, 15 * w);
}

TEST(GcodeAnalysis, StackedLayersAreFullySupported) {
    const double w = 0.45, h = 0.2;
    Program prog;
    for (int i = 1; i <= 5; ++i) prog.loop(square(0, 0, 20), 0.2 * i, w, h);
    TempGcode file(prog.str());
    GcodeAnalysis a = analyse_gcode(file.path());
    EXPECT_EQ(a.layers, 5);
    EXPECT_NEAR(a.unsupported_area_mm2, 0, 1e-6);
    EXPECT_NEAR(a.last_z_mm, 1.0, 1e-9);
}

TEST(GcodeAnalysis, RelativeAndAbsoluteExtrusionAgree) {
    const double w = 0.45, h = 0.2;
    Program absolute(false), relative(true);
    for (Program* p : {&absolute, &relative}) {
        p->loop(square(0, 0, 20), 0.2, w, h);
        p->loop(square(2, 0, 20), 0.4, w, h);
    }
    TempGcode fa(absolute.str()), fr(relative.str());
    GcodeAnalysis a = analyse_gcode(fa.path()), r = analyse_gcode(fr.path());
    EXPECT_NEAR(a.filament_length_mm, r.filament_length_mm, 1e-4);
    EXPECT_NEAR(a.footprint_area_mm2, r.footprint_area_mm2, 1e-3);
    EXPECT_NEAR(a.unsupported_area_mm2, r.unsupported_area_mm2, 1e-3);
    EXPECT_GT(a.unsupported_area_mm2, 0);
}

TEST(GcodeAnalysis, G92ResetsTheExtruderRegister) {
    const double w = 0.45, h = 0.2;
    Program plain, with_resets;
    plain.loop(square(0, 0, 20), 0.2, w, h);
    plain.loop(square(0, 0, 20), 0.4, w, h);
    with_resets.loop(square(0, 0, 20), 0.2, w, h);
    with_resets.reset_e();  // E restarts from 0: the next absolute values are small again
    with_resets.loop(square(0, 0, 20), 0.4, w, h);
    TempGcode fp(plain.str()), fr(with_resets.str());
    GcodeAnalysis p = analyse_gcode(fp.path()), r = analyse_gcode(fr.path());
    EXPECT_NEAR(p.filament_length_mm, r.filament_length_mm, 1e-4);
    EXPECT_NEAR(p.footprint_area_mm2, r.footprint_area_mm2, 1e-3);
    EXPECT_NEAR(r.per_layer[1].footprint_area_mm2, r.per_layer[0].footprint_area_mm2, 1e-3);
}

TEST(GcodeAnalysis, RetractionsAndWipesDrawNothing) {
    const double w = 0.45, h = 0.2;
    Program prog;
    prog.loop(square(0, 0, 20), 0.2, w, h);
    double e = prog.filament();
    std::ostringstream extra;
    // Retract while wiping along a path away from the loop, hop, travel, come back, unretract.
    extra << "G1 X10 Y10 E" << e - 1 << "\n"
          << "G1 E" << e - 3 << "\n"
          << "G0 Z0.6\nG0 X40 Y40\nG0 Z0.2\n"
          << "G1 E" << e << "\n";
    prog.raw(extra.str());
    TempGcode file(prog.str());
    GcodeAnalysis a = analyse_gcode(file.path());
    EXPECT_EQ(a.layers, 1);  // the z hop is travel only
    EXPECT_EQ(a.retractions, 2);
    EXPECT_NEAR(a.filament_length_mm, e, 1e-4);  // retracted filament came back
    double expected = 80 * w - (4 - std::numbers::pi) * w * w / 4;
    EXPECT_NEAR(a.footprint_area_mm2, expected, 0.002 * expected);
    EXPECT_GT(a.travel_length_mm, 40);
}

TEST(GcodeAnalysis, ExtrusionsGroupByTheirZNotByZHops) {
    const double w = 0.45, h = 0.2;
    Program prog;
    prog.loop(square(0, 0, 20), 0.2, w, h);
    prog.raw("G1 Z1.2 F600");  // hop before the next layer, never extruded at
    prog.loop(square(0, 0, 20), 0.4, w, h);
    TempGcode file(prog.str());
    GcodeAnalysis a = analyse_gcode(file.path());
    EXPECT_EQ(a.layers, 2);
    EXPECT_NEAR(a.per_layer[1].height_mm, 0.2, 1e-9);
}

TEST(GcodeAnalysis, ArcsAreFollowed) {
    const double w = 0.45, h = 0.2, radius = 10;
    double e = filament_for(2 * std::numbers::pi * radius, w, h);
    std::ostringstream g;
    g << "G90\nM83\nG0 X10 Y0 Z0.2\nG3 X10 Y0 I-10 J0 E" << e << "\n";
    TempGcode file(g.str());
    GcodeAnalysis a = analyse_gcode(file.path());
    EXPECT_EQ(a.arcs, 1);
    EXPECT_NEAR(a.footprint_area_mm2, 2 * std::numbers::pi * radius * w, 0.03);
    // Clockwise half circle by radius: a half ring.
    std::ostringstream g2;
    g2 << "G90\nM83\nG0 X-10 Y0 Z0.2\nG2 X10 Y0 R10 E" << e / 2 << "\n";
    TempGcode file2(g2.str());
    GcodeAnalysis b = analyse_gcode(file2.path());
    EXPECT_NEAR(b.footprint_area_mm2, std::numbers::pi * radius * w + std::numbers::pi * w * w / 4,
                0.03);
}

TEST(GcodeAnalysis, HeaderTimeBothFormats) {
    EXPECT_DOUBLE_EQ(parse_duration_s("1h 2m 3s"), 3723);
    EXPECT_DOUBLE_EQ(parse_duration_s(" 1d 0h 0m 5s"), 86405);
    EXPECT_DOUBLE_EQ(parse_duration_s("45s"), 45);
    EXPECT_DOUBLE_EQ(parse_duration_s("none"), -1);

    TempGcode prusa(
        "; generated by PrusaSlicer 2.5.0 on 2026-01-01 at 00:00:00 UTC\nG1 X1 Y1\n"
        "; filament used [mm] = 12.5\n"
        "; estimated printing time (normal mode) = 1h 2m 3s\n"
        "; estimated printing time (silent mode) = 2h 2m 3s\n");
    GcodeAnalysis p = analyse_gcode(prusa.path());
    EXPECT_DOUBLE_EQ(p.estimated_time_from_header_s, 3723);
    EXPECT_DOUBLE_EQ(p.filament_used_from_header_mm, 12.5);
    EXPECT_EQ(p.generator, "PrusaSlicer 2.5.0");

    TempGcode cura(
        ";FLAVOR:Marlin\n;TIME:123\n;Filament used: 1.5m\n;Generated with Cura_SteamEngine "
        "4.13.0\n;LAYER:0\n;TIME_ELAPSED:99.0\nG1 X1 Y1\n");
    GcodeAnalysis c = analyse_gcode(cura.path());
    EXPECT_DOUBLE_EQ(c.estimated_time_from_header_s, 123);
    EXPECT_DOUBLE_EQ(c.filament_used_from_header_mm, 1500);
    EXPECT_EQ(c.generator, "Cura_SteamEngine 4.13.0");

    TempGcode none("G1 X1 Y1\n");
    EXPECT_EQ(analyse_gcode(none.path()).estimated_time_from_header_s, -1);
}

TEST(GcodeAnalysis, FilamentDiameterFromHeaderUnlessTurnedOff) {
    const double w = 0.45, h = 0.2;
    Program prog;  // E computed for 1.75 mm filament
    prog.loop(square(0, 0, 20), 0.2, w, h);
    TempGcode file(prog.str() + "; filament_diameter = 2.85\n");
    GcodeAnalysis a = analyse_gcode(file.path());
    EXPECT_DOUBLE_EQ(a.filament_diameter_mm, 2.85);
    EXPECT_EQ(a.filament_diameter_source, "header");
    EXPECT_NEAR(a.extruded_volume_mm3, prog.filament() * std::numbers::pi * 2.85 * 2.85 / 4, 1e-3);
    GcodeAnalysisOptions options;
    options.filament_diameter_from_header = false;
    options.filament_diameter_mm = 1.75;
    GcodeAnalysis b = analyse_gcode(file.path(), options);
    EXPECT_DOUBLE_EQ(b.filament_diameter_mm, 1.75);
    EXPECT_EQ(b.filament_diameter_source, "option");
    EXPECT_NEAR(b.mean_line_width_mm, w, 1e-3);
}

TEST(GcodeAnalysis, LineNumbersChecksumsAndLowerCase) {
    const double w = 0.45, h = 0.2;
    double e = filament_for(20, w, h);
    std::ostringstream g;
    g << "N1 G90*12\nN2 m83\nN3 g0 x0 y0 z0.2\nN4 G1 X20 Y0 E" << e << " ; comment\n";
    TempGcode file(g.str());
    GcodeAnalysis a = analyse_gcode(file.path());
    EXPECT_EQ(a.extruding_moves, 1);
    EXPECT_NEAR(a.footprint_area_mm2, 20 * w + std::numbers::pi * w * w / 4, 0.01);
}

TEST(GcodeAnalysis, ModelCheckMeasuresExtrusionOutside) {
    const double w = 0.45, h = 0.2;
    Program prog;
    prog.loop(square(0, 0, 20), 0.2, w, h);
    prog.loop(square(0, 0, 20), 0.4, w, h);
    TempGcode file(prog.str());
    auto box = [](double x0, double y0, double x1, double y1) {
        Path p{Point(to_units(x0), to_units(y0)), Point(to_units(x1), to_units(y0)),
               Point(to_units(x1), to_units(y1)), Point(to_units(x0), to_units(y1))};
        return Paths{p};
    };
    GcodeAnalysisOptions options;
    std::vector<double> asked;
    // The bead centres run on the model's contour: half a width outside, within tolerance.
    options.model_slice = [&](double z) {
        asked.push_back(z);
        return box(0, 0, 20, 20);
    };
    GcodeAnalysis inside = analyse_gcode(file.path(), options);
    EXPECT_TRUE(inside.model_checked);
    EXPECT_NEAR(inside.outside_area_mm2, 0, 0.01);
    EXPECT_NEAR(inside.max_outside_model_mm, w / 2, 0.01);
    ASSERT_EQ(asked.size(), 2u);
    EXPECT_NEAR(asked[0], 0.1, 1e-9);  // middle of each layer
    EXPECT_NEAR(asked[1], 0.3, 1e-9);

    // A model 2 mm smaller on every side: the whole loop is outside it.
    options.model_slice = [&](double) { return box(2, 2, 18, 18); };
    GcodeAnalysis outside = analyse_gcode(file.path(), options);
    EXPECT_NEAR(outside.max_outside_model_mm, std::hypot(2.0, 2.0) + w / 2, 0.01);
    EXPECT_NEAR(outside.outside_area_mm2, outside.footprint_area_mm2, 0.01);
}

// Closed boxes {x0, y0, z0, x1, y1, z1}, one shell each, faces counter-clockwise from outside.
Mesh boxes(const std::vector<std::array<double, 6>>& list) {
    Mesh m;
    for (const auto& [x0, y0, z0, x1, y1, z1] : list) {
        const auto base = static_cast<uint32_t>(m.vertices.size());
        for (int k = 0; k < 8; ++k)
            m.vertices.push_back({k & 1 ? x1 : x0, k & 2 ? y1 : y0, k & 4 ? z1 : z0});
        const uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                      {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
        for (const auto& q : quads) {
            m.triangles.push_back({base + q[0], base + q[1], base + q[2]});
            m.triangles.push_back({base + q[0], base + q[2], base + q[3]});
        }
    }
    return m;
}

// Area of a closed square-cornered loop of beads of width w along a rectangle a x b.
double loop_area(double a, double b, double w) {
    return 2 * (a + b) * w - (4 - std::numbers::pi) * w * w / 4;
}

std::vector<XY> rectangle(double x0, double y0, double x1, double y1) {
    return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

// A 20 mm box printed as its wall up to mid-height, then one layer with a square loop floating
// inside it (over the box's slice below: inside) and a loop under a shelf that the model only
// has from that height on (nothing of the model below: overhang). Both loops lie farther than
// 2 mm from the box's wall, so each is hanging whole.
std::string box_and_shelf_gcode(double dx, double dy, double w, double h) {
    Program prog;
    auto shifted = [&](std::vector<XY> loop) {
        for (XY& p : loop) p = {p.x + dx, p.y + dy};
        return loop;
    };
    prog.raw(";TYPE:Skirt");  // a prime line on the first layer, outside everything
    prog.travel({dx - 30, dy - 5}, h);
    prog.extrude_to({dx + 50, dy - 5}, w, h);
    prog.raw(";TYPE:WALL-OUTER");
    for (int i = 1; i <= 11; ++i) prog.loop(shifted(square(0, 0, 20)), i * h, w, h);
    prog.loop(shifted(square(8, 8, 4)), 11 * h, w, h);
    prog.loop(shifted(rectangle(24, 0, 30, 20)), 11 * h, w, h);
    return prog.str();
}

TEST(GcodeAnalysis, MeshSplitsHangingIntoInsideAndOverhang) {
    const double w = 0.45, h = 0.2;
    // The shelf starts at z = 2.05: in the slice of the last layer (z 2.0 .. 2.2, cut at 2.1),
    // not in the one below (cut at 1.9).
    const Mesh mesh = boxes({{0, 0, 0, 20, 20, 4}, {24, 0, 2.05, 30, 20, 4}});
    const double inside = loop_area(4, 4, w), overhang = loop_area(6, 20, w);

    TempGcode file(box_and_shelf_gcode(0, 0, w, h));
    GcodeAnalysis a = analyse_gcode_on_mesh(file.path(), mesh, {}, Vec3{0, 0, 0});
    ASSERT_TRUE(a.model_checked);
    EXPECT_EQ(a.mesh_alignment, "given");
    EXPECT_NEAR(a.far_unsupported_area_mm2, inside + overhang, 0.02 * (inside + overhang));
    EXPECT_NEAR(a.hanging_inside_mm2, inside, 0.02 * inside);
    EXPECT_NEAR(a.hanging_overhang_mm2, overhang, 0.02 * overhang);
    ASSERT_EQ(a.per_layer.size(), 11u);
    EXPECT_NEAR(a.per_layer.back().hanging_inside_mm2, a.hanging_inside_mm2, 1e-9);

    // The same print moved on the bed: the automatic placement finds it again (the skirt on the
    // first layer does not pull the mesh off), with the same split.
    TempGcode moved(box_and_shelf_gcode(100, 50, w, h));
    GcodeAnalysis b = analyse_gcode_on_mesh(moved.path(), mesh, {});
    EXPECT_EQ(b.mesh_alignment, "automatic");
    EXPECT_NEAR(b.mesh_offset_mm[0], 100, 1e-6);
    EXPECT_NEAR(b.mesh_offset_mm[1], 50, 1e-6);
    EXPECT_NEAR(b.mesh_offset_mm[2], 0, 1e-9);
    EXPECT_NEAR(b.mesh_extent_mismatch_mm, 0, 1e-6);  // the beads' centres span the mesh
    EXPECT_EQ(a.mesh_extent_mismatch_mm, -1);         // not measured when the offset is given
    EXPECT_NEAR(b.hanging_inside_mm2, a.hanging_inside_mm2, 1e-6);
    EXPECT_NEAR(b.hanging_overhang_mm2, a.hanging_overhang_mm2, 1e-6);

    // A wrong placement changes the split: the check is really looking at the mesh.
    GcodeAnalysis c = analyse_gcode_on_mesh(moved.path(), mesh, {}, Vec3{0, 0, 0});
    EXPECT_NEAR(c.hanging_inside_mm2, 0, 1e-9);
    EXPECT_NEAR(c.hanging_overhang_mm2, inside + overhang, 0.02 * (inside + overhang));

    // A mesh lying above z = 0 is put on the bed.
    const Mesh high = boxes({{0, 0, 10, 20, 20, 14}, {24, 0, 12.05, 30, 20, 14}});
    GcodeAnalysis d = analyse_gcode_on_mesh(file.path(), high, {});
    EXPECT_NEAR(d.mesh_offset_mm[2], -10, 1e-9);
    // A mesh at another scale is told apart by its extent.
    const Mesh big = boxes({{0, 0, 0, 40, 40, 8}, {48, 0, 4.1, 60, 40, 8}});
    EXPECT_NEAR(analyse_gcode_on_mesh(file.path(), big, {}).mesh_extent_mismatch_mm, 30, 1e-6);
    EXPECT_NEAR(d.hanging_inside_mm2, a.hanging_inside_mm2, 1e-6);
}

TEST(GcodeAnalysis, CountsRetractionsOfEveryKind) {
    const double w = 0.45, h = 0.2;
    Program prog;
    prog.loop(square(0, 0, 20), h, w, h);
    double e = prog.filament();
    std::ostringstream extra;
    extra << "G1 E" << e - 0.8 << " F2100\n"          // 1: plain retraction
          << "G0 X30 Y30\nG1 E" << e << "\n"          // recovery is no retraction
          << "G1 X31 Y30 E" << e - 0.4 << "\n"        // 2: wipe while retracting
          << "G1 X32 Y30 E" << e - 0.8 << "\n"        // 3: and its second move
          << "G2 X34 Y30 I1 J0 E" << e - 1.2 << "\n"  // 4: one arc, however many chords
          << "G1 E" << e << "\n"
          << "G10\nG0 X0 Y0\nG11\n"  // 5: firmware retraction
          << "G10 P0 X1 Y2\n"        // tool offset (RepRapFirmware): not
          << "G10\nG11\n";           // 6
    prog.raw(extra.str());
    prog.loop(square(0, 0, 20), 2 * h, w, h);
    TempGcode file(prog.str());
    GcodeAnalysis a = analyse_gcode(file.path());
    EXPECT_EQ(a.retractions, 6);
    EXPECT_EQ(a.firmware_retractions, 2);
    ASSERT_EQ(a.per_layer.size(), 2u);
    // Everything between the two layers' extrusions belongs to the layer it leads to.
    EXPECT_EQ(a.per_layer[0].retractions, 0);
    EXPECT_EQ(a.per_layer[1].retractions, 6);
}

TEST(GcodeAnalysis, TravelLeavingACShapeCrossesItsWall) {
    const double w = 0.45, h = 0.2, tol = w / 2;
    // A C open to +x: a bar at x 10..14 and two arms at y 10..14 and 26..30; its mouth is 12 mm.
    const Mesh mesh =
        boxes({{10, 10, 0, 14, 30, 1}, {14, 10, 0, 30, 14, 1}, {14, 26, 0, 30, 30, 1}});
    Program prog;
    prog.travel({11, 11}, h);  // from the origin, outside: not a crossing
    prog.extrude_to({13, 11}, w, h);
    prog.travel({28, 12}, h);  // along the lower arm: inside
    prog.extrude_to({29, 12}, w, h);
    prog.travel({29, 28}, h);  // straight across the mouth: a crossing
    prog.extrude_to({28, 28}, w, h);
    prog.travel({12, 28}, h);  // round the C, inside it: none
    prog.travel({12, 12}, h);
    prog.extrude_to({13, 12}, w, h);
    // Along the arm, then out beyond the mouth and back over a vertex outside: one crossing.
    prog.travel({28, 12}, h);
    prog.travel({34, 20}, h);
    prog.travel({28, 28}, h);
    prog.extrude_to({27, 28}, w, h);
    prog.travel({0, 28}, h);  // away at the end, never back: not a crossing
    TempGcode file(prog.str());
    GcodeAnalysis a = analyse_gcode_on_mesh(file.path(), mesh, {}, Vec3{0, 0, 0});
    ASSERT_EQ(a.per_layer.size(), 1u);
    EXPECT_NEAR(a.model_tolerance_mm, tol, 1e-6);
    EXPECT_EQ(a.wall_crossings, 2);
    EXPECT_EQ(a.per_layer[0].wall_crossings, 2);
    // Outside the slice grown by the tolerance: the start up to the grown (rounded) corner, the
    // mouth less the tolerance on both arms, the excursion (each of its 10 mm moves is outside
    // above the lower arm's grown edge, 2 + tol mm up its 8 mm rise), the way out at the end.
    const double start = 10 * std::numbers::sqrt2 - tol;
    const double mouth = 12 - 2 * tol;
    const double excursion = 2 * 10 * (1 - (2 + tol) / 8);
    const double away = 10 - tol;
    EXPECT_NEAR(a.travel_outside_mm, start + mouth + excursion + away, 0.02);
    EXPECT_NEAR(a.travel_inside_mm + a.travel_outside_mm, a.travel_length_mm, 1e-6);
    EXPECT_NEAR(a.per_layer[0].travel_length_mm, a.travel_length_mm, 1e-9);
}

TEST(GcodeAnalysis, StickTimeIsATrapezoidPerMoveFromRestToRest) {
    const double w = 0.45, h = 0.2;
    const double e = filament_for(10, w, h);
    std::ostringstream g;
    g << "G90\nM83\n"
      << "G0 X100 Y0 Z0.2 F6000\n"                  // 100 mm at 100 mm/s, 1500 mm/s^2: cruises
      << "G1 X110 Y0 E" << e << " F1200\n"          // 10 mm at 20 mm/s, 1000 mm/s^2: cruises
      << "G1 X110.1 Y0 E" << e / 100 << " F6000\n"  // 0.1 mm: never reaches 100 mm/s
      << "G1 E-1 F2100\n"                           // 1 mm of filament at 35 mm/s
      << "G4 P500\n"                                // half a second's dwell
      << "G10\n";                                   // a firmware retraction, fixed time
    TempGcode file(g.str());
    GcodeAnalysisOptions options;
    GcodeAnalysis a = analyse_gcode(file.path(), options);
    const double travel = std::hypot(100.0, 0.2) / 100 + 100 / 1500.0;
    const double print = 10 / 20.0 + 20 / 1000.0;
    const double short_move = 2 * std::sqrt(0.1 / 1000);  // triangle: accelerate half, brake half
    const double expected =
        travel + print + short_move + 1 / 35.0 + 0.5 + options.stick_firmware_retract_s;
    EXPECT_NEAR(a.stick_time_s, expected, 1e-6);
    ASSERT_EQ(a.per_layer.size(), 1u);
    EXPECT_NEAR(a.per_layer[0].stick_time_s, expected, 1e-6);
}

TEST(GcodeAnalysis, MaterialByFeatureType) {
    const double w = 0.45, h = 0.2;
    Program prog(true);
    prog.travel({0, 0}, h);
    prog.extrude_to({1, 0}, w, h);  // before any type
    prog.raw(";TYPE:External perimeter");
    prog.extrude_to({21, 0}, w, h);
    prog.raw(";TYPE:FILL");
    prog.extrude_to({21, 60}, w, h);
    prog.raw("G1 E-1\nG1 E1");  // retraction and recovery count for no type
    prog.extrude_to({22, 60}, w, h);
    TempGcode file(prog.str());
    GcodeAnalysis a = analyse_gcode(file.path());
    const double unit = filament_for(1, w, h) * kFilamentArea;
    ASSERT_EQ(a.volume_by_type_mm3.size(), 3u);
    // E is written with six digits: compare to 1e-5 relative.
    EXPECT_NEAR(a.volume_by_type_mm3["none"], unit, 1e-5 * unit);
    EXPECT_NEAR(a.volume_by_type_mm3["External perimeter"], 20 * unit, 2e-4 * unit);
    EXPECT_NEAR(a.volume_by_type_mm3["FILL"], 61 * unit, 6e-4 * unit);
    nlohmann::json j = to_json(a);
    EXPECT_NEAR(j["material_by_type"]["FILL"]["percent"].get<double>(), 100.0 * 61 / 82, 1e-3);
}

TEST(GcodeAnalysis, MissingFileIsAnInputError) {
    EXPECT_THROW(analyse_gcode("/nonexistent/file.gcode"), InputError);
}

TEST(GcodeAnalysis, JsonHasTheFigures) {
    const double w = 0.45, h = 0.2;
    Program prog;
    prog.loop(square(0, 0, 20), 0.2, w, h);
    TempGcode file(prog.str());
    GcodeAnalysis a = analyse_gcode(file.path());
    nlohmann::json j = to_json(a, true);
    EXPECT_EQ(j["layers"], 1);
    EXPECT_DOUBLE_EQ(j["extruded_volume_mm3"].get<double>(), a.extruded_volume_mm3);
    EXPECT_TRUE(j.contains("far_unsupported_percent"));
    EXPECT_EQ(j["per_layer"].size(), 1u);
    EXPECT_FALSE(to_json(a).contains("per_layer"));
}

}  // namespace
}  // namespace carve

// Tests of the G-code analyser on small synthetic programs whose footprints can be computed by
// hand or by brute-force sampling of the distance definition.
#include "check/gcode_analysis.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "base/error.hpp"

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

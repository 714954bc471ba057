// carve check's uncovered area (issue 47) on G-code written here: a box with a 1 mm fin, printed
// whole or with the fin left out, with PrusaSlicer's, CuraEngine's or no comments; the --strict
// rule; the pieces' measure.
#include "check/uncovered.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "check/footprint.hpp"
#include "check/gcode_analysis.hpp"
#include "mesh/mesh.hpp"
#include "report/stats.hpp"
#include "support/carve_run.hpp"
#include "support/stl_boxes.hpp"

namespace carve {
namespace {

constexpr double kW = 0.45, kH = 0.2;
constexpr int kLayers = 25;  // 5 mm
// A 20 x 20 mm box with a fin 1 mm thick sticking 10 mm out of its side at y 9.5 .. 10.5; the
// fin's box overlaps the box by 0.1 mm (the union is the model, as bench/thin_shapes.py does).
constexpr double kSide = 20, kFinOut = 10, kFinY0 = 9.5, kFinY1 = 10.5;

enum class Style { kNone, kPrusa, kCura };

// G-code with absolute E, beads kW wide and kH high by the rounded bead model, the comments a
// slicer of `style` writes: its layer and type marks, its nozzle in its header (PrusaSlicer's at
// the end, Cura's at the start).
class Program {
  public:
    explicit Program(Style style) : style_(style) {
        if (style == Style::kCura)
            out_ << ";FLAVOR:Marlin\n;Generated with Cura_SteamEngine 4.13.0\n"
                    ";EXTRUDER_TRAIN.0.NOZZLE.DIAMETER:0.4\n";
        out_ << "G21\nG90\nM82\nG92 E0\n";
    }
    void layer(int k) {
        if (style_ == Style::kPrusa) out_ << ";LAYER_CHANGE\n;Z:" << (k + 1) * kH << "\n";
        if (style_ == Style::kCura) out_ << ";LAYER:" << k << "\n";
    }
    void type(const char* prusa, const char* cura) {
        if (style_ == Style::kPrusa) out_ << ";TYPE:" << prusa << "\n;WIDTH:" << kW << "\n";
        if (style_ == Style::kCura) out_ << ";TYPE:" << cura << "\n";
    }
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
    std::string str() const {
        std::string s = out_.str();
        if (style_ == Style::kPrusa)
            s += "; prusaslicer_config = begin\n; nozzle_diameter = 0.4\n"
                 "; prusaslicer_config = end\n";
        return s;
    }

  private:
    Style style_;
    std::ostringstream out_;
    double x_ = 0, y_ = 0, e_ = 0;
};

// Every layer: the box's outer wall (bead centres half a width in), with `solid` lines 0.4 mm
// apart filling it, and with `fin` the fin as
// two lines from the wall to half a width short of the fin's end, 0.4 mm apart (overlapping by
// 0.05 mm, as a slicer spaces its perimeters).
std::string box_gcode(bool fin, Style style, bool solid = true) {
    Program p(style);
    for (int k = 0; k < kLayers; ++k) {
        const double z = (k + 1) * kH, a = kW / 2, b = kSide - kW / 2;
        p.layer(k);
        p.type("External perimeter", "WALL-OUTER");
        p.travel(a, a, z);
        p.extrude_to(b, a);
        p.extrude_to(b, b);
        p.extrude_to(a, b);
        p.extrude_to(a, a);
        // Solid: every layer filled (the other rules of --strict pass); else a hollow box.
        if (solid) {
            p.type("Solid infill", "SKIN");
            for (double y = 0.6; y < kSide - 0.5; y += 0.4) {
                p.travel(0.4, y, z);
                p.extrude_to(kSide - 0.4, y);
            }
        }
        if (!fin) continue;
        p.type("Perimeter", "WALL-INNER");
        for (double y : {(kFinY0 + kFinY1) / 2 - 0.2, (kFinY0 + kFinY1) / 2 + 0.2}) {
            p.travel(b, y, z);
            p.extrude_to(kSide + kFinOut - kW / 2, y);
        }
    }
    return p.str();
}

std::filesystem::path write(const std::string& name, const std::string& text) {
    const auto p = test::scratch() / name;
    std::ofstream(p) << text;
    return p;
}

std::filesystem::path fin_stl() {
    std::vector<test::StlTriangle> t;
    test::add_box(t, 0, 0, 0, kSide, kSide, kLayers * kH);
    test::add_box(t, kSide - 0.1f, kFinY0, 0, kSide + kFinOut, kFinY1, kLayers * kH);
    return test::write_stl("fin.stl", t);
}

GcodeAnalysis check(const std::string& name, const std::string& gcode) {
    MeshReport report;
    const Mesh mesh = load_mesh(fin_stl().string(), report);
    return analyse_gcode_on_mesh(write(name, gcode).string(), mesh, {}, Vec3{0, 0, 0});
}

// The fin as the check measures it: the slice shrunk by 0.1 mm, 0.8 mm wide, from the wall's
// outer edge (x 20) to 0.1 mm short of its end, on every layer. (The fin's own area, 1 x 10 mm a
// layer, is a quarter more: the measure leaves out 0.1 mm along the model's surface.)
constexpr double kFinMm2 = (kFinY1 - kFinY0 - 0.2) * (kFinOut - 0.1) * kLayers;

TEST(Uncovered, FinLeftOutIsReportedWithItsArea) {
    const GcodeAnalysis a = check("no_fin.gcode", box_gcode(false, Style::kNone, false));
    const UncoveredFigures& u = a.printability.uncovered;
    EXPECT_NEAR(u.uncovered_mm2, kFinMm2, 0.1 * kFinMm2);
    EXPECT_NEAR(u.largest.area_mm2, kFinMm2 / kLayers, 0.1 * kFinMm2 / kLayers);
    EXPECT_NEAR(u.largest.x_mm, kSide + kFinOut / 2, 0.2);
    EXPECT_NEAR(u.largest.y_mm, (kFinY0 + kFinY1) / 2, 0.05);
    EXPECT_GE(u.largest.layer, 0);
    EXPECT_LT(u.largest.layer, kLayers);
    // The box's inside, enclosed by its wall, is the interior a hollow print leaves: not counted.
    EXPECT_GT(u.enclosed_mm2, 300.0 * kLayers);
    EXPECT_EQ(u.wide_pieces, kLayers);
    EXPECT_EQ(u.wide_layers, kLayers);
    EXPECT_NEAR(u.line_width_mm, kW, 0.01);  // measured: no header
    EXPECT_EQ(u.line_width_source, "measured");
    // Hollow, the box's skins are left open too: the skin rules fail before this one.
    const std::vector<std::string> failed = failed_rules(a);
    ASSERT_FALSE(failed.empty());
    EXPECT_NE(failed.back().find("model left unprinted: 25 pieces wider than a line (0.45 mm)"),
              std::string::npos)
        << failed.back();
    double per_layer = 0;
    for (const LayerFigures& l : a.per_layer) per_layer += l.uncovered_mm2;
    EXPECT_NEAR(per_layer, u.uncovered_mm2, 1e-6);
}

TEST(Uncovered, FullPrintLeavesOnlySpecksAndPasses) {
    const GcodeAnalysis a = check("fin.gcode", box_gcode(true, Style::kNone));
    const UncoveredFigures& u = a.printability.uncovered;
    // The fin's two corners at its end, where the lines' round caps leave the square: specks
    // under 0.01 mm2 a layer.
    EXPECT_LT(u.uncovered_mm2, 0.01 * kLayers);
    EXPECT_LT(u.percent(), 0.01);
    EXPECT_EQ(u.wide_pieces, 0);
    EXPECT_TRUE(failed_rules(a).empty());
}

TEST(Uncovered, SameFiguresWithPrusaSlicerAndCuraComments) {
    for (bool fin : {false, true}) {
        const GcodeAnalysis plain = check("plain.gcode", box_gcode(fin, Style::kNone));
        const GcodeAnalysis prusa = check("prusa.gcode", box_gcode(fin, Style::kPrusa));
        const GcodeAnalysis cura = check("cura.gcode", box_gcode(fin, Style::kCura));
        for (const GcodeAnalysis* a : {&prusa, &cura}) {
            const UncoveredFigures &u = a->printability.uncovered,
                                   &v = plain.printability.uncovered;
            EXPECT_NEAR(u.uncovered_mm2, v.uncovered_mm2, 1e-9);
            EXPECT_NEAR(u.slice_mm2, v.slice_mm2, 1e-9);
            EXPECT_NEAR(u.largest.area_mm2, v.largest.area_mm2, 1e-9);
            EXPECT_EQ(u.largest.layer, v.largest.layer);
            EXPECT_EQ(u.wide_pieces, v.wide_pieces);
            // Their headers name the nozzle: the disk is 1.125 x 0.4 mm, as wide as the lines.
            EXPECT_EQ(u.line_width_source, "nozzle");
            EXPECT_NEAR(u.line_width_mm, 0.45, 1e-9);
            EXPECT_NEAR(a->nozzle_diameter_mm, 0.4, 1e-9);
        }
    }
}

TEST(Uncovered, OpenPiecesReachTheSliceBoundary) {
    // A 10 mm square with a 2 mm wall printed: the 6 mm inside is enclosed; cut the wall at one
    // side and the inside opens to the surface.
    auto square = [](double a, double b) {
        return Path{Point(to_units(a), to_units(a)), Point(to_units(b), to_units(a)),
                    Point(to_units(b), to_units(b)), Point(to_units(a), to_units(b))};
    };
    const Paths slice{square(0, 10)};
    Paths ring{square(0, 10), square(2, 8)};
    std::reverse(ring[1].begin(), ring[1].end());
    const Paths inside = check::difference(slice, ring);
    EXPECT_TRUE(check::open_pieces(slice, inside).empty());
    const Paths cut{Path{Point(to_units(4), 0), Point(to_units(6), 0), Point(to_units(6), 2000),
                         Point(to_units(4), 2000)}};
    const Paths opened = check::difference(slice, check::difference(ring, cut));
    const std::vector<check::OpenPiece> open = check::open_pieces(slice, opened);
    ASSERT_EQ(open.size(), 1u);
    EXPECT_LE(open.front().contact.Y, 5);  // in the 5 um band along the boundary
    const UncoveredPiece p = check::measure_piece(open.front().piece);
    EXPECT_NEAR(p.area_mm2, 36 + 4, 1e-6);
    EXPECT_TRUE(check::holds_disk(open.front().piece, to_units(2)));
    EXPECT_FALSE(check::holds_disk(open.front().piece, to_units(6.01)));
}

Path rect(double x0, double y0, double x1, double y1) {
    return Path{Point(to_units(x0), to_units(y0)), Point(to_units(x1), to_units(y0)),
                Point(to_units(x1), to_units(y1)), Point(to_units(x0), to_units(y1))};
}

// A 10 mm square's wall, 0.45 mm wide.
Paths ring() {
    Paths r{rect(0, 0, 10, 10), rect(0.45, 0.45, 9.55, 9.55)};
    std::reverse(r[1].begin(), r[1].end());
    return r;
}

TEST(Uncovered, SlitClosedOverByTheWallLeavesTheInteriorEnclosed) {
    // The square with a slit 0.2 mm wide cut from its side 7 mm in; the wall goes straight
    // across the slit's mouth. The slit's sides lie inside the wall, narrower than two lines:
    // the inside is the print's interior, not the model left out.
    const Paths model = check::difference({rect(0, 0, 10, 10)}, {rect(3, 4.9, 11, 5.1)});
    check::UncoveredMeter meter;
    EXPECT_NEAR(meter.layer(0, 0.2, model, ring(), kW), 0, 1e-6);
    EXPECT_GT(meter.figures().enclosed_mm2, 70);
    // A slot 2 mm wide is the model's own: the inside beside it is open.
    const Paths slot = check::difference({rect(0, 0, 10, 10)}, {rect(3, 4, 11, 6)});
    check::UncoveredMeter open;
    EXPECT_GT(open.layer(0, 0.2, slot, ring(), kW), 1);
}

TEST(Uncovered, GapInTheWallCountsWithinAMillimetre) {
    // The wall cut 2 mm wide at y = 0: the interior behind the gap is open, counted within 1 mm
    // of the gap's stretch of surface only.
    const Paths wall = check::difference(ring(), {rect(4, -1, 6, 1)});
    check::UncoveredMeter meter;
    const double counted = meter.layer(0, 0.2, {rect(0, 0, 10, 10)}, wall, kW);
    // The gap (1.8 x 0.35 mm of the measured slice) and at most 1 mm around its stretch.
    EXPECT_GT(counted, 0.6);
    EXPECT_LT(counted, 4 * 1.35);
    EXPECT_GT(meter.figures().deep_mm2, 70);
    EXPECT_EQ(meter.figures().wide_pieces, 1);
}

TEST(Uncovered, ModelAboveTheLastLayerIsUncoveredWhole) {
    // The fin's box printed up to z 3 of 5: the 10 layers above count whole, slice and fin.
    std::string gcode = box_gcode(true, Style::kNone);
    gcode = gcode.substr(0, gcode.find("Z3.2"));
    gcode = gcode.substr(0, gcode.rfind('\n') + 1);
    const GcodeAnalysis a = check("half.gcode", gcode);
    const UncoveredFigures& u = a.printability.uncovered;
    EXPECT_EQ(u.layers_above_print, 10);
    const double slice = ((kSide - 0.2) * (kSide - 0.2) + kFinMm2 / kLayers) * 10;
    EXPECT_NEAR(u.uncovered_mm2, slice, 0.01 * slice);
    EXPECT_GE(u.largest.layer, 15);
}

TEST(Uncovered, StrictExitsFiveWhenTheFinIsLeftOut) {
    const auto stl = fin_stl();
    const auto whole = write("strict_fin.gcode", box_gcode(true, Style::kPrusa));
    const auto cut = write("strict_no_fin.gcode", box_gcode(false, Style::kCura));
    test::CarveRun r = test::run_carve("check " + whole.string() + " --mesh " + stl.string() +
                                       " --mesh-offset 0,0 --strict");
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("uncovered        "), std::string::npos) << r.out;
    r = test::run_carve("check " + cut.string() + " --mesh " + stl.string() +
                        " --mesh-offset 0,0 --strict");
    EXPECT_EQ(r.status, 5) << r.out;
    EXPECT_NE(r.err.find("carve: check: fails: model left unprinted"), std::string::npos) << r.err;
    r = test::run_carve("check " + cut.string() + " --mesh " + stl.string() +
                        " --mesh-offset 0,0 --json");
    EXPECT_EQ(r.status, 0);
    for (const char* key : {"\"uncovered_mm2\"", "\"uncovered_percent\"", "\"largest_uncovered\"",
                            "\"area_mm2\"", "\"layer\"", "\"wide_pieces\"", "\"deep_mm2\"",
                            "\"layers_above_print\"", "\"enclosed_mm2\""})
        EXPECT_NE(r.out.find(key), std::string::npos) << key;
}

}  // namespace
}  // namespace carve

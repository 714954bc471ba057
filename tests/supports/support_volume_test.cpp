// Supports under the model's own overhangs: the planner on hand-made outlines (a T, an arch that
// needs none, a part floating above the bed) and the whole run on a mushroom, whose G-code must
// keep the z and xy gaps and leave almost nothing hanging.
#include "supports/support_volume.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"
#include "support/carve_run.hpp"
#include "support/shapes.hpp"
#include "support/stl_boxes.hpp"

namespace carve {
namespace {

using test::rect_region;

SupportOptions options(SupportMode mode = SupportMode::Auto) {
    Settings s;
    s.support = mode;
    return support_options(s, 0.0);
}

// Feeds the outlines (index = layer, bottom up) top down as the pipeline does and collects the
// support of every layer.
std::map<int, SupportLayer> plan_all(const std::vector<Paths>& outlines, SupportOptions o) {
    SupportPlanner planner(o);
    std::map<int, SupportLayer> out;
    for (int i = int(outlines.size()) - 1; i >= 0; --i) {
        planner.add_outline(i, outlines[size_t(i)]);
        for (int j = planner.ready(false); j >= 0; j = planner.ready(false))
            out[j] = planner.plan(j);
    }
    for (int j = planner.ready(true); j >= 0; j = planner.ready(true)) out[j] = planner.plan(j);
    return out;
}

double area_of(const SupportLayer& l) {
    return area_mm2(l.region);
}

// A 10 mm stem, then a 30 mm cap from layer 50: the cap needs support from layer 48 (one layer
// of gap) down to the bed, clear of the stem by the xy gap and of the cap by the z gap.
TEST(SupportPlanner, TShapeIsHeldDownToTheBedWithBothGaps) {
    std::vector<Paths> outlines;
    for (int i = 0; i < 50; ++i) outlines.push_back(rect_region(10000, 10000, 20000, 20000));
    for (int i = 50; i < 60; ++i) outlines.push_back(rect_region(0, 0, 30000, 30000));
    const SupportOptions o = options();
    const auto s = plan_all(outlines, o);
    ASSERT_EQ(s.size(), outlines.size());
    EXPECT_TRUE(s.at(49).region.empty()) << "the z gap";
    EXPECT_GT(area_of(s.at(48)), 500);
    EXPECT_GT(area_mm2(s.at(48).interface), 500);
    EXPECT_GT(s.at(48).new_mm2, 500);
    EXPECT_FALSE(s.at(0).region.empty() && s.at(0).walls.empty()) << "down to the bed";
    for (int j = 0; j < 60; ++j) {
        const Paths& r = s.at(j).region;
        if (r.empty()) continue;
        EXPECT_LT(j, 49);
        // Never closer to the model than the xy gap, in this layer or the next.
        for (int k : {j, j + 1})
            EXPECT_NEAR(area_mm2(intersect(r, dilate(outlines[size_t(k)], o.xy_gap - 5))), 0, 1e-6)
                << "layer " << j;
    }
    // Going down it narrows at the support angle and no layer sticks out past the one below.
    for (int j = 1; j <= 48; ++j) {
        const Paths& above = s.at(j).region;
        const Paths& below = s.at(j - 1).region;
        if (above.empty()) continue;
        EXPECT_LT(area_mm2(subtract(above, dilate(below, o.lean + 20))), 0.5) << "layer " << j;
    }
    EXPECT_LT(area_of(s.at(0)), area_of(s.at(48)));
}

// Two legs leaning towards each other at 45 degrees (0.2 mm per 0.2 mm layer) until they meet:
// an arch that prints without support.
TEST(SupportPlanner, ArchAtFortyFiveDegreesNeedsNone) {
    std::vector<Paths> outlines;
    for (int i = 0; i < 60; ++i) {
        const Coord in = std::min<Coord>(200 * i, 10000);
        outlines.push_back(
            unite(rect_region(0, 0, 5000 + in, 10000), rect_region(25000 - in, 0, 30000, 10000)));
    }
    for (int i = 0; i < 5; ++i) outlines.push_back(rect_region(0, 0, 30000, 10000));
    for (const auto& [j, l] : plan_all(outlines, options())) {
        EXPECT_TRUE(l.region.empty()) << "layer " << j;
        EXPECT_TRUE(l.walls.empty()) << "layer " << j;
    }
}

// A part whose lowest layer is 25 layers above the bed (another part stands on it) is held from
// the bed up; with buildplate only where nothing of the model lies below.
TEST(SupportPlanner, FloatingPartIsHeldFromTheBed) {
    std::vector<Paths> outlines;
    for (int i = 0; i < 50; ++i) {
        Paths o = rect_region(0, 0, 3000, 3000);  // a small post at the side
        if (i >= 25) o = unite(o, rect_region(10000, 0, 20000, 10000));
        outlines.push_back(o);
    }
    const auto s = plan_all(outlines, options());
    EXPECT_TRUE(s.at(24).region.empty());
    for (int j = 0; j <= 23; ++j)
        EXPECT_GT(area_of(s.at(j)) + double(s.at(j).walls.size()), 0) << "layer " << j;
    const BBox2 b = bounds(s.at(0).region);
    EXPECT_GT(b.min_x, 3000);  // under the floating part, not the post
}

// A 20 mm plate from the second layer on a 10 mm foot: the plate's overhang starts 0.2 mm above
// the bed, where a support keeping the z gap would have to stand below the bed. It is held from
// the bed, on layer 0, touching the plate (dense, as an interface), clear of the foot by the xy
// gap. With a z gap of two layers (and a second layer a little wider than the foot), the third
// layer's overhang beyond the second is held there too.
TEST(SupportPlanner, SecondLayerOverhangIsHeldFromTheBed) {
    for (int gap : {1, 2}) {
        std::vector<Paths> outlines;
        outlines.push_back(rect_region(5000, 5000, 15000, 15000));
        if (gap == 2) outlines.push_back(rect_region(4000, 4000, 16000, 16000));
        while (outlines.size() < 12) outlines.push_back(rect_region(0, 0, 20000, 20000));
        SupportOptions o = options();
        o.gap_layers = gap;
        const auto s = plan_all(outlines, o);
        ASSERT_EQ(s.size(), outlines.size());
        const SupportLayer& bed = s.at(0);
        // The plate's ring beyond the foot (400 - 100 mm²), less the xy gap round the foot (and
        // with two layers, the band of the third layer within reach of the second).
        EXPECT_GT(area_mm2(bed.region), 275) << "gap " << gap;
        EXPECT_GT(area_mm2(bed.interface), 275) << "gap " << gap;
        EXPECT_GT(bed.new_mm2, 275) << "gap " << gap;
        // Nothing of it within the xy gap of the foot, the model beside it.
        EXPECT_NEAR(area_mm2(intersect(bed.region, dilate(outlines[0], o.xy_gap - 5))), 0, 1e-6)
            << "gap " << gap;
        for (int j = 1; j < int(outlines.size()); ++j)
            EXPECT_TRUE(s.at(j).region.empty() && s.at(j).walls.empty())
                << "gap " << gap << ", layer " << j;
    }
}

// The 12 triangles of a box, for ModelShadow.
void add_box(std::vector<Vec3>& v, std::vector<std::array<uint32_t, 3>>& t, double x0, double y0,
             double z0, double x1, double y1, double z1) {
    const uint32_t b = static_cast<uint32_t>(v.size());
    for (int k = 0; k < 8; ++k) v.push_back({k & 1 ? x1 : x0, k & 2 ? y1 : y0, k & 4 ? z1 : z0});
    const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& f : faces) {
        t.push_back({b + f[0], b + f[1], b + f[2]});
        t.push_back({b + f[0], b + f[2], b + f[3]});
    }
}

// A shelf (x 0..30, from z 5) on a post (x 0..10), with a low block (x 20..30, z 0..2) under the
// shelf's far end: auto stands the support on the block as well, buildplate only beside it.
TEST(SupportPlanner, BuildplateKeepsOffWhatTheModelHasBelow) {
    std::vector<Vec3> v;
    std::vector<std::array<uint32_t, 3>> t;
    add_box(v, t, 0, 0, 0, 10, 10, 5);
    add_box(v, t, 0, 0, 5, 30, 10, 10);
    add_box(v, t, 20, 0, 0, 30, 10, 2);
    const ModelShadow shadow(v, t, 0.5);
    EXPECT_TRUE(shadow.below(-1, 0).empty());
    EXPECT_NEAR(area_mm2(shadow.below(1.0, 0)), 200, 25);  // the post and the block
    EXPECT_NEAR(area_mm2(shadow.below(7.0, 0)), 300, 30);  // and the shelf

    std::vector<Paths> outlines;
    for (int i = 0; i < 50; ++i) {
        Paths o = i < 25 ? rect_region(0, 0, 10000, 10000) : rect_region(0, 0, 30000, 10000);
        if (i < 10) o = unite(o, rect_region(20000, 0, 30000, 10000));
        outlines.push_back(o);
    }
    const auto with_auto = plan_all(outlines, options(SupportMode::Auto));
    SupportPlanner planner(options(SupportMode::Buildplate), &shadow);
    std::map<int, SupportLayer> plate;
    for (int i = 49; i >= 0; --i) {
        planner.add_outline(i, outlines[size_t(i)]);
        for (int j = planner.ready(false); j >= 0; j = planner.ready(false))
            plate[j] = planner.plan(j);
    }
    for (int j = planner.ready(true); j >= 0; j = planner.ready(true)) plate[j] = planner.plan(j);
    const BBox2 a = bounds(with_auto.at(20).region), p = bounds(plate.at(20).region);
    EXPECT_GT(a.max_x, 25000);  // over the block too (it stops on the block's top)
    EXPECT_LT(p.max_x, 20000);  // only where the bed is below
    EXPECT_GT(p.min_x, 10000);
    EXPECT_TRUE(with_auto.at(10).region.empty() || bounds(with_auto.at(10).region).max_x < 20000);
    EXPECT_FALSE(plate.at(0).region.empty() && plate.at(0).walls.empty());
}

// Where the G-code extrudes support: the end of every move that extrudes and moves under a
// ;TYPE: naming support (an unretract in place keeps the last ;TYPE: until the next path
// names its own, so it is not a support point).
struct GcodePoint {
    double x, y, z;
};
std::vector<GcodePoint> support_points(const std::string& gcode) {
    std::vector<GcodePoint> out;
    std::istringstream in(gcode);
    std::string line, type;
    double z = 0, x = 0, y = 0, e = 0;
    while (std::getline(in, line)) {
        if (line.rfind(";TYPE:", 0) == 0) type = line.substr(6);
        if (line.rfind("G1", 0) != 0) continue;
        double nx = x, ny = y, nz = z, ne = e;
        std::istringstream words(line.substr(2, line.find(';') - 2));
        std::string w;
        while (words >> w) {
            const double v = std::stod(w.substr(1));
            if (w[0] == 'X') nx = v;
            if (w[0] == 'Y') ny = v;
            if (w[0] == 'Z') nz = v;
            if (w[0] == 'E') ne = v;
        }
        if (ne > e && (nx != x || ny != y) && type.rfind("Support", 0) == 0)
            out.push_back({nx, ny, nz});
        x = nx, y = ny, z = nz, e = ne;
    }
    return out;
}

// Distance from p to the 10 x 10 mm foot both end-to-end shapes stand on, once carve has
// centred them on the 250 x 210 bed: x 120..130, y 100..110.
double distance_to_foot(const GcodePoint& p) {
    const double dx = std::max({120 - p.x, p.x - 130, 0.0});
    const double dy = std::max({100 - p.y, p.y - 110, 0.0});
    return std::hypot(dx, dy);
}

// `carve check GCODE --mesh MESH --json EXTRA`, parsed.
nlohmann::json check_json(const std::string& gcode, const std::string& mesh,
                          const std::string& extra = "") {
    const auto r = test::run_carve("check " + gcode + " --mesh " + mesh + " --json" + extra);
    EXPECT_EQ(r.status, 0) << r.err;
    return nlohmann::json::parse(r.out);
}

nlohmann::json json_of(const std::string& path) {
    std::ifstream in(path);
    return nlohmann::json::parse(in);
}

// The whole run on a mushroom (10 mm stem to z 10.1, 30 x 30 mm cap above): support material in
// the G-code under its own types, the cap held (far hanging overhang under a tenth of what it is
// without supports), the z gap (no support at the layer under the cap) and the xy gap (no
// support point within the gap of the stem) kept, and nothing else outside the model.
TEST(SupportCli, MushroomKeepsBothGapsAndHoldsTheCap) {
    const auto dir = test::scratch();
    std::vector<test::StlTriangle> t;
    test::add_box(t, 10, 10, 0, 20, 20, 10.1f);
    test::add_box(t, 0, 0, 10, 30, 30, 14);
    const std::string mushroom = test::write_stl("support_mushroom.stl", t).string();
    const std::string none = (dir / "none.gcode").string(), with = (dir / "auto.gcode").string();
    const std::string stats = (dir / "auto.json").string();
    auto r = test::run_carve("slice " + mushroom + " -o " + none + " -q");
    ASSERT_EQ(r.status, 0) << r.err;
    r = test::run_carve("slice " + mushroom + " -o " + with + " --stats " + stats +
                        " --support auto -q");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(test::read(none).find("Support"), std::string::npos);
    const std::string g = test::read(with);
    EXPECT_NE(g.find(";TYPE:Support material\n"), std::string::npos);
    EXPECT_NE(g.find(";TYPE:Support material interface\n"), std::string::npos);
    // The configuration block names the supports (it does not without them).
    EXPECT_NE(g.find("\n; support_material = 1\n"), std::string::npos);
    EXPECT_NE(g.find("\n; support_material_contact_distance = 0.2\n"), std::string::npos);
    EXPECT_EQ(test::read(none).find("support_material_contact_distance"), std::string::npos);
    const auto j = json_of(stats);
    EXPECT_GT(j["support_volume_mm3"].get<double>(), 0);
    EXPECT_GT(j["supported_area_mm2"].get<double>(), 500);
    EXPECT_EQ(j["settings"]["support"], "auto");

    // The G-code: the mesh is centred on the 250 x 210 bed, so the stem is x 120..130,
    // y 100..110; the cap's first layer is the one at z 10.2.
    double top = 0;
    const double keep = 0.25 + 0.2 - 0.02;  // xy gap + half a line, less rounding
    const std::vector<GcodePoint> points = support_points(g);
    for (const GcodePoint& p : points) {
        top = std::max(top, p.z);
        EXPECT_GE(distance_to_foot(p), keep) << p.x << ", " << p.y << " at z " << p.z;
    }
    EXPECT_GT(points.size(), 100u);
    EXPECT_NEAR(top, 9.8, 1e-6) << "the support's top leaves one layer under the cap at 10.2";

    const auto a = check_json(none, mushroom);
    const auto b = check_json(with, mushroom);
    EXPECT_GT(a["hanging_overhang_mm2"].get<double>(), 500);
    EXPECT_LT(b["hanging_overhang_mm2"].get<double>(),
              0.1 * a["hanging_overhang_mm2"].get<double>());
    EXPECT_GT(b["outside_support_mm2"].get<double>(), 0);
    EXPECT_LT(b["outside_other_mm2"].get<double>(), 1.0);
}

// The same on a whole run: a 20 x 20 mm plate from z 0.2 on a 10 x 10 mm foot one layer high.
// Its overhang hangs unless the first layer holds it; carve check counts support printed on the
// bed under it as held.
TEST(SupportCli, PlateOnAOneLayerFootIsHeldByTheFirstLayer) {
    const auto dir = test::scratch();
    std::vector<test::StlTriangle> t;
    test::add_box(t, 5, 5, 0, 15, 15, 0.2f);
    test::add_box(t, 0, 0, 0.2f, 20, 20, 2);
    const std::string plate = test::write_stl("support_plate_on_foot.stl", t).string();
    const std::string none = (dir / "plate_none.gcode").string();
    const std::string with = (dir / "plate_auto.gcode").string();
    auto r = test::run_carve("slice " + plate + " -o " + none + " -q");
    ASSERT_EQ(r.status, 0) << r.err;
    r = test::run_carve("slice " + plate + " -o " + with + " --support auto -q");
    ASSERT_EQ(r.status, 0) << r.err;
    // The first layer's support keeps the xy gap from the foot (x 120..130, y 100..110 once
    // centred on the 250 x 210 bed), and stands there only: the plate is above it.
    const double keep = 0.25 + 0.2 - 0.02;  // xy gap + half a line, less rounding
    const std::vector<GcodePoint> points = support_points(test::read(with));
    for (const GcodePoint& p : points) {
        EXPECT_NEAR(p.z, 0.2, 1e-6) << p.x << ", " << p.y;
        EXPECT_GE(distance_to_foot(p), keep) << p.x << ", " << p.y;
    }
    EXPECT_GT(points.size(), 50u);

    const auto a = check_json(none, plate, " --support-gap 0.4");
    const auto b = check_json(with, plate, " --support-gap 0.4");
    EXPECT_GT(a["hanging_overhang_mm2"].get<double>(), 100);
    EXPECT_LT(b["hanging_overhang_mm2"].get<double>(),
              0.1 * a["hanging_overhang_mm2"].get<double>());
    EXPECT_GT(b["support_volume_mm3"].get<double>(), 0);
    EXPECT_LT(b["outside_other_mm2"].get<double>(), 1.0);
}

}  // namespace
}  // namespace carve

// --orient auto (issue #48): the convex hull's planes, a tilted box laid flat on a face, a T that
// needs supports as given and none upside down, and the default leaving the model as it lies.
#include "mesh/orient.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "support/carve_run.hpp"
#include "support/sanitizers.hpp"
#include "support/stl_boxes.hpp"

namespace carve {
namespace {

using test::StlTriangle;

// Every corner turned by `deg` about x.
std::vector<StlTriangle> turned_x(std::vector<StlTriangle> t, double deg) {
    const double a = deg * std::numbers::pi / 180, c = std::cos(a), s = std::sin(a);
    for (auto& tri : t)
        for (auto& v : tri) {
            const double y = v[1], z = v[2];
            v[1] = float(c * y - s * z);
            v[2] = float(s * y + c * z);
        }
    return t;
}

nlohmann::json stats_of(const std::string& model, const std::string& name,
                        const std::string& options) {
    const auto gcode = test::scratch() / (name + ".gcode");
    const auto stats = test::scratch() / (name + ".json");
    const test::CarveRun r = test::run_carve("slice " + model + " -o " + gcode.string() +
                                             " --stats " + stats.string() + " " + options);
    EXPECT_EQ(r.status, 0) << r.err;
    return nlohmann::json::parse(test::read(stats));
}

// A candidate that needs supports: carved with them, or given up part way as heavier than the
// one chosen (its layers so far, with the least those to come extrude, outweighed it).
void needs_more(const nlohmann::json& orientation, size_t k) {
    const nlohmann::json& c = orientation["candidates"][k];
    double chosen = 0;
    for (const auto& d : orientation["candidates"])
        if (d["chosen"].get<bool>()) chosen = d["extruded_volume_mm3"].get<double>();
    if (c["given_up"].get<bool>())
        EXPECT_GT(c["extruded_at_least_mm3"].get<double>(), chosen) << c.dump();
    else
        EXPECT_GT(c["support_volume_mm3"].get<double>(), 0) << c.dump();
}

Vec3 times(const nlohmann::json& m, const Vec3& v) {
    return {
        m[0][0].get<double>() * v.x + m[0][1].get<double>() * v.y + m[0][2].get<double>() * v.z,
        m[1][0].get<double>() * v.x + m[1][1].get<double>() * v.y + m[1][2].get<double>() * v.z,
        m[2][0].get<double>() * v.x + m[2][1].get<double>() * v.y + m[2][2].get<double>() * v.z};
}

TEST(HullPlanes, BoxHasSixFacesOfItsAreas) {
    Mesh box;
    for (int k = 0; k < 8; ++k)
        box.vertices.push_back({k & 1 ? 30.0 : 0, k & 2 ? 20.0 : 0, k & 4 ? 10.0 : 0});
    // Points inside the box add nothing to its hull.
    box.vertices.push_back({15, 10, 5});
    box.vertices.push_back({1, 19, 9});
    const std::vector<HullPlane> planes = hull_planes(box.vertices);
    ASSERT_EQ(planes.size(), 6u);
    EXPECT_NEAR(planes[0].area_mm2, 600, 1e-9);  // 30 x 20, top and bottom first
    EXPECT_NEAR(planes[1].area_mm2, 600, 1e-9);
    EXPECT_NEAR(planes[2].area_mm2, 300, 1e-9);  // 30 x 10
    EXPECT_NEAR(planes[5].area_mm2, 200, 1e-9);  // 20 x 10
    EXPECT_NEAR(std::fabs(planes[0].normal.z), 1, 1e-12);
    // Flat points span no volume: no hull, and only the six axis turns are proposed.
    Mesh flat;
    for (int k = 0; k < 4; ++k) flat.vertices.push_back({k & 1 ? 1.0 : 0, k & 2 ? 1.0 : 0, 0});
    EXPECT_TRUE(hull_planes(flat.vertices).empty());
    EXPECT_EQ(orientation_candidates(flat, 6).size(), 6u);
}

// A real mesh (the repository's fandisk, 6,475 vertices, many of them coplanar on its flat
// faces): rounding once made the hull's visible patches pinched or inside out, and the hull grew
// until memory ran out. Its area is Qhull's (scipy.spatial.ConvexHull of the same vertices:
// 14,647.5 mm2).
TEST(HullPlanes, FandiskHullIsQhulls) {
    MeshReport report;
    const Mesh mesh = load_mesh(std::string(CARVE_SOURCE_DIR) + "/data/sample/fandisk.stl", report);
    const std::vector<HullPlane> planes = hull_planes(mesh.vertices);
    ASSERT_FALSE(planes.empty());
    double hull_area = 0;
    for (const HullPlane& p : planes) hull_area += p.area_mm2;
    // Within 0.5 %: points level with the hull within rounding are dropped rather than risk a
    // facet inside out (14,632 mm2 here); the broken hull had 16,834.
    EXPECT_NEAR(hull_area, 14647.5, 0.005 * 14647.5);
    // Laid on its largest hull plane, the model stands on a facet: three vertices or more at its
    // lowest height.
    Mesh turned = mesh;
    rotate_mesh(turned, lay_down(planes[0].normal));
    const BBox3 box = bounding_box(turned);
    int on_bed = 0;
    for (const Vec3& v : turned.vertices) on_bed += v.z < box.min.z + 1e-3;
    EXPECT_GE(on_bed, 3);
}

TEST(HullPlanes, LayDownTurnsTheFaceOntoTheBed) {
    const Vec3 n{0.6, -0.48, 0.64};
    const Vec3 d = lay_down(n).apply(n);
    EXPECT_NEAR(d.x, 0, 1e-12);
    EXPECT_NEAR(d.y, 0, 1e-12);
    EXPECT_NEAR(d.z, -1, 1e-12);
    const Vec3 up = lay_down({0, 0, 1}).apply({0, 0, 1});
    EXPECT_NEAR(up.z, -1, 1e-12);
}

// A 30 x 20 x 10 box turned 30 degrees about x: its lower faces lean 60 degrees from vertical,
// past the 45 the printer holds, so as given it needs supports; --orient auto lays a face flat.
// (At exactly 45 degrees the box needs neither supports nor covers over its sloping faces, and
// carve rightly keeps it on its edge: fewer cover layers than any face down.)
TEST(OrientAuto, TiltedBoxIsLaidFlatOnAFace) {
    std::vector<StlTriangle> t;
    test::add_box(t, 0, 0, 0, 30, 20, 10);
    const double tilt = 30;
    const std::string model = test::write_stl("tilted_box.stl", turned_x(t, tilt)).string();
    const nlohmann::json j = stats_of(model, "tilted_box", "--orient auto");
    ASSERT_TRUE(j.contains("orientation"));
    const nlohmann::json& o = j["orientation"];
    ASSERT_GE(o["candidates"].size(), 6u);
    needs_more(o, 0);  // as given
    // One of the box's faces (their normals turned with it) faces the bed.
    const double a = tilt * std::numbers::pi / 180;
    const std::vector<Vec3> normals{{1, 0, 0},
                                    {-1, 0, 0},
                                    {0, std::cos(a), std::sin(a)},
                                    {0, -std::cos(a), -std::sin(a)},
                                    {0, -std::sin(a), std::cos(a)},
                                    {0, std::sin(a), -std::cos(a)}};
    int flat = 0;
    for (const Vec3& n : normals)
        if (times(o["chosen"]["matrix"], n).z < -1 + 1e-6) ++flat;
    EXPECT_EQ(flat, 1) << o["chosen"].dump();
    bool chosen_listed = false;
    for (const auto& c : o["candidates"])
        if (c["chosen"].get<bool>()) {
            chosen_listed = true;
            EXPECT_EQ(c["support_volume_mm3"].get<double>(), 0);
        }
    EXPECT_TRUE(chosen_listed);
}

// A T: a 40 x 40 x 4 cap on a 10 x 10 x 40 stem needs supports under the cap as given, and none
// upside down, standing on the cap.
TEST(OrientAuto, TeeStandsOnItsCap) {
    SKIP_UNDER_SANITIZERS("TiltedBoxIsLaidFlatOnAFace: the same candidates' runs, smaller");
    std::vector<StlTriangle> t;
    test::add_box(t, 15, 15, 0, 25, 25, 40);
    test::add_box(t, 0, 0, 40, 40, 40, 44);
    const std::string model = test::write_stl("tee.stl", t).string();
    const auto gcode = test::scratch() / "tee_auto.gcode";
    const test::CarveRun r = test::run_carve("slice " + model + " -o " + gcode.string() +
                                             " --orient auto --support auto");
    ASSERT_EQ(r.status, 0) << r.err;
    // The summary lists every candidate and marks the one chosen; the header names it.
    EXPECT_NE(r.out.find("  * x+180 (180.0 deg about 1.000,0.000,0.000)"), std::string::npos)
        << r.out;
    EXPECT_NE(test::read(gcode).find("; orientation = x+180 (180.0 deg about"), std::string::npos);
    const nlohmann::json j = stats_of(model, "tee", "--orient auto --support auto");
    EXPECT_EQ(j["orientation"]["chosen"]["name"], "x+180");
    needs_more(j["orientation"], 0);
    EXPECT_EQ(j["support_volume_mm3"].get<double>(), 0);
}

// The bound a candidate is given up by counts the supports its layers below would print (planned
// as the run plans them): the T as given, whose supports under the cap outweigh the T upside down
// by themselves, is given up within its cap's layers, before it carves any layer of its stem (a
// bound of walls and covers alone carried it 12 layers down, two into the stem), or before it
// carves any.
TEST(OrientAuto, SupportsToComeGiveACandidateUpBeforeItCarvesThem) {
    SKIP_UNDER_SANITIZERS("TiltedBoxIsLaidFlatOnAFace: the same candidates' runs, smaller");
    std::vector<StlTriangle> t;
    test::add_box(t, 15, 15, 0, 25, 25, 40);
    test::add_box(t, 0, 0, 40, 40, 40, 44);
    const std::string model = test::write_stl("tee_bound.stl", t).string();
    const nlohmann::json j = stats_of(model, "tee_bound", "--orient auto --support auto");
    const nlohmann::json& given = j["orientation"]["candidates"][0];
    ASSERT_EQ(given["name"], "as given");
    ASSERT_TRUE(given["given_up"].get<bool>()) << given.dump();
    const int carved = given["layers"].get<int>() - given["layers_not_carved"].get<int>();
    const double cap_layers = 4 / given["layer_height_mm"].get<double>();
    EXPECT_GE(carved, 0);
    EXPECT_LE(carved, cap_layers) << given.dump();
}

// The default is the orientation given: the same G-code as --orient given, no orientation in the
// header or the stats.
TEST(OrientAuto, DefaultLeavesTheModelAsGiven) {
    std::vector<StlTriangle> t;
    test::add_box(t, 15, 15, 0, 25, 25, 40);
    test::add_box(t, 0, 0, 40, 40, 40, 44);
    const std::string model = test::write_stl("tee_given.stl", t).string();
    const nlohmann::json plain = stats_of(model, "plain", "--support auto");
    const nlohmann::json given = stats_of(model, "given", "--support auto --orient given");
    EXPECT_FALSE(plain.contains("orientation"));
    EXPECT_GT(plain["support_volume_mm3"].get<double>(), 0);  // the cap still overhangs
    const std::string a = test::read(test::scratch() / "plain.gcode");
    EXPECT_EQ(a, test::read(test::scratch() / "given.gcode"));
    EXPECT_EQ(a.find("orientation"), std::string::npos);
}

// A model that fits in no orientation is refused with one line, and nothing is written.
TEST(OrientAuto, NothingFitsIsRefused) {
    std::vector<StlTriangle> t;
    test::add_box(t, 0, 0, 0, 300, 300, 300);
    const std::string model = test::write_stl("huge.stl", t).string();
    const auto gcode = test::scratch() / "huge.gcode";
    const test::CarveRun r =
        test::run_carve("slice " + model + " -o " + gcode.string() + " --orient auto");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("--orient auto: no orientation fits the printer"), std::string::npos)
        << r.err;
    EXPECT_FALSE(std::filesystem::exists(gcode));
    for (const auto& e : std::filesystem::directory_iterator(test::scratch()))
        EXPECT_EQ(e.path().filename().string().find(".carve-tmp"), std::string::npos);
}

}  // namespace
}  // namespace carve

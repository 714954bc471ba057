// cut_across_z and plan_cuts (mesh/cut.hpp): closed pieces whose volumes add up, connectors at
// the same place in both faces, and --cut auto's fewest planes.
#include "mesh/cut.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "base/error.hpp"

namespace carve {
namespace {

Mesh box(double x, double y, double z) {
    Mesh m;
    m.vertices = {{0, 0, 0}, {x, 0, 0}, {x, y, 0}, {0, y, 0},
                  {0, 0, z}, {x, 0, z}, {x, y, z}, {0, y, z}};
    m.triangles = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                   {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
    return m;
}

Mesh sphere(double r, int rings, int sectors) {
    Mesh m;
    m.vertices.push_back({0, 0, -r});
    for (int i = 1; i < rings; ++i) {
        const double phi = std::numbers::pi * i / rings - std::numbers::pi / 2;
        for (int j = 0; j < sectors; ++j) {
            const double t = 2 * std::numbers::pi * j / sectors;
            m.vertices.push_back({r * std::cos(phi) * std::cos(t), r * std::cos(phi) * std::sin(t),
                                  r * std::sin(phi)});
        }
    }
    m.vertices.push_back({0, 0, r});
    auto at = [&](int i, int j) { return uint32_t(1 + (i - 1) * sectors + (j % sectors)); };
    const uint32_t top = uint32_t(m.vertices.size() - 1);
    for (int j = 0; j < sectors; ++j) {
        m.triangles.push_back({0, at(1, j + 1), at(1, j)});
        m.triangles.push_back({top, at(rings - 1, j), at(rings - 1, j + 1)});
        for (int i = 1; i < rings - 1; ++i) {
            m.triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
            m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
        }
    }
    return m;
}

void expect_sound(const Mesh& m) {
    Mesh copy = m;
    MeshReport report;
    analyse_and_repair(copy, report);
    EXPECT_TRUE(report.closed());
    EXPECT_EQ(report.flipped_triangles, 0u);
    EXPECT_FALSE(report.inverted);
    EXPECT_GT(signed_volume(m), 0);
}

TEST(Cut, BoxWithoutConnectorsAddsUp) {
    const Mesh m = box(20, 30, 100);
    ConnectorSpec none;
    none.kind = ConnectorKind::None;
    const std::vector<MeshPiece> pieces = cut_across_z(m, {40}, none);
    ASSERT_EQ(pieces.size(), 2u);
    for (const MeshPiece& p : pieces) expect_sound(p.mesh);
    EXPECT_NEAR(signed_volume(pieces[0].mesh), 20 * 30 * 40, 1e-3);
    EXPECT_NEAR(signed_volume(pieces[1].mesh), 20 * 30 * 60, 1e-3);
    EXPECT_NEAR(bounding_box(pieces[0].mesh).max.z, 40, 1e-5);
    EXPECT_NEAR(bounding_box(pieces[1].mesh).min.z, 40, 1e-5);
}

TEST(Cut, DowelHolesMatchInBothFaces) {
    const Mesh m = box(40, 30, 100);
    ConnectorSpec dowel;
    const std::vector<MeshPiece> pieces = cut_across_z(m, {50, 75}, dowel);
    ASSERT_EQ(pieces.size(), 3u);
    double total = 0;
    for (const MeshPiece& p : pieces) {
        expect_sound(p.mesh);
        total += signed_volume(p.mesh);
    }
    ASSERT_EQ(pieces[0].connectors.size(), 2u);
    ASSERT_EQ(pieces[1].connectors.size(), 4u);  // two below, two above
    ASSERT_EQ(pieces[2].connectors.size(), 2u);
    const double r = dowel.diameter_mm / 2 + dowel.clearance_mm;
    double holes = 0;
    for (const MeshPiece& p : pieces)
        for (const Connector& c : p.connectors) {
            EXPECT_FALSE(c.pin);
            EXPECT_NEAR(c.diameter_mm / 2, r, 1e-9);
            // Clear of the outer wall by the margin.
            EXPECT_GE(c.x, r + dowel.margin_mm - 0.01);
            EXPECT_LE(c.x, 40 - r - dowel.margin_mm + 0.01);
            EXPECT_GE(c.y, r + dowel.margin_mm - 0.01);
            holes += 32 * r * r * std::tan(std::numbers::pi / 32) * c.depth_mm;
        }
    for (size_t k = 0; k < 2; ++k) {
        EXPECT_NEAR(pieces[0].connectors[k].x, pieces[1].connectors[k].x, 1e-9);
        EXPECT_NEAR(pieces[0].connectors[k].y, pieces[1].connectors[k].y, 1e-9);
    }
    EXPECT_GT(std::hypot(pieces[0].connectors[0].x - pieces[0].connectors[1].x,
                         pieces[0].connectors[0].y - pieces[0].connectors[1].y),
              20);
    // The pieces and the holes make up the model.
    EXPECT_NEAR(total + holes, 40 * 30 * 100, 1e-3 * 40 * 30 * 100);
}

TEST(Cut, PinsStandOnThePieceBelow) {
    const Mesh m = box(40, 30, 100);
    ConnectorSpec pin;
    pin.kind = ConnectorKind::Pin;
    const std::vector<MeshPiece> pieces = cut_across_z(m, {50}, pin);
    ASSERT_EQ(pieces.size(), 2u);
    for (const MeshPiece& p : pieces) expect_sound(p.mesh);
    ASSERT_EQ(pieces[0].connectors.size(), 2u);
    EXPECT_TRUE(pieces[0].connectors[0].pin);
    EXPECT_FALSE(pieces[1].connectors[0].pin);
    EXPECT_NEAR(bounding_box(pieces[0].mesh).max.z, 50 + pin.depth_mm - pin.clearance_mm, 1e-5);
    EXPECT_GT(pieces[1].connectors[0].diameter_mm, pieces[0].connectors[0].diameter_mm);
}

// The piece carrying the pins never stands on them: across x it lies with its pinned face up,
// on the box's flat end (what touches the bed spans the whole 60 x 40 end, not a pin's tip);
// across z the lower piece stays as it was.
TEST(Cut, APieceWithPinsIsNotLaidOnThem) {
    ConnectorSpec pin;
    pin.kind = ConnectorKind::Pin;
    CutPlane across_x;
    across_x.point = {150, 0, 0};
    across_x.normal = {1, 0, 0};
    for (MeshPiece& p : cut_by_planes(box(300, 60, 40), {across_x}, pin)) {
        rotate_mesh(p.mesh, lay_on_cut_face(p));
        const BBox3 b = bounding_box(p.mesh);
        double lo_x = 1e9, hi_x = -1e9, lo_y = 1e9, hi_y = -1e9;
        for (const Vec3& v : p.mesh.vertices)
            if (v.z < b.min.z + 0.01)
                lo_x = std::min(lo_x, v.x), hi_x = std::max(hi_x, v.x), lo_y = std::min(lo_y, v.y),
                hi_y = std::max(hi_y, v.y);
        const double sx = hi_x - lo_x, sy = hi_y - lo_y;
        EXPECT_NEAR(std::max(sx, sy), 60, 0.01);
        EXPECT_NEAR(std::min(sx, sy), 40, 0.01);
    }
    const std::vector<MeshPiece> z = cut_across_z(box(40, 30, 100), {50}, pin);
    ASSERT_EQ(z.size(), 2u);
    ASSERT_TRUE(z[0].connectors[0].pin);
    Mesh lower = z[0].mesh;
    const BBox3 before = bounding_box(lower);
    rotate_mesh(lower, lay_on_cut_face(z[0]));
    const BBox3 after = bounding_box(lower);
    EXPECT_NEAR(after.max.z - after.min.z, before.max.z - before.min.z, 1e-6);
    EXPECT_NEAR(after.max.x - after.min.x, 40, 1e-6);
}

TEST(Cut, SphereSectionsAreCapped) {
    const Mesh m = sphere(30, 40, 64);
    const double v = signed_volume(m);
    ConnectorSpec none;
    none.kind = ConnectorKind::None;
    const std::vector<MeshPiece> pieces = cut_across_z(m, {-12.3, 0.0, 17}, none);
    ASSERT_EQ(pieces.size(), 4u);
    double total = 0;
    for (const MeshPiece& p : pieces) {
        expect_sound(p.mesh);
        total += signed_volume(p.mesh);
    }
    EXPECT_NEAR(total, v, 1e-6 * v);
    EXPECT_NEAR(section_area_mm2(m, 0.0), std::numbers::pi * 30 * 30, 0.01 * 900 * 3.1416);
}

TEST(Cut, AutoPlansTheFewestPieces) {
    const Mesh m = box(20, 30, 400);
    CutLimits limits;
    limits.max_x = 250;
    limits.max_y = 210;
    limits.max_height = 210;
    const std::vector<double> zs = plan_cuts(m, limits, "tall.stl");
    ASSERT_EQ(zs.size(), 1u);
    EXPECT_GE(zs[0], 190);
    EXPECT_LE(zs[0], 210);
    // A slab wider than the bed is refused, naming its height.
    const Mesh wide = box(300, 300, 50);
    try {
        plan_cuts(wide, limits, "wide.stl");
        FAIL() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("larger than the"), std::string::npos) << e.what();
    }
}

TEST(Cut, APlaneAcrossXIsTurnedOntoZAndBack) {
    const Mesh m = box(100, 20, 30);
    ConnectorSpec spec;
    const std::vector<MeshPiece> pieces = cut_by_planes(m, {{{40, 0, 0}, {1, 0, 0}}}, spec);
    ASSERT_EQ(pieces.size(), 2u);
    for (const MeshPiece& p : pieces) {
        expect_sound(p.mesh);
        ASSERT_EQ(p.faces.size(), 1u);
        EXPECT_NEAR(p.faces[0].area_mm2, 20 * 30, 1e-6);
        ASSERT_FALSE(p.connectors.empty());
        for (const Connector& c : p.connectors) EXPECT_NEAR(c.x, 40, 1e-6);
    }
    EXPECT_NEAR(bounding_box(pieces[0].mesh).max.x, 40, 1e-3);
    EXPECT_NEAR(bounding_box(pieces[1].mesh).min.x, 40, 1e-3);
    EXPECT_NEAR(pieces[0].faces[0].outward.x, 1, 1e-12);
    EXPECT_NEAR(pieces[1].faces[0].outward.x, -1, 1e-12);
    EXPECT_NEAR(signed_volume(pieces[0].mesh) + signed_volume(pieces[1].mesh), 100 * 20 * 30,
                0.01 * 100 * 20 * 30);
    // Laid on its cut face: the face (at x = 40) goes to the bottom.
    Mesh laid = pieces[0].mesh;
    rotate_mesh(laid, lay_on_cut_face(pieces[0]));
    const BBox3 b = bounding_box(laid);
    EXPECT_NEAR(b.max.z - b.min.z, 40, 1e-6);
    // A plane that misses the model is refused.
    EXPECT_THROW(cut_by_planes(m, {{{200, 0, 0}, {1, 0, 0}}}, spec), InputError);
    // A plane across z gives the pieces cut_across_z gives.
    const std::vector<MeshPiece> by_plane = cut_by_planes(m, {{{0, 0, 10}, {0, 0, 1}}}, spec);
    const std::vector<MeshPiece> by_z = cut_across_z(m, {10}, spec);
    ASSERT_EQ(by_plane.size(), 2u);
    for (size_t k = 0; k < 2; ++k)
        EXPECT_NEAR(signed_volume(by_plane[k].mesh), signed_volume(by_z[k].mesh), 1e-6);
}

TEST(Cut, PlanarAutoCutsALongBoxAcrossX) {
    CutLimits limits;
    limits.max_x = 250;
    limits.max_y = 210;
    limits.max_height = 210;
    double area = 0;
    const std::vector<CutPlane> planes =
        plan_planar_cuts(box(300, 60, 40), limits, std::numeric_limits<size_t>::max(), 0, area);
    ASSERT_EQ(planes.size(), 1u);
    EXPECT_NEAR(planes[0].normal.x, 1, 1e-12);
    EXPECT_NEAR(area, 60 * 40, 1e-6);
    // No plan better than one of a single piece.
    EXPECT_TRUE(plan_planar_cuts(box(300, 60, 40), limits, 1, 0, area).empty());
}

}  // namespace
}  // namespace carve

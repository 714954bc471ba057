// Tests of the streaming top-down slicer on programmatic shapes (sphere, torus, boxes, an
// octahedron, open and multi-shell meshes) and on the real models of the developer set.
#include "slice/slicer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>

#include "base/error.hpp"
#include "geometry/polygon.hpp"
#include "support/models.hpp"
#include "support/test_rng.hpp"

using namespace carve;

namespace {

constexpr double kPi = std::numbers::pi;

// ---- programmatic meshes, counter-clockwise seen from outside ----

Mesh uv_sphere(double radius, int segments, int rings, Vec3 c = {}) {
    Mesh m;
    m.vertices.push_back({c.x, c.y, c.z + radius});  // north pole
    for (int j = 1; j < rings; ++j) {
        const double theta = kPi * j / rings;
        for (int k = 0; k < segments; ++k) {
            const double phi = 2 * kPi * k / segments;
            m.vertices.push_back({c.x + radius * std::sin(theta) * std::cos(phi),
                                  c.y + radius * std::sin(theta) * std::sin(phi),
                                  c.z + radius * std::cos(theta)});
        }
    }
    m.vertices.push_back({c.x, c.y, c.z - radius});  // south pole
    const uint32_t south = uint32_t(m.vertices.size() - 1);
    auto at = [&](int j, int k) { return uint32_t(1 + (j - 1) * segments + (k % segments)); };
    for (int k = 0; k < segments; ++k) {
        m.triangles.push_back({0, at(1, k), at(1, k + 1)});
        m.triangles.push_back({south, at(rings - 1, k + 1), at(rings - 1, k)});
        for (int j = 1; j + 1 < rings; ++j) {
            // a above-left, b above-right, c below-left, d below-right (phi grows to the right)
            const uint32_t a = at(j, k), b = at(j, k + 1), cc = at(j + 1, k), d = at(j + 1, k + 1);
            m.triangles.push_back({a, cc, d});
            m.triangles.push_back({a, d, b});
        }
    }
    return m;
}

Mesh torus(double major, double minor, int nu, int nv) {
    Mesh m;
    for (int i = 0; i < nu; ++i) {
        const double u = 2 * kPi * i / nu;
        for (int j = 0; j < nv; ++j) {
            const double v = 2 * kPi * j / nv;
            const double rho = major + minor * std::cos(v);
            m.vertices.push_back({rho * std::cos(u), rho * std::sin(u), minor * std::sin(v)});
        }
    }
    auto at = [&](int i, int j) { return uint32_t((i % nu) * nv + (j % nv)); };
    for (int i = 0; i < nu; ++i)
        for (int j = 0; j < nv; ++j) {
            const uint32_t a = at(i, j), b = at(i + 1, j), c = at(i, j + 1), d = at(i + 1, j + 1);
            m.triangles.push_back({a, b, d});
            m.triangles.push_back({a, d, c});
        }
    return m;
}

// A vertical prism over a convex counter-clockwise polygon, with vertex rings at the heights zs
// (ascending) and fan-triangulated caps.
Mesh prism(const std::vector<std::pair<double, double>>& polygon, const std::vector<double>& zs,
           bool with_top = true) {
    Mesh m;
    const uint32_t n = uint32_t(polygon.size());
    for (double z : zs)
        for (auto [x, y] : polygon) m.vertices.push_back({x, y, z});
    auto at = [&](size_t ring, uint32_t i) { return uint32_t(ring * n + i % n); };
    for (size_t k = 0; k + 1 < zs.size(); ++k)
        for (uint32_t i = 0; i < n; ++i) {
            const uint32_t a = at(k, i), b = at(k, i + 1), c = at(k + 1, i), d = at(k + 1, i + 1);
            m.triangles.push_back({a, b, d});
            m.triangles.push_back({a, d, c});
        }
    const size_t top = zs.size() - 1;
    for (uint32_t i = 1; i + 1 < n; ++i) {
        m.triangles.push_back({at(0, 0), at(0, i + 1), at(0, i)});
        if (with_top) m.triangles.push_back({at(top, 0), at(top, i), at(top, i + 1)});
    }
    return m;
}

Mesh box(double x0, double y0, double z0, double x1, double y1, double z1) {
    return prism({{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, {z0, z1});
}

void append(Mesh& to, const Mesh& from, bool flip = false) {
    const uint32_t base = uint32_t(to.vertices.size());
    to.vertices.insert(to.vertices.end(), from.vertices.begin(), from.vertices.end());
    for (auto t : from.triangles) {
        if (flip) std::swap(t[1], t[2]);
        to.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    }
}

Mesh octahedron(double r) {
    Mesh m;
    m.vertices = {{r, 0, 0}, {0, r, 0}, {-r, 0, 0}, {0, -r, 0}, {0, 0, r}, {0, 0, -r}};
    for (uint32_t i = 0; i < 4; ++i) {
        const uint32_t j = (i + 1) % 4;
        m.triangles.push_back({i, j, 4});
        m.triangles.push_back({j, i, 5});
    }
    return m;
}

double mesh_volume(const Mesh& m) {
    double v = 0;
    for (const auto& t : m.triangles) {
        const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
        v += a.x * (b.y * c.z - b.z * c.y) - a.y * (b.x * c.z - b.z * c.x) +
             a.z * (b.x * c.y - b.y * c.x);
    }
    return v / 6;
}

// The exact cross-section area (mm^2) of a closed polyhedron at a plane that avoids vertices:
// each crossing triangle contributes the shoelace term of its segment, oriented along
// up x normal. Independent of the slicer's chaining and union (shells add up, so this is the
// signed sum for overlapping shells).
double exact_section_area(const Mesh& m, double z) {
    double sum = 0;
    for (const auto& t : m.triangles) {
        const Vec3* v[3] = {&m.vertices[t[0]], &m.vertices[t[1]], &m.vertices[t[2]]};
        double px[2], py[2];
        int n = 0;
        for (int i = 0; i < 3; ++i) {
            const Vec3 &a = *v[i], &b = *v[(i + 1) % 3];
            if ((a.z < z) != (b.z < z)) {
                const double s = (z - a.z) / (b.z - a.z);
                px[n] = a.x + s * (b.x - a.x);
                py[n] = a.y + s * (b.y - a.y);
                ++n;
            }
        }
        if (n != 2) continue;
        const double ux = v[1]->x - v[0]->x, uy = v[1]->y - v[0]->y, uz = v[1]->z - v[0]->z;
        const double wx = v[2]->x - v[0]->x, wy = v[2]->y - v[0]->y, wz = v[2]->z - v[0]->z;
        const double nx = uy * wz - uz * wy, ny = uz * wx - ux * wz;
        // up x n = (-ny, nx)
        if ((px[1] - px[0]) * -ny + (py[1] - py[0]) * nx < 0) {
            std::swap(px[0], px[1]);
            std::swap(py[0], py[1]);
        }
        sum += 0.5 * (px[0] * py[1] - px[1] * py[0]);
    }
    return sum;
}

// A slow, simple reference: the same plane rule (a vertex on the plane counts as above), one
// segment per crossing triangle kept in an ordered map from its start edge, loops followed
// through the map. Only for closed manifold meshes. The raw loops, not united.
Paths reference_loops(const Mesh& m, double z) {
    using Edge = std::pair<uint32_t, uint32_t>;
    auto edge = [](uint32_t a, uint32_t b) { return a < b ? Edge{a, b} : Edge{b, a}; };
    std::map<Edge, std::pair<Edge, Point>> next;
    for (const auto& t : m.triangles) {
        bool above[3];
        for (int i = 0; i < 3; ++i) above[i] = m.vertices[t[i]].z >= z;
        int down = -1, up = -1;
        for (int i = 0; i < 3; ++i) {
            if (above[i] && !above[(i + 1) % 3]) down = i;
            if (!above[i] && above[(i + 1) % 3]) up = i;
        }
        if (down < 0) continue;
        const Vec3 &a = m.vertices[t[down]], &b = m.vertices[t[(down + 1) % 3]];
        const double s = (z - b.z) / (a.z - b.z);
        const Point p(to_units(b.x + s * (a.x - b.x)), to_units(b.y + s * (a.y - b.y)));
        next[edge(t[down], t[(down + 1) % 3])] = {edge(t[up], t[(up + 1) % 3]), p};
    }
    Paths loops;
    while (!next.empty()) {
        Path loop;
        Edge e = next.begin()->first;
        for (auto it = next.find(e); it != next.end(); it = next.find(e)) {
            loop.push_back(it->second.second);
            e = it->second.first;
            next.erase(it);
        }
        loops.push_back(std::move(loop));
    }
    return loops;
}

int count_holes(const Paths& region) {
    return int(
        std::count_if(region.begin(), region.end(), [](const Path& p) { return area(p) < 0; }));
}
int count_outers(const Paths& region) {
    return int(
        std::count_if(region.begin(), region.end(), [](const Path& p) { return area(p) > 0; }));
}

// A normalised region: every contour a real polygon, and re-uniting it changes nothing.
void expect_valid_region(const Paths& region) {
    for (const Path& p : region) {
        EXPECT_GE(p.size(), 3u);
        EXPECT_NE(area(p), 0.0);
    }
    EXPECT_NEAR(area(unite(region)), area(region), 1e-9 * std::abs(area(region)) + 1);
}

// ---- real models, through the project's loader ----

Mesh read_model(const std::string& path) {
    MeshReport report;
    return load_mesh(path, report);
}

std::string model(const std::string& name) {
    return carve::test::any_model(name);
}

}  // namespace

// ---- layer arithmetic and order ----

TEST(Slicer, CubeOf40mmAt02GivesExactly200LayersTopDown) {
    for (double z0 : {0.0, -20.0, 3.7}) {
        const Mesh cube = box(0, 0, z0, 40, 40, z0 + 40);
        TopDownSlicer slicer(cube, 0.2);
        ASSERT_EQ(slicer.layer_count(), 200);
        int expected = 199;
        while (auto s = slicer.next()) {
            EXPECT_EQ(s->index, expected);
            EXPECT_NEAR(s->z, z0 + (expected + 0.5) * 0.2, 1e-9);
            EXPECT_NEAR(area_mm2(s->region), 1600.0, 1e-6);
            ASSERT_EQ(s->region.size(), 1u);
            EXPECT_GT(area(s->region[0]), 0);  // outer counter-clockwise
            --expected;
        }
        EXPECT_EQ(expected, -1);
        EXPECT_FALSE(slicer.next().has_value());
    }
}

TEST(Slicer, LayerCountOnlyCountsPlanesInsideTheMesh) {
    EXPECT_EQ(TopDownSlicer(box(0, 0, 0, 1, 1, 0.25), 0.2).layer_count(), 1);  // 0.1
    EXPECT_EQ(TopDownSlicer(box(0, 0, 0, 1, 1, 0.35), 0.2).layer_count(), 2);  // 0.1, 0.3
    EXPECT_EQ(TopDownSlicer(box(0, 0, 0, 1, 1, 0.05), 0.2).layer_count(), 0);
    EXPECT_EQ(TopDownSlicer(Mesh{}, 0.2).layer_count(), 0);
    TopDownSlicer empty(Mesh{}, 0.2);
    EXPECT_FALSE(empty.next().has_value());
    EXPECT_THROW(TopDownSlicer(box(0, 0, 0, 1, 1, 1), 0.0), InputError);
    EXPECT_THROW(TopDownSlicer(box(0, 0, 0, 1, 1, 1), -0.2), InputError);
    EXPECT_THROW(TopDownSlicer(box(0, 0, 0, 1000, 1000, 1000), 1e-6), InputError);
}

// ---- areas against the analytic cross-sections ----

// A first layer of its own height (--first-layer-height): cut at its middle, the layers above
// at theirs, counted while the middle lies inside the mesh; 0 is the layer height.
TEST(Slicer, FirstLayerOfItsOwnHeightIsCutAtItsMiddle) {
    const Mesh b = box(0, 0, 1.5, 10, 10, 4.5);  // 3 mm
    TopDownSlicer slicer(b, 0.2, 0.3);
    // 0.15, then 0.4, 0.6 .. 2.8 (2.8 + 0.2 = 3.0 is the top): 1 + 13 layers.
    ASSERT_EQ(slicer.layer_count(), 14);
    int expected = 13;
    while (auto s = slicer.next()) {
        EXPECT_EQ(s->index, expected);
        EXPECT_NEAR(s->z, 1.5 + (expected == 0 ? 0.15 : 0.3 + (expected - 0.5) * 0.2), 1e-9);
        EXPECT_NEAR(area_mm2(s->region), 100.0, 1e-6);
        --expected;
    }
    EXPECT_EQ(expected, -1);
    EXPECT_EQ(TopDownSlicer(box(0, 0, 0, 1, 1, 0.2), 0.2, 0.3).layer_count(), 1);   // 0.15
    EXPECT_EQ(TopDownSlicer(box(0, 0, 0, 1, 1, 0.1), 0.2, 0.3).layer_count(), 0);   // above
    EXPECT_EQ(TopDownSlicer(box(0, 0, 0, 1, 1, 0.45), 0.2, 0.1).layer_count(), 3);  // .05 .2 .4
    EXPECT_EQ(TopDownSlicer(box(0, 0, 0, 1, 1, 40), 0.2, 0).layer_count(), 200);
    EXPECT_THROW(TopDownSlicer(box(0, 0, 0, 1, 1, 1), 0.2, -0.1), InputError);
}

TEST(Slicer, SphereAreaMatchesAnalyticAndPolyhedralSection) {
    const double r = 20;
    const Mesh sphere = uv_sphere(r, 512, 256);
    for (double z : {-17.3, -9.1, -0.05, 4.3, 12.7, 18.1}) {
        const Paths region = slice_at(sphere, z);
        const double a = area_mm2(region);
        EXPECT_NEAR(a, kPi * (r * r - z * z), 0.005 * kPi * (r * r - z * z)) << "z=" << z;
        // Simplification moves the contour by at most 12.5 um, inwards or outwards.
        EXPECT_NEAR(a, exact_section_area(sphere, z), length(region, true) * 12.5e-6) << z;
        ASSERT_EQ(region.size(), 1u);
        EXPECT_GT(area(region[0]), 0);
    }
}

// A scan's outline: 80,000 vertices 3 um apart, each moved up to 50 um off a 40 mm circle. Every
// later Clipper pass costs per vertex (it took minutes to carve), and no printer can follow it:
// the slice keeps the outline within a quarter of a line width with a few thousand vertices.
TEST(Slicer, NoisyOutlineIsSimplifiedToWhatAPrinterCanFollow) {
    const double R = 40, noise = 0.05;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> jitter(-noise, noise);
    std::vector<std::pair<double, double>> outline;
    const int n = 80000;
    for (int i = 0; i < n; ++i) {
        const double t = 2 * kPi * i / n, r = R + jitter(rng);
        outline.push_back({r * std::cos(t), r * std::sin(t)});
    }
    const Paths region = slice_at(prism(outline, {0, 1}), 0.5);
    ASSERT_EQ(region.size(), 1u);
    EXPECT_LT(region[0].size(), 6000u);
    for (const Point& q : region[0]) {
        const double r = std::hypot(double(q.X), double(q.Y)) / kUnitsPerMm;
        EXPECT_NEAR(r, R, noise + 0.1 + 0.002);
    }
    EXPECT_NEAR(area_mm2(region), kPi * R * R, 2 * kPi * R * 0.1);

    // A clean circle as finely sampled keeps every vertex within 12.5 um of it.
    outline.clear();
    for (int i = 0; i < n; ++i) {
        const double t = 2 * kPi * i / n;
        outline.push_back({R * std::cos(t), R * std::sin(t)});
    }
    const Paths clean = slice_at(prism(outline, {0, 1}), 0.5);
    ASSERT_EQ(clean.size(), 1u);
    EXPECT_LT(clean[0].size(), 1000u);
    for (const Point& q : clean[0])
        EXPECT_NEAR(std::hypot(double(q.X), double(q.Y)) / kUnitsPerMm, R, 0.0125 + 0.001);
}

TEST(Slicer, TorusAreaMatchesAnalyticAndHasAHole) {
    const double R = 30, r = 10;
    const Mesh t = torus(R, r, 512, 128);
    for (double z : {-9.3, -6.1, -0.07, 3.3, 8.9}) {
        const Paths region = slice_at(t, z);
        const double expected = 4 * kPi * R * std::sqrt(r * r - z * z);  // annulus
        EXPECT_NEAR(area_mm2(region), expected, 0.005 * expected) << "z=" << z;
        // Within the 12.5 um the slicer simplifies by.
        EXPECT_NEAR(area_mm2(region), exact_section_area(t, z), length(region, true) * 12.5e-6);
        EXPECT_EQ(count_outers(region), 1);
        EXPECT_EQ(count_holes(region), 1);
    }
    // Through the middle: outer circle R + r counter-clockwise, hole R - r clockwise.
    const Paths mid = slice_at(t, 0.0);
    ASSERT_EQ(mid.size(), 2u);
    const Path& outer = area(mid[0]) > 0 ? mid[0] : mid[1];
    const Path& hole = area(mid[0]) > 0 ? mid[1] : mid[0];
    EXPECT_NEAR(area(outer) * 1e-6, kPi * 40 * 40, 0.005 * kPi * 1600);
    EXPECT_NEAR(-area(hole) * 1e-6, kPi * 20 * 20, 0.005 * kPi * 400);
    EXPECT_TRUE(point_in_region({to_units(30), 0}, mid));
    EXPECT_FALSE(point_in_region({0, 0}, mid));
}

TEST(Slicer, BoxAreaIsExact) {
    const Mesh b = box(-3, 2, -1, 7.5, 12, 11);
    TopDownSlicer slicer(b, 0.3);
    EXPECT_EQ(slicer.layer_count(), 40);
    while (auto s = slicer.next()) EXPECT_NEAR(area_mm2(s->region), 10.5 * 10, 1e-9);
}

// ---- streaming agrees with single planes ----

TEST(Slicer, StreamingAgreesWithSliceAt) {
    Mesh m = uv_sphere(20, 96, 48);
    append(m, torus(30, 5, 96, 32));
    TopDownSlicer slicer(m, 0.25);
    int n = 0;
    while (auto s = slicer.next()) {
        // Same loops, but they may start elsewhere, so cleaning can keep other points: the two
        // contours stay within 2 um of each other.
        const Paths direct = slice_at(m, s->z);
        const double band = length(direct, true) * 2.0;
        EXPECT_NEAR(area(s->region), area(direct), band);
        EXPECT_LT(std::abs(area(symmetric_difference(s->region, direct))), band) << s->z;
        EXPECT_EQ(s->region.size(), direct.size());
        ++n;
    }
    EXPECT_EQ(n, slicer.layer_count());
    EXPECT_EQ(n, 160);
}

// ---- several shells ----

TEST(Slicer, OverlappingSpheresUniteIntoOneRegion) {
    const double r = 15, d = 8;
    Mesh m = uv_sphere(r, 256, 128, {-d, 0, 0});
    append(m, uv_sphere(r, 256, 128, {d, 0, 0}));
    const Paths region = slice_at(m, 0.03);
    ASSERT_EQ(region.size(), 1u);
    EXPECT_GT(area(region[0]), 0);
    const double rho2 = r * r - 0.03 * 0.03, rho = std::sqrt(rho2);
    const double lens = 2 * rho2 * std::acos(d / rho) - 2 * d * std::sqrt(rho2 - d * d);
    const double expected = 2 * kPi * rho2 - lens;
    EXPECT_LT(area_mm2(region), 2 * kPi * rho2 * 0.99);
    EXPECT_NEAR(area_mm2(region), expected, 0.005 * expected);
}

TEST(Slicer, InwardShellGivesAHole) {
    Mesh m = box(-20, -20, -20, 20, 20, 20);
    append(m, uv_sphere(12, 128, 64), /*flip=*/true);
    const Paths region = slice_at(m, 0.01);
    EXPECT_EQ(count_outers(region), 1);
    EXPECT_EQ(count_holes(region), 1);
    EXPECT_NEAR(area_mm2(region), 1600 - kPi * 144, 0.005 * (1600 - kPi * 144));
    // Above the void: a full square.
    EXPECT_NEAR(area_mm2(slice_at(m, 15)), 1600, 1e-6);
}

TEST(Slicer, DisjointShellsGiveSeparateOuters) {
    Mesh m = box(0, 0, 0, 10, 10, 10);
    append(m, box(20, 0, 0, 30, 10, 10));
    const Paths region = slice_at(m, 5);
    EXPECT_EQ(count_outers(region), 2);
    EXPECT_NEAR(area_mm2(region), 200, 1e-9);
}

// ---- vertices exactly on the plane ----

TEST(Slicer, BoxWithVertexRingsOnTheCuttingPlanes) {
    // Rings at every cut height of h = 0.5 from zmin = 0: planes 0.25, 0.75, ... hit them all.
    std::vector<double> zs{0};
    for (int i = 0; i < 20; ++i) zs.push_back(0.25 + 0.5 * i);
    zs.push_back(10);
    const Mesh b = prism({{0, 0}, {10, 0}, {10, 10}, {0, 10}}, zs);
    TopDownSlicer slicer(b, 0.5);
    EXPECT_EQ(slicer.layer_count(), 20);
    while (auto s = slicer.next()) {
        ASSERT_EQ(s->region.size(), 1u) << s->z;
        expect_valid_region(s->region);
        EXPECT_NEAR(area_mm2(s->region), 100, 1e-9);
    }
}

TEST(Slicer, PlaneSegmentsAreCountedBeforeAnyPlaneIsCut) {
    // Issue #38: the vertex limits read these counts before the first plane is chained. A ring
    // on a plane belongs to the band below it (a corner on the plane counts as above), so each
    // plane cuts the 8 side triangles of one band.
    std::vector<double> zs{0};
    for (int i = 0; i < 20; ++i) zs.push_back(0.25 + 0.5 * i);
    zs.push_back(10);
    const Mesh b = prism({{0, 0}, {10, 0}, {10, 10}, {0, 10}}, zs);
    const std::vector<uint32_t> rings = TopDownSlicer(b, 0.5).plane_segments();
    ASSERT_EQ(rings.size(), 20u);
    for (uint32_t n : rings) EXPECT_EQ(n, 8u);
    // On a sphere with a first layer of its own height: every triangle below a plane's z and
    // reaching it, as the slicer tests them.
    const Mesh sphere = uv_sphere(7, 48, 31);
    TopDownSlicer slicer(sphere, 0.3, 0.45);
    const std::vector<uint32_t> counts = slicer.plane_segments();
    ASSERT_EQ(counts.size(), size_t(slicer.layer_count()));
    for (int i = 0; i < slicer.layer_count(); ++i) {
        const double z = slicer.plane_z(i);
        uint32_t expected = 0;
        for (const auto& t : sphere.triangles) {
            const double a = sphere.vertices[t[0]].z, b2 = sphere.vertices[t[1]].z,
                         c = sphere.vertices[t[2]].z;
            expected += std::min({a, b2, c}) < z && std::max({a, b2, c}) >= z;
        }
        EXPECT_EQ(counts[size_t(i)], expected) << i;
        EXPECT_GT(expected, 0u) << i;
    }
    int i = slicer.layer_count() - 1;
    while (auto s = slicer.next()) EXPECT_EQ(s->z, slicer.plane_z(i--));
}

TEST(Slicer, SpikesNarrowerThanANozzlePrintsAreTakenOffTheSlice) {
    // Issue #38: a comb of 2,000 teeth 0.02 mm wide and 0.5 mm deep on a 40 x 10 mm bar. Each
    // tooth was a local minimum of every boolean on the layer (10,000 of them: no layer in
    // 120 s); what no nozzle prints goes: the comb becomes the bar, or the bar with its teeth
    // filled, whichever way round the loop meets them first.
    std::vector<std::pair<double, double>> comb{{40, 0}};
    for (int k = 0; k <= 4000; ++k) comb.push_back({40 - 0.01 * k, k % 2 ? 10.5 : 10});
    comb.push_back({0, 0});
    const Paths bar = slice_at(prism(comb, {0, 1}), 0.5);
    ASSERT_EQ(bar.size(), 1u);
    expect_valid_region(bar);
    EXPECT_LT(bar[0].size(), 16u);
    const double area = area_mm2(bar);
    EXPECT_TRUE(std::abs(area - 400) < 0.5 || std::abs(area - 420) < 0.5) << area;

    // Teeth a printer can draw stay: 0.2 mm wide (four times the spike width) and 0.5 mm deep.
    std::vector<std::pair<double, double>> coarse{{40, 0}};
    for (int k = 0; k <= 400; ++k) coarse.push_back({40 - 0.1 * k, k % 2 ? 10.5 : 10});
    coarse.push_back({0, 0});
    const Paths teeth = slice_at(prism(coarse, {0, 1}), 0.5);
    ASSERT_EQ(teeth.size(), 1u);
    EXPECT_GT(teeth[0].size(), 400u);
    EXPECT_NEAR(area_mm2(teeth), 400 + 40 * 0.5 / 2, 0.1);

    // So does a single needle 0.04 mm wide but only 0.02 mm long (no needle: a vertex left on a
    // curve), and a sharp corner of a triangle.
    const Paths nub = slice_at(
        prism({{0, 0}, {10, 0}, {10, 5}, {10.02, 5.02}, {10, 5.04}, {10, 10}, {0, 10}}, {0, 1}),
        0.5);
    ASSERT_EQ(nub.size(), 1u);
    EXPECT_EQ(nub[0].size(), 7u);
    const Paths sharp = slice_at(prism({{0, 0}, {30, 0}, {0, 0.5}}, {0, 1}), 0.5);
    ASSERT_EQ(sharp.size(), 1u);
    EXPECT_EQ(sharp[0].size(), 3u);
}

TEST(Slicer, PlaneThroughTopAndBottomFaces) {
    // A vertex on the plane counts as above: the top face's plane cuts just below it, the bottom
    // face's plane just below the mesh.
    const Mesh b = box(0, 0, 0, 10, 10, 10);
    const Paths top = slice_at(b, 10);
    ASSERT_EQ(top.size(), 1u);
    expect_valid_region(top);
    EXPECT_NEAR(area_mm2(top), 100, 1e-9);
    EXPECT_TRUE(slice_at(b, 0).empty());
    // Two stacked boxes sharing the plane z = 5 (top of one = bottom of the other).
    Mesh stack = box(0, 0, 0, 10, 10, 5);
    append(stack, box(2, 2, 5, 8, 8, 9));
    const Paths at5 = slice_at(stack, 5);
    expect_valid_region(at5);
    EXPECT_NEAR(area_mm2(at5), 100, 1e-9);
}

TEST(Slicer, OctahedronWithVerticesOnThePlane) {
    const Mesh o = octahedron(10);
    const Paths equator = slice_at(o, 0);  // four vertices on the plane
    ASSERT_EQ(equator.size(), 1u);
    expect_valid_region(equator);
    EXPECT_EQ(equator[0].size(), 4u);
    EXPECT_NEAR(area_mm2(equator), 200, 1e-9);
    EXPECT_TRUE(slice_at(o, 10).empty());   // apex: zero-length segments only
    EXPECT_TRUE(slice_at(o, -10).empty());  // bottom apex counts as above
    EXPECT_NEAR(area_mm2(slice_at(o, 5)), 50, 1e-6);
    // Streaming: zmin = -12.5 and h = 1 put plane 12 exactly through the equator's vertices.
    const Mesh big = octahedron(12.5);
    TopDownSlicer slicer(big, 1.0);  // planes -12 ... 12
    EXPECT_EQ(slicer.layer_count(), 25);
    while (auto s = slicer.next()) {
        if (s->index == 12) {
            EXPECT_EQ(s->z, 0.0);
        }
        const double half = 12.5 - std::abs(s->z);
        ASSERT_EQ(s->region.size(), 1u) << s->z;
        expect_valid_region(s->region);
        EXPECT_NEAR(area_mm2(s->region), 2 * half * half, 1e-6) << s->z;
    }
}

TEST(Slicer, BoxWhoseTopIsAtACutHeight) {
    // Layer 25 of h = 0.2 cuts exactly through the small box's top face and top vertices: they
    // count as above the plane, so the small box is still there on that layer.
    const double h = 0.2, top = 0 + (25 + 0.5) * h;
    Mesh m = box(0, 0, 0, 10, 10, 10);
    append(m, box(20, 0, 0, 30, 10, top));
    TopDownSlicer slicer(m, h);
    EXPECT_EQ(slicer.layer_count(), 50);
    while (auto s = slicer.next()) {
        expect_valid_region(s->region);
        EXPECT_NEAR(area_mm2(s->region), s->index <= 25 ? 200 : 100, 1e-9) << s->index;
        EXPECT_EQ(count_outers(s->region), s->index <= 25 ? 2 : 1);
    }
}

TEST(Slicer, NegativeZeroTopOnAPlaneAtZero) {
    // zmin = -10 and h = 4 put plane 2 at exactly +0.0; the first box's top is at -0.0, equal
    // to it, so it counts as above and the box is cut on that plane.
    Mesh m = box(0, 0, -10, 10, 10, -0.0);
    append(m, box(20, 0, -10, 30, 10, 10));
    TopDownSlicer slicer(m, 4.0);
    while (auto s = slicer.next()) {
        if (s->index != 2) continue;
        EXPECT_EQ(s->z, 0.0);
        EXPECT_NEAR(area_mm2(s->region), 200, 1e-9);
        EXPECT_EQ(count_outers(s->region), 2);
    }
    EXPECT_NEAR(area_mm2(slice_at(m, 0.0)), 200, 1e-9);
}

// ---- open and broken meshes ----

TEST(Slicer, BoxWithoutItsTopSlicesWithoutCrash) {
    const Mesh open = prism({{0, 0}, {10, 0}, {10, 10}, {0, 10}}, {0, 10}, /*with_top=*/false);
    TopDownSlicer slicer(open, 0.2);
    EXPECT_EQ(slicer.layer_count(), 50);
    while (auto s = slicer.next()) EXPECT_NEAR(area_mm2(s->region), 100, 1e-9);
    EXPECT_NEAR(area_mm2(slice_at(open, 10)), 100, 1e-9);
}

TEST(Slicer, BoxWithoutASideIsClosedAcrossTheGap) {
    Mesh b = box(0, 0, 0, 10, 10, 10);
    // Drop the two triangles of the side face x = 10 (both of their vertices have x = 10).
    std::erase_if(b.triangles, [&](const auto& t) {
        return b.vertices[t[0]].x == 10 && b.vertices[t[1]].x == 10 && b.vertices[t[2]].x == 10;
    });
    ASSERT_EQ(b.triangles.size(), 10u);
    const Paths region = slice_at(b, 3.3);
    ASSERT_EQ(region.size(), 1u);
    EXPECT_NEAR(area_mm2(region), 100, 1e-6);
}

TEST(Slicer, TornMeshesNeverCrash) {
    // A sphere with every 7th triangle missing, and a torus with a band removed: many open
    // chains per plane, matched greedily. Only sanity is asked of the result.
    Mesh s = uv_sphere(20, 64, 32);
    Mesh torn;
    torn.vertices = s.vertices;
    for (size_t i = 0; i < s.triangles.size(); ++i)
        if (i % 7 != 3) torn.triangles.push_back(s.triangles[i]);
    TopDownSlicer slicer(torn, 0.5);
    while (auto sl = slicer.next()) {
        expect_valid_region(sl->region);
        EXPECT_LE(area_mm2(sl->region), kPi * 400 * 1.01);
    }
    Mesh t = torus(30, 10, 64, 32);
    t.triangles.erase(t.triangles.begin() + 100, t.triangles.begin() + 400);
    TopDownSlicer slicer2(t, 0.5);
    while (auto sl = slicer2.next()) expect_valid_region(sl->region);
    // Lone triangles and a lone non-manifold fan.
    Mesh lone;
    lone.vertices = {{0, 0, 0}, {10, 0, 0}, {0, 10, 10}, {5, 5, -3}};
    lone.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 2, 1}, {1, 2, 3}};
    for (double z = -2.9; z < 10; z += 0.7) expect_valid_region(slice_at(lone, z));
}

// Closed polygons inside the mesh's footprint (a weaker check than expect_valid_region: on such
// degenerate input Clipper's union fills the right points but may leave touching or
// overlapping output contours, so the signed area need not be the filled area).
void expect_sane_region(const Paths& region, Coord extent) {
    for (const Path& p : region) {
        ASSERT_GE(p.size(), 3u);
        for (const Point& q : p) {
            EXPECT_LE(std::abs(q.X), extent);
            EXPECT_LE(std::abs(q.Y), extent);
        }
    }
}

TEST(Slicer, RandomTriangleSoupsNeverCrash) {
    // Non-manifold edges, duplicated and opposite triangles, vertices on the planes: whatever
    // comes in, closed polygons inside the footprint come out.
    carve::test::Rng rng(12345);
    const auto coord = [](carve::test::Rng& r) { return r.integer(-5, 5); };
    for (int soup = 0; soup < 300; ++soup) {
        Mesh m;
        const int nv = 4 + soup % 20;
        for (int i = 0; i < nv; ++i)
            m.vertices.push_back({double(coord(rng)), double(coord(rng)), 0.5 * coord(rng)});
        const auto pick = [nv](carve::test::Rng& r) { return uint32_t(r.integer(0, nv - 1)); };
        for (int t = 0; t < 3 * nv; ++t) {
            const uint32_t a = pick(rng), b = pick(rng), c = pick(rng);
            if (a != b && b != c && a != c) m.triangles.push_back({a, b, c});
        }
        TopDownSlicer slicer(m, 0.25);  // planes on the half-integer vertex heights too
        while (auto s = slicer.next()) expect_sane_region(s->region, 5000);
        for (double z = -2.5; z <= 2.5; z += 0.5) expect_sane_region(slice_at(m, z), 5000);
    }
}

TEST(Slicer, SliceAreasIntegrateToTheVolume) {
    const Mesh t = torus(30, 10, 256, 64);
    TopDownSlicer slicer(t, 0.1);
    double volume = 0;
    while (auto s = slicer.next()) volume += area_mm2(s->region) * 0.1;
    EXPECT_NEAR(volume, mesh_volume(t), 0.002 * mesh_volume(t));
}

// ---- the developer set of real models ----

namespace {

// Slices a model of the developer set and checks every layer; `name` for the overlap rule.
void expect_closed_layers(const std::string& path, const std::string& name) {
    SCOPED_TRACE(name);
    const Mesh m = read_model(path);
    // Overlapping shells count their overlap twice in signed measures.
    const bool overlapping = name == "two_spheres_overlapping.stl";
    TopDownSlicer slicer(m, 0.2);
    int layers = 0, empty = 0;
    double volume = 0;
    while (auto s = slicer.next()) {
        ++layers;
        if (s->region.empty() || area(s->region) <= 0) ++empty;
        for (const Path& p : s->region) ASSERT_GE(p.size(), 3u);
        EXPECT_GT(count_outers(s->region), 0) << "layer " << s->index;
        volume += area_mm2(s->region) * 0.2;
        if (s->index % 37 == 0) {
            // Same region as the slow reference's loops united, up to the 12.5 um
            // simplification; and no more than the signed cross-section, which counts
            // twice where the surface runs into itself (man.stl's hands, two_spheres).
            const double tol = length(s->region, true) * 12.5e-6;
            const double a = area_mm2(s->region);
            EXPECT_NEAR(a, area_mm2(unite(reference_loops(m, s->z))), tol) << "layer " << s->index;
            EXPECT_LE(a, exact_section_area(m, s->z) + tol) << "layer " << s->index;
        }
    }
    EXPECT_EQ(layers, slicer.layer_count());
    EXPECT_GT(layers, 0);
    EXPECT_EQ(empty, 0);
    if (!overlapping) {
        EXPECT_NEAR(volume, mesh_volume(m), 0.01 * mesh_volume(m));
    }
}

}  // namespace

TEST(SlicerModels, EveryRepositoryModelSlicesIntoClosedRegionsOnEveryLayer) {
    for (const char* name : {"fandisk.stl", "elephant.stl", "man.stl"})
        expect_closed_layers(carve::test::repo_model(name), name);
}

// The whole shared folder (the real models and the synthetic shapes), whatever it holds.
TEST(SlicerModels, EverySharedModelSlicesIntoClosedRegionsOnEveryLayer) {
    CARVE_NEED_MODEL("synthetic/two_spheres_overlapping.stl");
    namespace fs = std::filesystem;
    int models = 0;
    for (const char* folder : {"", "synthetic"}) {
        for (const auto& entry :
             fs::directory_iterator(carve::test::shared_models_dir() / folder)) {
            if (entry.path().extension() != ".stl") continue;
            expect_closed_layers(entry.path().string(), entry.path().filename().string());
            ++models;
        }
    }
    EXPECT_EQ(models, 12);
}

TEST(SlicerModels, SyntheticShapes) {
    CARVE_NEED_MODEL("synthetic/box_with_internal_void.stl");
    CARVE_NEED_MODEL("synthetic/two_spheres_overlapping.stl");
    CARVE_NEED_MODEL("synthetic/fig3_cube_indent.stl");
    const Mesh voided = read_model(model("synthetic/box_with_internal_void.stl"));
    const Paths mid = slice_at(voided, 0.0);
    EXPECT_EQ(count_outers(mid), 1);
    EXPECT_EQ(count_holes(mid), 1);
    EXPECT_NEAR(area_mm2(mid), 1600 - kPi * 144, 0.01 * (1600 - kPi * 144));

    // Overlapping shells: the union is smaller than the sum the signed areas give.
    const Mesh two = read_model(model("synthetic/two_spheres_overlapping.stl"));
    const Paths both = slice_at(two, 0.01);
    ASSERT_EQ(both.size(), 1u);
    EXPECT_LT(area_mm2(both), 0.95 * exact_section_area(two, 0.01));

    // The paper's figure 3 cube: the step at z = 9 lies between the planes 8.9 and 9.1 of
    // h = 0.2; a plane exactly on the step cuts just below it.
    const Mesh fig3 = read_model(model("synthetic/fig3_cube_indent.stl"));
    EXPECT_NEAR(area_mm2(slice_at(fig3, 8.9)), 144, 1e-6);
    EXPECT_NEAR(area_mm2(slice_at(fig3, 9.0)), 144, 1e-6);  // plane on the step: below it
    EXPECT_NEAR(area_mm2(slice_at(fig3, 9.1)), 108, 1e-6);
    TopDownSlicer slicer(fig3, 0.2);
    EXPECT_EQ(slicer.layer_count(), 60);
}

// Mesh loading: every broken input in models/bad, the real and synthetic models with their
// published volumes, OBJ and 3MF files written here, and the repair of orientation and voids.
#include "mesh/mesh.hpp"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zip.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <random>
#include <set>
#include <string>
#include <thread>

#include "base/error.hpp"
#include "mesh/loader.hpp"
#include "report/mesh_info.hpp"
#include "support/models.hpp"
#include "support/scratch.hpp"

using namespace carve;
namespace fs = std::filesystem;

namespace {

const std::string kModels = carve::test::shared_models_dir().string();

std::string bad(const std::string& name) {
    return kModels + "/bad/" + name;
}

// A fresh directory for the files the tests write, removed at the end of the program.
class TempDir {
  public:
    std::string file(const std::string& name) const { return (dir_.path() / name).string(); }
    std::string dir() const { return dir_.path().string(); }

  private:
    test::ScratchDir dir_{"carve_mesh_test_"};
};

const TempDir& temp() {
    static TempDir t;
    return t;
}

void write_file(const std::string& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// A binary STL with this header byte for byte (carve::binary_stl never starts one with "solid").
std::string raw_stl(const Mesh& m, const std::string& header) {
    std::string out(80, ' ');
    std::memcpy(out.data(), header.data(), std::min<size_t>(header.size(), 80));
    uint32_t n = static_cast<uint32_t>(m.triangles.size());
    out.append(reinterpret_cast<const char*>(&n), 4);
    for (const auto& t : m.triangles) {
        float rec[12] = {0, 0, 0};
        for (int k = 0; k < 3; ++k) {
            const Vec3& v = m.vertices[t[k]];
            rec[3 + 3 * k] = float(v.x), rec[4 + 3 * k] = float(v.y), rec[5 + 3 * k] = float(v.z);
        }
        out.append(reinterpret_cast<const char*>(rec), sizeof rec);
        out.append(2, '\0');
    }
    return out;
}

// "word x y z" with every digit a double needs, so that the text reads back to the same point.
std::string fmt_point(const char* word, const Vec3& p) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "%s %.17g %.17g %.17g", word, p.x, p.y, p.z);
    return buf;
}

// The 20 mm cube [0,20]^3 as 8 corners and 6 counter-clockwise quads (seen from outside).
const double kCorner[8][3] = {{0, 0, 0},  {20, 0, 0},  {20, 20, 0},  {0, 20, 0},
                              {0, 0, 20}, {20, 0, 20}, {20, 20, 20}, {0, 20, 20}};
const int kQuads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                          {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};

Mesh cube_mesh(double size = 20, Vec3 at = {}) {
    Mesh m;
    for (const auto& c : kCorner)
        m.vertices.push_back(
            {at.x + c[0] * size / 20, at.y + c[1] * size / 20, at.z + c[2] * size / 20});
    for (const auto& q : kQuads) {
        m.triangles.push_back({uint32_t(q[0]), uint32_t(q[1]), uint32_t(q[2])});
        m.triangles.push_back({uint32_t(q[0]), uint32_t(q[2]), uint32_t(q[3])});
    }
    return m;
}

bool has_warning(const MeshReport& r, const std::string& words) {
    for (const auto& w : r.warnings)
        if (w.find(words) != std::string::npos) return true;
    return false;
}

std::string all_warnings(const MeshReport& r) {
    std::string s;
    for (const auto& w : r.warnings) s += w + " | ";
    return s;
}

// Expects load_mesh to throw InputError whose single line contains every word given.
void expect_input_error(const std::string& path, std::initializer_list<std::string> words) {
    MeshReport r;
    try {
        load_mesh(path, r);
        ADD_FAILURE() << path << " loaded without error";
    } catch (const InputError& e) {
        const std::string msg = e.what();
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
        EXPECT_NE(msg.find(fs::path(path).filename().string()), std::string::npos)
            << "message does not name the file: " << msg;
        for (const auto& w : words) EXPECT_NE(msg.find(w), std::string::npos) << msg;
    }
}

MeshReport load_ok(const std::string& path, Mesh* out = nullptr) {
    MeshReport r;
    Mesh m = load_mesh(path, r);
    EXPECT_EQ(m.triangles.size(), r.triangles);
    EXPECT_EQ(m.vertices.size(), r.vertices);
    if (out) *out = std::move(m);
    return r;
}

}  // namespace

// ---- models/bad ----

TEST(MeshBad, EmptyFileIsAnInputError) {
    CARVE_NEED_MODEL("bad/empty.stl");
    expect_input_error(bad("empty.stl"), {"empty"});
}

TEST(MeshBad, TruncatedBinaryIsAnInputError) {
    CARVE_NEED_MODEL("bad/truncated.stl");
    expect_input_error(bad("truncated.stl"), {"truncated", "12 triangles", "459 bytes"});
}

TEST(MeshBad, NanCoordinatesAreAnInputError) {
    CARVE_NEED_MODEL("bad/nan_coords.stl");
    expect_input_error(bad("nan_coords.stl"), {"NaN", "triangle 3"});
}

TEST(MeshBad, AsciiCubeLoads) {
    CARVE_NEED_MODEL("bad/ascii_cube.stl");
    MeshReport r = load_ok(bad("ascii_cube.stl"));
    EXPECT_EQ(r.format, "ASCII STL");
    EXPECT_EQ(r.triangles, 12u);
    EXPECT_EQ(r.vertices, 8u);
    EXPECT_TRUE(r.closed());
    EXPECT_NEAR(r.volume_mm3, 8000.0, 1e-6);
    EXPECT_TRUE(r.warnings.empty()) << all_warnings(r);
}

TEST(MeshBad, FlippedAllInwardIsTurnedOut) {
    CARVE_NEED_MODEL("bad/flipped_all_inward.stl");
    MeshReport r = load_ok(bad("flipped_all_inward.stl"));
    EXPECT_NEAR(r.volume_mm3, 8000.0, 1e-6);
    EXPECT_TRUE(r.inverted);
    EXPECT_EQ(r.flipped_triangles, 0u);
    EXPECT_TRUE(has_warning(r, "inside out")) << all_warnings(r);
}

TEST(MeshBad, FlippedSomeAreFixed) {
    CARVE_NEED_MODEL("bad/flipped_some.stl");
    MeshReport r = load_ok(bad("flipped_some.stl"));
    EXPECT_NEAR(r.volume_mm3, 8000.0, 1e-6);
    EXPECT_EQ(r.flipped_triangles, 3u);
    EXPECT_FALSE(r.inverted);
    EXPECT_TRUE(r.closed());
    EXPECT_TRUE(has_warning(r, "flipped 3 facets")) << all_warnings(r);
}

TEST(MeshBad, WrongNormalsOnlyNeedNoFlip) {
    CARVE_NEED_MODEL("bad/wrong_normals_only.stl");
    MeshReport r = load_ok(bad("wrong_normals_only.stl"));
    EXPECT_NEAR(r.volume_mm3, 8000.0, 1e-6);
    EXPECT_EQ(r.flipped_triangles, 0u);
    EXPECT_FALSE(r.inverted);
    EXPECT_TRUE(r.warnings.empty()) << all_warnings(r);
}

TEST(MeshBad, DegenerateSliverIsDroppedAndTheCubeStaysClosed) {
    CARVE_NEED_MODEL("bad/degenerate_sliver.stl");
    MeshReport r = load_ok(bad("degenerate_sliver.stl"));
    EXPECT_EQ(r.triangles_read, 14u);
    EXPECT_EQ(r.degenerate_dropped, 1u);
    EXPECT_EQ(r.zero_area_splits, 1u);
    EXPECT_EQ(r.triangles, 14u);  // 13 minus the sliver plus the split neighbour
    EXPECT_TRUE(r.closed()) << r.open_edges << " open, " << r.nonmanifold_edges << " non-manifold";
    EXPECT_NEAR(r.volume_mm3, 8000.0, 1e-6);
    EXPECT_TRUE(has_warning(r, "dropped 1 degenerate triangle")) << all_warnings(r);
}

TEST(MeshBad, DegenerateCollapsedIsDropped) {
    CARVE_NEED_MODEL("bad/degenerate_collapsed.stl");
    MeshReport r = load_ok(bad("degenerate_collapsed.stl"));
    EXPECT_EQ(r.triangles_read, 13u);
    EXPECT_EQ(r.degenerate_dropped, 1u);
    EXPECT_EQ(r.triangles, 12u);
    EXPECT_TRUE(r.closed());
    EXPECT_NEAR(r.volume_mm3, 8000.0, 1e-6);
    EXPECT_TRUE(has_warning(r, "dropped 1 degenerate triangle")) << all_warnings(r);
}

TEST(MeshBad, OpenCubeReportsFourOpenEdges) {
    CARVE_NEED_MODEL("bad/open_cube_missing_top.stl");
    MeshReport r = load_ok(bad("open_cube_missing_top.stl"));
    EXPECT_EQ(r.triangles, 10u);
    EXPECT_EQ(r.open_edges, 4u);
    EXPECT_EQ(r.nonmanifold_edges, 0u);
    EXPECT_FALSE(r.closed());
    EXPECT_EQ(r.flipped_triangles, 0u);
    EXPECT_FALSE(r.inverted);
    EXPECT_TRUE(has_warning(r, "mesh is not closed: 4 open edges")) << all_warnings(r);
}

TEST(MeshBad, CubesSharingAnEdgeHaveOneNonManifoldEdge) {
    CARVE_NEED_MODEL("bad/nonmanifold_two_cubes_shared_edge.stl");
    MeshReport r = load_ok(bad("nonmanifold_two_cubes_shared_edge.stl"));
    EXPECT_EQ(r.triangles, 24u);
    EXPECT_EQ(r.nonmanifold_edges, 1u);
    EXPECT_EQ(r.open_edges, 0u);
    EXPECT_EQ(r.shells, 2u);
    EXPECT_NEAR(r.volume_mm3, 2000.0, 1e-6);
    EXPECT_TRUE(has_warning(r, "1 non-manifold edge")) << all_warnings(r);
}

TEST(MeshBad, CubesSharingAVertexLoad) {
    CARVE_NEED_MODEL("bad/nonmanifold_two_cubes_shared_vertex.stl");
    MeshReport r = load_ok(bad("nonmanifold_two_cubes_shared_vertex.stl"));
    EXPECT_EQ(r.triangles, 24u);
    EXPECT_EQ(r.vertices, 15u);
    EXPECT_TRUE(r.closed());
    EXPECT_EQ(r.shells, 2u);
    EXPECT_EQ(r.internal_voids, 0u);
    EXPECT_NEAR(r.volume_mm3, 2000.0, 1e-6);
    EXPECT_TRUE(r.warnings.empty()) << all_warnings(r);
}

TEST(MeshBad, EveryFileInTheFolderIsCovered) {
    CARVE_NEED_MODEL("bad/empty.stl");
    CARVE_NEED_MODEL("bad/truncated.stl");
    CARVE_NEED_MODEL("bad/nan_coords.stl");
    CARVE_NEED_MODEL("bad/ascii_cube.stl");
    CARVE_NEED_MODEL("bad/flipped_all_inward.stl");
    CARVE_NEED_MODEL("bad/flipped_some.stl");
    CARVE_NEED_MODEL("bad/wrong_normals_only.stl");
    CARVE_NEED_MODEL("bad/degenerate_sliver.stl");
    CARVE_NEED_MODEL("bad/degenerate_collapsed.stl");
    CARVE_NEED_MODEL("bad/open_cube_missing_top.stl");
    CARVE_NEED_MODEL("bad/nonmanifold_two_cubes_shared_edge.stl");
    CARVE_NEED_MODEL("bad/nonmanifold_two_cubes_shared_vertex.stl");
    // A new file in bad/ needs a test here.
    const std::set<std::string> known = {"empty.stl",
                                         "truncated.stl",
                                         "nan_coords.stl",
                                         "ascii_cube.stl",
                                         "flipped_all_inward.stl",
                                         "flipped_some.stl",
                                         "wrong_normals_only.stl",
                                         "degenerate_sliver.stl",
                                         "degenerate_collapsed.stl",
                                         "open_cube_missing_top.stl",
                                         "nonmanifold_two_cubes_shared_edge.stl",
                                         "nonmanifold_two_cubes_shared_vertex.stl",
                                         "MODELS.md"};
    for (const auto& entry : fs::directory_iterator(kModels + "/bad"))
        EXPECT_TRUE(known.count(entry.path().filename().string())) << entry.path();
}

// ---- real models (MODELS.md) ----

struct RealModel {
    const char* file;
    size_t triangles;
    double volume_cm3;
    double size_mm[3];
};

class RealModels : public ::testing::TestWithParam<RealModel> {};

TEST_P(RealModels, LoadClosedWithThePublishedVolume) {
    const RealModel& m = GetParam();
    CARVE_MODEL(path, m.file);
    MeshReport r = load_ok(path);
    EXPECT_EQ(r.format, "binary STL");
    EXPECT_EQ(r.triangles, m.triangles);
    EXPECT_TRUE(r.closed());
    EXPECT_EQ(r.shells, 1u);
    EXPECT_TRUE(r.warnings.empty()) << all_warnings(r);
    EXPECT_NEAR(r.volume_mm3 / 1000.0, m.volume_cm3, m.volume_cm3 * 1e-3);
    const double size[3] = {r.bbox.max.x - r.bbox.min.x, r.bbox.max.y - r.bbox.min.y,
                            r.bbox.max.z - r.bbox.min.z};
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(size[k], m.size_mm[k], 0.006) << "axis " << k;
    EXPECT_NEAR(r.bbox.min.z, 0.0, 1e-4);
}

INSTANTIATE_TEST_SUITE_P(
    Models, RealModels,
    ::testing::Values(RealModel{"skull.stl", 100002, 362.3, {74.99, 104.54, 120.00}},
                      RealModel{"skull_x4_400k.stl", 400008, 362.3, {74.99, 104.54, 120.00}},
                      RealModel{"elephant.stl", 88928, 155.3, {107.93, 90.24, 150.00}},
                      RealModel{"fandisk.stl", 12946, 71.9, {73.65, 40.89, 80.00}},
                      RealModel{"man.stl", 34986, 42.3, {63.28, 44.45, 150.00}},
                      RealModel{"cat.stl", 15894, 82.3, {107.16, 40.00, 120.00}}),
    [](const auto& info) { return fs::path(info.param.file).stem().string(); });

// ---- synthetic models ----

TEST(MeshSynthetic, BoxWithInternalVoidKeepsTheVoid) {
    CARVE_NEED_MODEL("synthetic/box_with_internal_void.stl");
    MeshReport r = load_ok(kModels + "/synthetic/box_with_internal_void.stl");
    EXPECT_EQ(r.triangles, 4104u);
    EXPECT_EQ(r.shells, 2u);
    EXPECT_EQ(r.internal_voids, 1u);
    EXPECT_TRUE(r.closed());
    EXPECT_FALSE(r.inverted);
    EXPECT_TRUE(r.warnings.empty()) << all_warnings(r);
    EXPECT_NEAR(r.volume_mm3 / 1000.0, 56.79, 56.79 * 1e-3);
}

TEST(MeshSynthetic, OtherShapesHaveTheirPublishedVolumes) {
    CARVE_NEED_MODEL("synthetic/fig3_cube_indent.stl");
    CARVE_NEED_MODEL("synthetic/sphere_40mm.stl");
    CARVE_NEED_MODEL("synthetic/torus.stl");
    CARVE_NEED_MODEL("synthetic/tall_box_30x30x80.stl");
    CARVE_NEED_MODEL("synthetic/two_spheres_overlapping.stl");
    struct Case {
        const char* file;
        double cm3;
        size_t shells;
    } cases[] = {{"fig3_cube_indent.stl", 1.620, 1},
                 {"sphere_40mm.stl", 33.45, 1},
                 {"torus.stl", 59.03, 1},
                 {"tall_box_30x30x80.stl", 72.0, 1},
                 {"two_spheres_overlapping.stl", 28.16, 2}};
    for (const Case& c : cases) {
        MeshReport r = load_ok(kModels + "/synthetic/" + c.file);
        EXPECT_NEAR(r.volume_mm3 / 1000.0, c.cm3, c.cm3 * 1e-3) << c.file;
        EXPECT_EQ(r.shells, c.shells) << c.file;
        EXPECT_EQ(r.internal_voids, 0u) << c.file;  // overlapping spheres are not a void
        EXPECT_TRUE(r.closed()) << c.file;
        EXPECT_TRUE(r.warnings.empty()) << c.file << ": " << all_warnings(r);
    }
}

// ---- orientation repair on meshes built here ----

TEST(MeshRepair, VoidFacingOutwardsIsTurnedToFaceIntoTheVoid) {
    CARVE_NEED_MODEL("synthetic/box_with_internal_void.stl");
    MeshReport first;
    Mesh m = load_mesh(kModels + "/synthetic/box_with_internal_void.stl", first);
    // Turn every triangle of the inner (void) shell outwards: those within the sphere's radius.
    for (auto& t : m.triangles) {
        const Vec3& p = m.vertices[t[0]];
        if (std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z) < 13.0) std::swap(t[1], t[2]);
    }
    MeshReport r;
    analyse_and_repair(m, r);
    EXPECT_EQ(r.inverted_shells, 1u);
    EXPECT_EQ(r.internal_voids, 1u);
    EXPECT_NEAR(r.volume_mm3, first.volume_mm3, 1e-6 * first.volume_mm3);
    EXPECT_TRUE(has_warning(r, "1 shell of 2")) << all_warnings(r);
}

TEST(MeshRepair, WholeVoidBoxInsideOutIsTurnedAround) {
    CARVE_NEED_MODEL("synthetic/box_with_internal_void.stl");
    MeshReport first;
    Mesh m = load_mesh(kModels + "/synthetic/box_with_internal_void.stl", first);
    for (auto& t : m.triangles) std::swap(t[1], t[2]);
    MeshReport r;
    analyse_and_repair(m, r);
    EXPECT_EQ(r.inverted_shells, 2u);
    EXPECT_NEAR(r.volume_mm3, first.volume_mm3, 1e-6 * first.volume_mm3);
}

TEST(MeshRepair, BallInsideAVoidIsSolidAgain) {
    // Outer cube 60, void cube 40 inside it, solid cube 20 inside the void: depths 0, 1, 2.
    Mesh m;
    auto add = [&](const Mesh& part, bool inward) {
        const uint32_t base = static_cast<uint32_t>(m.vertices.size());
        m.vertices.insert(m.vertices.end(), part.vertices.begin(), part.vertices.end());
        for (auto t : part.triangles) {
            if (inward) std::swap(t[1], t[2]);
            m.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
        }
    };
    add(cube_mesh(60, {0, 0, 0}), true);  // all three start inside out
    add(cube_mesh(40, {10, 10, 10}), false);
    add(cube_mesh(20, {20, 20, 20}), true);
    MeshReport r;
    analyse_and_repair(m, r);
    EXPECT_EQ(r.shells, 3u);
    EXPECT_EQ(r.internal_voids, 1u);
    EXPECT_EQ(r.inverted_shells, 3u);
    EXPECT_NEAR(r.volume_mm3, 216000.0 - 64000.0 + 8000.0, 1e-6);
}

// A shell standing partly inside another (a blade set 2 mm deep into a plate, all of it but its
// top inside) is a second solid, not a void: nothing is turned, the volume is the two added.
TEST(MeshRepair, ShellPokingOutOfAnotherIsNoVoid) {
    Mesh m;
    auto add = [&](const Mesh& part) {
        const uint32_t base = static_cast<uint32_t>(m.vertices.size());
        m.vertices.insert(m.vertices.end(), part.vertices.begin(), part.vertices.end());
        for (auto t : part.triangles)
            m.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    };
    add(cube_mesh(20, {0, 0, 0}));
    add(cube_mesh(10, {5, 5, 18}));
    add(cube_mesh(4, {8, 8, 8}));  // and one wholly inside: a void once turned around
    for (auto& t : m.triangles)
        if (m.vertices[t[0]].z >= 8 && m.vertices[t[0]].z <= 12 && m.vertices[t[0]].x >= 8 &&
            m.vertices[t[0]].x <= 12 && m.vertices[t[1]].x >= 8 && m.vertices[t[1]].x <= 12)
            std::swap(t[1], t[2]);  // the inner cube's triangles face inwards, as a void's do
    MeshReport r;
    analyse_and_repair(m, r);
    EXPECT_EQ(r.shells, 3u);
    EXPECT_EQ(r.internal_voids, 1u) << all_warnings(r);
    EXPECT_EQ(r.inverted_shells, 0u) << all_warnings(r);
    EXPECT_EQ(r.flipped_triangles, 0u) << all_warnings(r);
    EXPECT_NEAR(r.volume_mm3, 8000.0 + 1000.0 - 64.0, 1e-6);
}

TEST(MeshRepair, DuplicateTrianglesAreDropped) {
    Mesh m = cube_mesh();
    m.triangles.push_back(m.triangles[3]);
    m.triangles.push_back({m.triangles[5][0], m.triangles[5][2], m.triangles[5][1]});
    MeshReport r;
    analyse_and_repair(m, r);
    // The repeated triangle goes; the pair facing opposite ways (5 and its reverse) both go,
    // leaving an open cube.
    EXPECT_EQ(r.duplicate_dropped, 3u);
    EXPECT_EQ(r.triangles, 11u);
    EXPECT_EQ(r.open_edges, 3u);
    EXPECT_TRUE(has_warning(r, "dropped 3 duplicate triangles")) << all_warnings(r);
}

// n disjoint triangles: every edge open.
Mesh soup_mesh(uint32_t n) {
    Mesh m;
    for (uint32_t t = 0; t < n; ++t) {
        const double x = 3.0 * t;
        m.vertices.push_back({x, 0, 0});
        m.vertices.push_back({x + 1, 0, 0});
        m.vertices.push_back({x, 1, t % 7 * 0.5});
        m.triangles.push_back({3 * t, 3 * t + 1, 3 * t + 2});
    }
    return m;
}

TEST(MeshRepair, TheEdgeCountsAreReportedOnceBeforeTheShellsAreWalked) {
    Mesh m = soup_mesh(2000);
    // Ten of them twice more, once facing the other way: 20 duplicates cancel out.
    for (uint32_t t = 0; t < 10; ++t) {
        const auto tri = m.triangles[t];
        m.triangles.push_back({tri[0], tri[2], tri[1]});
    }
    MeshReport r;
    int calls = 0;
    size_t seen_open = 0;
    analyse_and_repair(m, r, [&](const MeshReport& counted) {
        ++calls;
        seen_open = counted.open_edges;
        EXPECT_EQ(counted.shells, 0u);  // not walked yet
        EXPECT_EQ(counted.duplicate_dropped, 20u);
    });
    EXPECT_EQ(calls, 1);
    EXPECT_EQ(seen_open, 3u * 1990);
    EXPECT_EQ(r.open_edges, 3u * 1990);
    EXPECT_EQ(r.shells, 1990u);
    EXPECT_TRUE(is_triangle_soup(r));

    // A throw from the callback ends the repair there.
    Mesh again = soup_mesh(2000);
    MeshReport r2;
    EXPECT_THROW(analyse_and_repair(again, r2, [](const MeshReport&) { throw InputError("stop"); }),
                 InputError);
    EXPECT_EQ(r2.shells, 0u);
}

TEST(MeshRepair, ASoupIsRefusedOnlyWhenAsked) {
    const std::string path = temp().file("soup.stl");
    write_file(path, raw_stl(soup_mesh(2000), "soup"));
    MeshReport r = load_ok(path);
    EXPECT_EQ(r.open_edges, 6000u);
    EXPECT_EQ(r.shells, 2000u);
    EXPECT_TRUE(is_triangle_soup(r));
    LoadOptions refuse;
    refuse.refuse_soup = true;
    try {
        load_mesh(path, r, refuse);
        ADD_FAILURE() << "the soup loaded";
    } catch (const InputError& e) {
        EXPECT_EQ(std::string(e.what()),
                  path +
                      ": not a solid: its 2000 triangles have 6000 distinct corners or more, "
                      "over 2.25 a triangle, so more than half of their edges are shared with "
                      "no other triangle (a triangle soup); repair the mesh first");
    }
    // A closed model passes, and so does a small soup (up to 1000 triangles).
    const std::string cube = temp().file("cube_refuse.stl");
    write_file(cube, raw_stl(cube_mesh(), "cube"));
    EXPECT_NO_THROW(load_mesh(cube, r, refuse));
    EXPECT_FALSE(is_triangle_soup(r));
    write_file(path, raw_stl(soup_mesh(1000), "small soup"));
    EXPECT_NO_THROW(load_mesh(path, r, refuse));
}

// A large binary STL soup is proved one before it is welded: more than 2.25 distinct corners a
// triangle imply more than half of the edges open (see binary_stl_soup_corners). The proof is
// exact or nothing: a mesh the bound cannot prove is left to the edge count.
TEST(MeshRepair, ASoupIsProvedFromItsCornersBeforeItIsWelded) {
    auto proof = [](const Mesh& m, const std::string& name) {
        const std::string path = temp().file(name);
        write_file(path, raw_stl(m, name));
        std::FILE* f = std::fopen(path.c_str(), "rb");
        auto p = detail::binary_stl_soup_corners(f, path, 0);
        std::fclose(f);
        return p;
    };
    const auto soup = proof(soup_mesh(30000), "proof_soup.stl");
    ASSERT_TRUE(soup.has_value());
    EXPECT_EQ(soup->triangles, 30000u);
    EXPECT_GT(double(soup->corners), 2.25 * 30000);
    EXPECT_LE(soup->corners, 90000u);

    auto append = [](Mesh& to, const Mesh& m) {
        const auto first = static_cast<uint32_t>(to.vertices.size());
        to.vertices.insert(to.vertices.end(), m.vertices.begin(), m.vertices.end());
        for (auto t : m.triangles)
            to.triangles.push_back({t[0] + first, t[1] + first, t[2] + first});
    };
    Mesh boxes;
    for (int i = 0; i < 1000; ++i) append(boxes, cube_mesh(1, {2.0 * i, 50, 0}));
    EXPECT_FALSE(proof(boxes, "proof_boxes.stl").has_value());
    // 20,000 soup triangles and 1000 boxes: 68,000 corners for 32,000 triangles, more than 2 a
    // triangle (the passes run) but not 2.25 (no proof). Still a soup by its edges.
    Mesh mixed = soup_mesh(20000);
    append(mixed, boxes);
    EXPECT_FALSE(proof(mixed, "proof_mixed.stl").has_value());
    LoadOptions refuse;
    refuse.refuse_soup = true;
    MeshReport r;
    const std::string path = temp().file("proof_mixed.stl");
    EXPECT_THROW(load_mesh(path, r, refuse), InputError);
}

// Every corner of every triangle written out, as an ASCII STL or as an OBJ with three vertex
// lines a face (both exporters' habit), with the given line end.
std::string ascii_stl(const Mesh& m, const std::string& eol = "\n") {
    std::string out = "solid written here" + eol;
    for (const auto& t : m.triangles) {
        out += " facet normal 0 0 0" + eol + "  outer loop" + eol;
        for (uint32_t v : t) {
            const Vec3& p = m.vertices[v];
            out += fmt_point("   vertex", p) + eol;
        }
        out += "  endloop" + eol + " endfacet" + eol;
    }
    return out + "endsolid written here" + eol;
}

std::string obj_per_face(const Mesh& m, size_t unused_lines = 0) {
    std::string out;
    for (size_t i = 0; i < unused_lines; ++i)
        out += fmt_point("v", {1000.0 + double(i), -5, 0.25 * double(i % 9)}) + "\n";
    size_t line = unused_lines;
    for (const auto& t : m.triangles) {
        for (uint32_t v : t) out += fmt_point("v", m.vertices[v]) + "\n";
        out += "f " + std::to_string(line + 1) + " " + std::to_string(line + 2) + " -1\n";
        line += 3;
    }
    return out;
}

// Reads path with the streaming reader of its kind, after the first pass when counted.
Mesh read_streamed(const std::string& path, bool counted, bool obj) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    const auto size = static_cast<size_t>(fs::file_size(path));
    Mesh m;
    MeshReport r;
    std::optional<detail::TextCounts> counts;
    try {
        if (counted) {
            counts =
                obj ? detail::count_obj(f, size, path) : detail::count_ascii_stl(f, size, path);
            std::rewind(f);
        }
        if (obj)
            detail::read_obj(f, size, path, m, r, counts ? &*counts : nullptr);
        else
            detail::read_ascii_stl(f, size, path, m, r, counts ? &*counts : nullptr);
    } catch (...) {
        std::fclose(f);
        throw;
    }
    std::fclose(f);
    return m;
}

detail::TextCounts first_pass(const std::string& path, bool obj) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    const auto size = static_cast<size_t>(fs::file_size(path));
    const auto counts =
        obj ? detail::count_obj(f, size, path) : detail::count_ascii_stl(f, size, path);
    std::fclose(f);
    return counts;
}

void expect_same_mesh(const Mesh& a, const Mesh& b) {
    ASSERT_EQ(a.vertices.size(), b.vertices.size());
    ASSERT_EQ(a.triangles.size(), b.triangles.size());
    for (size_t i = 0; i < a.vertices.size(); ++i) {
        EXPECT_EQ(a.vertices[i].x, b.vertices[i].x);
        EXPECT_EQ(a.vertices[i].y, b.vertices[i].y);
        EXPECT_EQ(a.vertices[i].z, b.vertices[i].z);
    }
    EXPECT_TRUE(a.triangles == b.triangles);
}

// 1000 closed boxes: 8 points and 12 triangles each, far from a soup.
Mesh boxes_mesh(int n = 1000) {
    Mesh boxes;
    for (int i = 0; i < n; ++i) {
        const Mesh c = cube_mesh(1, {2.0 * i + 0.125, 50, 0});
        const auto first = static_cast<uint32_t>(boxes.vertices.size());
        boxes.vertices.insert(boxes.vertices.end(), c.vertices.begin(), c.vertices.end());
        for (auto t : c.triangles)
            boxes.triangles.push_back({t[0] + first, t[1] + first, t[2] + first});
    }
    return boxes;
}

TEST(MeshLoad, AnAsciiStlReadInBlocksEqualsItReadWhole) {
    // 50,000 triangles are over 4 MB of text: words and lines fall across a block's end.
    const Mesh soup = soup_mesh(50000);
    for (const std::string eol : {"\n", "\r\n", "\r"}) {
        for (const bool bom : {false, true}) {
            const std::string text = (bom ? "\xEF\xBB\xBF" : "") + ascii_stl(soup, eol);
            ASSERT_GT(text.size(), size_t(4 << 20));
            const std::string path = temp().file("blocks.stl");
            write_file(path, text);
            Mesh whole;
            MeshReport r;
            const std::string_view d = std::string_view(text).substr(bom ? 3 : 0);
            detail::read_ascii_stl(d, path, whole, r);
            expect_same_mesh(read_streamed(path, false, false), whole);
            if (eol == "\n" && !bom) {
                expect_same_mesh(read_streamed(path, true, false), whole);
                // load_mesh streams it too.
                load_mesh(path, r);
                EXPECT_EQ(r.format, "ASCII STL");
                EXPECT_EQ(r.triangles_read, 50000u);
            }
        }
    }
    // A file that ends in a word, without a line end (fuzz: the word was cut wrongly).
    for (const std::string last : {"endsolid", "endsolid name", "endfacet"}) {
        std::string text = ascii_stl(soup_mesh(3));
        text.resize(text.rfind("endsolid"));
        text += last;
        const std::string path = temp().file("no_eol.stl");
        write_file(path, text);
        Mesh whole;
        MeshReport r;
        bool whole_ok = true;
        try {
            detail::read_ascii_stl(std::string_view(text), path, whole, r);
        } catch (const InputError&) {
            whole_ok = false;
        }
        EXPECT_EQ(whole_ok, last != "endfacet") << last;
        if (whole_ok)
            expect_same_mesh(read_streamed(path, false, false), whole);
        else
            EXPECT_THROW(read_streamed(path, false, false), InputError) << last;
    }
    // A mistake past the first block is reported at its own line, as when read whole.
    std::string text = ascii_stl(soup);
    const size_t at = text.find("vertex", (4u << 20) + 1000);
    text.replace(at, 6, "vortex");
    const std::string path = temp().file("blocks_bad.stl");
    write_file(path, text);
    const std::string line =
        std::to_string(1 + std::count(text.begin(), text.begin() + long(at), '\n'));
    try {
        read_streamed(path, false, false);
        ADD_FAILURE() << "the misspelt word was read";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("at line " + line +
                                             ": expected 'vertex' or 'endloop', found 'vortex'"),
                  std::string::npos)
            << e.what();
    }
}

TEST(MeshRepair, ATextSoupIsRefusedBeforeItIsWelded) {
    // 3000 triangles of their own three points, and 1000 closed boxes whose files repeat every
    // point for every face, the OBJ with 30,000 vertex lines no face uses.
    const Mesh soup = soup_mesh(3000), boxes = boxes_mesh();
    const std::string obj = temp().file("text_soup.obj"), stl = temp().file("text_soup.stl");
    const std::string box_obj = temp().file("boxes.obj"), box_stl = temp().file("boxes.stl");
    write_file(obj, obj_per_face(soup));
    write_file(stl, ascii_stl(soup));
    write_file(box_obj, obj_per_face(boxes, 30000));
    write_file(box_stl, ascii_stl(boxes));
    LoadOptions refuse;
    refuse.refuse_soup = true;
    refuse.text_first_pass_bytes = 0;
    for (const auto& [path, is_obj] : {std::pair{obj, true}, std::pair{stl, false}}) {
        const detail::TextCounts counts = first_pass(path, is_obj);
        EXPECT_EQ(counts.triangles, 3000u);
        EXPECT_EQ(counts.corners, 9000u);
        MeshReport r;
        try {
            load_mesh(path, r, refuse);
            ADD_FAILURE() << path << " was read";
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(
                          "not a solid: its 3000 triangles have 9000 distinct corners or more"),
                      std::string::npos)
                << e.what();
        }
        // Not refused when it is not asked.
        EXPECT_EQ(read_streamed(path, true, is_obj).triangles.size(), 3000u);
    }
    for (const auto& [path, is_obj] : {std::pair{box_obj, true}, std::pair{box_stl, false}}) {
        const detail::TextCounts counts = first_pass(path, is_obj);
        EXPECT_EQ(counts.triangles, 12000u);
        EXPECT_EQ(counts.corners, 8000u) << "the unused vertex lines are not corners";
        MeshReport r;
        EXPECT_EQ(load_mesh(path, r, refuse).triangles.size(), 12000u);
        // Welded as without the first pass.
        expect_same_mesh(read_streamed(path, true, is_obj), read_streamed(path, false, is_obj));
    }
}

TEST(MeshRepair, Measures) {
    const Mesh m = cube_mesh(10, {5, -5, 2});
    EXPECT_NEAR(signed_volume(m), 1000.0, 1e-9);
    const BBox3 b = bounding_box(m);
    EXPECT_DOUBLE_EQ(b.min.x, 5);
    EXPECT_DOUBLE_EQ(b.max.y, 5);
    EXPECT_DOUBLE_EQ(b.min.z, 2);
    EXPECT_DOUBLE_EQ(b.max.z, 12);
}

// ---- other formats and awkward files written here ----

TEST(MeshFormats, BinaryStlWhoseHeaderSaysSolid) {
    const std::string path = temp().file("solid_header.stl");
    write_file(path, raw_stl(cube_mesh(), "solid cube written by a careless exporter"));
    MeshReport r = load_ok(path);
    EXPECT_EQ(r.format, "binary STL");
    EXPECT_EQ(r.triangles, 12u);
    EXPECT_NEAR(r.volume_mm3, 8000.0, 1e-6);
}

// carve's own writer (the plates of --plate-meshes): the cube reads back as the same 12
// triangles and volume, its header starts with carve's name even when the name given is
// "solid", and each facet's stored normal points out.
TEST(MeshFormats, BinaryStlWrittenByCarveReadsBack) {
    const std::string bytes = carve::binary_stl(cube_mesh(), "solid");
    ASSERT_EQ(bytes.size(), 84u + 12 * 50);
    EXPECT_EQ(bytes.substr(0, 11), "carve solid");
    float normal[3];
    std::memcpy(normal, bytes.data() + 84, sizeof normal);  // the bottom quad's first facet
    EXPECT_FLOAT_EQ(normal[2], -1);
    const std::string path = temp().file("carve_written.stl");
    write_file(path, bytes);
    MeshReport r = load_ok(path);
    EXPECT_EQ(r.format, "binary STL");
    EXPECT_EQ(r.triangles, 12u);
    EXPECT_EQ(r.flipped_triangles, 0u);
    EXPECT_NEAR(r.volume_mm3, 8000.0, 1e-6);
}

// Loads bytes through a named pipe, which carve reads whole before it parses. load_mesh opens
// the pipe and reads it to its end before it can fail, so the writer always finishes.
MeshReport load_through_pipe(const std::string& bytes, const std::string& name, Mesh& mesh) {
    const std::string fifo = temp().file(name);
    std::remove(fifo.c_str());
    EXPECT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    std::thread writer([&] { write_file(fifo, bytes); });
    MeshReport r;
    try {
        mesh = load_mesh(fifo, r);
    } catch (...) {
        writer.join();
        throw;
    }
    writer.join();
    return r;
}

// A binary STL file is welded block by block as it is read; from a pipe it is read whole
// first. Both give the same mesh (skull: 100,002 facets, two blocks of 65,536).
TEST(MeshFormats, BinaryStlStreamedFromAFileEqualsItReadWhole) {
    CARVE_NEED_MODEL("skull.stl");
    const std::string file = kModels + "/skull.stl";
    std::ifstream in(file, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    MeshReport from_file;
    Mesh piped;
    const MeshReport from_pipe = load_through_pipe(bytes, "skull.fifo", piped);
    Mesh streamed = load_mesh(file, from_file);
    EXPECT_EQ(from_file.format, "binary STL");
    EXPECT_EQ(from_pipe.format, "binary STL");
    EXPECT_EQ(from_file.triangles_read, 100002u);
    ASSERT_EQ(streamed.vertices.size(), piped.vertices.size());
    ASSERT_EQ(streamed.triangles, piped.triangles);
    for (size_t v = 0; v < piped.vertices.size(); ++v) {
        ASSERT_EQ(streamed.vertices[v].x, piped.vertices[v].x) << v;
        ASSERT_EQ(streamed.vertices[v].y, piped.vertices[v].y) << v;
        ASSERT_EQ(streamed.vertices[v].z, piped.vertices[v].z) << v;
    }
    EXPECT_EQ(from_file.open_edges, 0u);
    EXPECT_EQ(from_file.volume_mm3, from_pipe.volume_mm3);
}

// An .obj file is parsed in 4 MB blocks as it is read, from a pipe whole: the same mesh, and the
// same line in an error past the first block. This one has a byte order mark, CRLF line ends,
// comments, quads and no line end after its last face.
TEST(MeshFormats, ObjStreamedFromAFileEqualsItReadWhole) {
    std::string obj = "\xEF\xBB\xBF# a 300 x 300 grid of quads on a wavy sheet\r\n";
    const int n = 300;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            obj += "v " + std::to_string(i * 0.25) + " " + std::to_string(j * 0.25) + " " +
                   std::to_string(std::sin(i * 0.1) * std::cos(j * 0.07)) + "  # vertex\r\n";
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int a = j * (n + 1) + i + 1;
            obj += "f " + std::to_string(a) + " " + std::to_string(a + 1) + " " +
                   std::to_string(a + n + 2) + " " + std::to_string(a + n + 1);
            if (i + 1 < n || j + 1 < n) obj += "\n";
        }
    ASSERT_GT(obj.size(), size_t(5) << 20);  // more than one block
    const std::string file = temp().file("grid.obj");
    write_file(file, obj);
    MeshReport from_file;
    const Mesh streamed = load_mesh(file, from_file);
    Mesh piped;
    const MeshReport from_pipe = load_through_pipe(obj, "grid.fifo", piped);
    EXPECT_EQ(from_file.format, "OBJ");
    EXPECT_EQ(from_pipe.format, "OBJ");
    EXPECT_EQ(from_file.triangles_read, size_t(2 * n * n));
    ASSERT_EQ(streamed.triangles, piped.triangles);
    ASSERT_EQ(streamed.vertices.size(), piped.vertices.size());
    for (size_t v = 0; v < piped.vertices.size(); ++v) {
        ASSERT_EQ(streamed.vertices[v].x, piped.vertices[v].x) << v;
        ASSERT_EQ(streamed.vertices[v].z, piped.vertices[v].z) << v;
    }
    EXPECT_EQ(from_file.open_edges, from_pipe.open_edges);
    EXPECT_EQ(from_file.open_edges, size_t(4 * n));

    // A bad reference on the last line, some 6 MB in (in the second block).
    const std::string broken = obj + "\nf 1 2 x";
    const std::string line = std::to_string(2 + (n + 1) * (n + 1) + n * n);
    write_file(file, broken);
    expect_input_error(file, {"malformed OBJ at line " + line, "'x' is not a vertex reference"});
    Mesh unused;
    try {
        load_through_pipe(broken, "broken.fifo", unused);
        ADD_FAILURE() << "the broken OBJ loaded from a pipe";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("malformed OBJ at line " + line), std::string::npos)
            << e.what();
    }
}

TEST(MeshFormats, ObjWithQuadsNegativeIndicesAndSlashes) {
    CARVE_NEED_MODEL("bad/ascii_cube.stl");
    MeshReport stl = load_ok(bad("ascii_cube.stl"));
    std::string obj = "# cube\nmtllib none.mtl\no cube\n";
    for (const auto& c : kCorner)
        obj += "v " + std::to_string(c[0]) + " " + std::to_string(c[1]) + " " +
               std::to_string(c[2]) + "\n";
    obj += "vt 0 0\nvn 0 0 1\ng sides\ns off\n";
    // Two faces with plain indices, two with v/t/n, one with v//n and one with negative indices.
    const int(&q)[6][4] = kQuads;
    obj += "f 1 4 3 2\nf 5 6 7 8\n";
    obj += "f 1/1/1 2/1/1 6/1/1 5/1/1\nf 2/1/1 3/1/1 7/1/1 6/1/1\n";
    obj += "f 3//1 4//1 8//1 7//1\n";
    obj += "f " + std::to_string(q[5][0] - 8) + " " + std::to_string(q[5][1] - 8) + " " +
           std::to_string(q[5][2] - 8) + " " + std::to_string(q[5][3] - 8) + "\n";
    const std::string path = temp().file("cube.obj");
    write_file(path, obj);
    MeshReport r = load_ok(path);
    EXPECT_EQ(r.format, "OBJ");
    EXPECT_EQ(r.triangles, 12u);
    EXPECT_TRUE(r.closed());
    EXPECT_NEAR(r.volume_mm3, stl.volume_mm3, 1e-9);
    EXPECT_TRUE(r.warnings.empty()) << all_warnings(r);
}

TEST(MeshFormats, MalformedObjNamesTheLine) {
    const std::string path = temp().file("broken.obj");
    write_file(path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
    expect_input_error(path, {"line 4", "vertex 7"});
    write_file(path, "v 0 0 zero\n");
    expect_input_error(path, {"line 1", "zero"});
}

namespace {

std::string model_xml(const std::string& build, const std::string& unit = "millimeter") {
    std::string xml =
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
        "<model unit=\"" +
        unit +
        "\" xml:lang=\"en-US\" "
        "xmlns=\"http://schemas.microsoft.com/3dmanufacturing/core/2015/02\">\n"
        "<!-- a comment with <vertex x=\"99\"/> inside -->\n"
        "<resources>\n<object id=\"1\" type=\"model\">\n<mesh>\n<vertices>\n";
    for (const auto& c : kCorner)
        xml += "<vertex x=\"" + std::to_string(c[0]) + "\" y='" + std::to_string(c[1]) + "' z=\"" +
               std::to_string(c[2]) + "\" />\n";
    xml += "</vertices>\n<triangles>\n";
    for (const auto& q : kQuads) {
        xml += "<triangle v1=\"" + std::to_string(q[0]) + "\" v2=\"" + std::to_string(q[1]) +
               "\" v3=\"" + std::to_string(q[2]) + "\"/>\n";
        xml += "<triangle v1=\"" + std::to_string(q[0]) + "\" v2=\"" + std::to_string(q[2]) +
               "\" v3=\"" + std::to_string(q[3]) + "\"/>\n";
    }
    xml +=
        "</triangles>\n</mesh>\n</object>\n"
        "<object id=\"2\" type=\"model\"><components>"
        "<component objectid=\"1\" transform=\"1 0 0 0 1 0 0 0 1 100 0 0\"/>"
        "</components></object>\n</resources>\n<build>\n" +
        build + "</build>\n</model>\n";
    return xml;
}

void write_3mf(const std::string& path, const std::string& model) {
    std::remove(path.c_str());
    int err = 0;
    zip_t* z = zip_open(path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &err);
    ASSERT_NE(z, nullptr);
    auto add = [&](const char* name, const std::string& text) {
        char* copy = static_cast<char*>(std::malloc(text.size()));
        std::memcpy(copy, text.data(), text.size());
        zip_source_t* s = zip_source_buffer(z, copy, text.size(), 1);
        ASSERT_NE(s, nullptr);
        ASSERT_GE(zip_file_add(z, name, s, ZIP_FL_OVERWRITE), 0);
    };
    add("[Content_Types].xml",
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<Types "
        "xmlns=\"http://schemas.openxmlformats.org/package/2006/content-types\"><Default "
        "Extension=\"rels\" "
        "ContentType=\"application/vnd.openxmlformats-package.relationships+xml\"/><Default "
        "Extension=\"model\" "
        "ContentType=\"application/vnd.ms-package.3dmanufacturing-3dmodel+xml\"/>"
        "</Types>");
    add("_rels/.rels",
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<Relationships "
        "xmlns=\"http://schemas.openxmlformats.org/package/2006/relationships\"><Relationship "
        "Target=\"/3D/3dmodel.model\" Id=\"rel0\" "
        "Type=\"http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel\"/></Relationships>");
    add("3D/3dmodel.model", model);
    ASSERT_EQ(zip_close(z), 0);
}

}  // namespace

TEST(MeshFormats, ThreeMfCube) {
    CARVE_NEED_MODEL("bad/ascii_cube.stl");
    MeshReport stl = load_ok(bad("ascii_cube.stl"));
    const std::string path = temp().file("cube.3mf");
    write_3mf(path, model_xml("<item objectid=\"1\" transform=\"1 0 0 0 1 0 0 0 1 5 6 7\"/>\n"));
    MeshReport r = load_ok(path);
    EXPECT_EQ(r.format, "3MF");
    EXPECT_EQ(r.triangles, 12u);
    EXPECT_TRUE(r.closed());
    EXPECT_NEAR(r.volume_mm3, stl.volume_mm3, 1e-9);
    EXPECT_DOUBLE_EQ(r.bbox.min.x, 5.0);
    EXPECT_DOUBLE_EQ(r.bbox.max.z, 27.0);
    EXPECT_TRUE(r.warnings.empty()) << all_warnings(r);
}

TEST(MeshFormats, ThreeMfItemsComponentsMirrorAndUnits) {
    // Object 1 placed as is, object 2 (object 1 moved by 100 in x) mirrored in x: two cubes.
    const std::string path = temp().file("two.3mf");
    write_3mf(path, model_xml("<item objectid=\"1\"/>\n"
                              "<item objectid=\"2\" transform=\"-1 0 0 0 1 0 0 0 1 0 0 0\"/>\n"));
    MeshReport r = load_ok(path);
    EXPECT_EQ(r.triangles, 24u);
    EXPECT_EQ(r.shells, 2u);
    EXPECT_EQ(r.inverted_shells, 0u);  // the mirror's winding was swapped back on reading
    EXPECT_NEAR(r.volume_mm3, 16000.0, 1e-6);
    EXPECT_DOUBLE_EQ(r.bbox.min.x, -120.0);
    // Each build item an object of its own, with its extent (--copies' labels use them).
    ASSERT_EQ(r.items.size(), 2u);
    EXPECT_EQ(r.items[0].name, "object1");
    EXPECT_EQ(r.items[1].name, "object2");
    EXPECT_DOUBLE_EQ(r.items[0].min_x, 0.0);
    EXPECT_DOUBLE_EQ(r.items[0].max_x, 20.0);
    EXPECT_DOUBLE_EQ(r.items[1].min_x, -120.0);
    EXPECT_DOUBLE_EQ(r.items[1].max_x, -100.0);
    EXPECT_DOUBLE_EQ(r.items[1].max_y, 20.0);
    std::string named = model_xml("<item objectid=\"1\"/>\n<item objectid=\"2\"/>\n");
    named.replace(named.find("<object id=\"1\" type=\"model\">"), 28,
                  "<object id=\"1\" type=\"model\" name=\"Left part\">");
    write_3mf(path, named);
    r = load_ok(path);
    ASSERT_EQ(r.items.size(), 2u);
    EXPECT_EQ(r.items[0].name, "Left part");

    write_3mf(path, model_xml("<item objectid=\"1\"/>\n", "centimeter"));
    r = load_ok(path);
    EXPECT_NEAR(r.volume_mm3, 8000.0 * 1000.0, 1e-3);

    write_3mf(path, model_xml("<item objectid=\"9\"/>\n"));
    expect_input_error(path, {"object 9"});
}

TEST(MeshFormats, DamagedThreeMfIsAnInputError) {
    const std::string path = temp().file("damaged.3mf");
    write_3mf(path, model_xml("<item objectid=\"1\"/>\n"));
    std::ifstream in(path, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    write_file(path, bytes.substr(0, bytes.size() / 2));
    expect_input_error(path, {"3MF"});
}

TEST(MeshFormats, ThreeMfWithAForgedSizeIsRefusedWithoutAllocatingIt) {
    // The model part's uncompressed size, as stated in the zip headers, set to 3.75 GiB in a
    // file of a few kilobytes. The reader used to allocate and zero that much (3.9 GB peak RSS)
    // before noticing that the data is not there.
    const std::string path = temp().file("forged.3mf");
    write_3mf(path, model_xml("<item objectid=\"1\"/>\n"));
    std::ifstream in(path, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    in.close();
    const std::string name = "3D/3dmodel.model";
    int patched = 0;
    for (size_t at = bytes.find(name); at != std::string::npos; at = bytes.find(name, at + 1)) {
        const uint32_t forged = 0xF0000000u;
        if (at >= 30 && bytes.compare(at - 30, 4, "PK\x03\x04") == 0)
            std::memcpy(bytes.data() + at - 30 + 22, &forged, 4), ++patched;
        if (at >= 46 && bytes.compare(at - 46, 4, "PK\x01\x02") == 0)
            std::memcpy(bytes.data() + at - 46 + 24, &forged, 4), ++patched;
    }
    ASSERT_EQ(patched, 2);
    write_file(path, bytes);
    rusage before{}, after{};
    getrusage(RUSAGE_SELF, &before);
    expect_input_error(path, {"3MF", "inflate", "refusing"});
    getrusage(RUSAGE_SELF, &after);
    EXPECT_LT(after.ru_maxrss - before.ru_maxrss, 512 * 1024) << "kilobytes of peak memory";
}

TEST(MeshErrors, MissingFile) {
    expect_input_error(temp().file("no_such_model.stl"), {"No such file"});
}

TEST(MeshErrors, Directory) {
    expect_input_error(temp().dir(), {"directory"});
}

TEST(MeshErrors, RandomBytes) {
    std::mt19937 rng(42);
    std::string bytes(3000, '\0');
    for (char& c : bytes) c = static_cast<char>(rng());
    write_file(temp().file("noise.bin"), bytes);
    expect_input_error(temp().file("noise.bin"), {"unknown mesh format"});
    write_file(temp().file("noise.stl"), bytes);
    expect_input_error(temp().file("noise.stl"), {"binary STL"});
}

TEST(MeshErrors, TruncatedAsciiStl) {
    CARVE_NEED_MODEL("bad/ascii_cube.stl");
    std::ifstream in(bad("ascii_cube.stl"));
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    write_file(temp().file("ascii_cut.stl"), text.substr(0, text.size() - 40));
    expect_input_error(temp().file("ascii_cut.stl"), {"ASCII STL", "line"});
}

TEST(MeshErrors, NoTrianglesLeft) {
    write_file(temp().file("flat.stl"),
               "solid flat\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
               "vertex 2 0 0\nendloop\nendfacet\nendsolid flat\n");
    expect_input_error(temp().file("flat.stl"), {"degenerate"});
    write_file(temp().file("none.stl"), "solid none\nendsolid none\n");
    expect_input_error(temp().file("none.stl"), {"no triangles"});
}

TEST(MeshErrors, CoordinatesBeyondAKilometre) {
    Mesh m = cube_mesh(2e6);
    write_file(temp().file("huge.stl"), raw_stl(m, "huge"));
    expect_input_error(temp().file("huge.stl"), {"1 km", "wrong units"});
}

// ---- mesh_info ----

TEST(MeshInfo, JsonAndText) {
    CARVE_NEED_MODEL("bad/open_cube_missing_top.stl");
    MeshReport r = load_ok(bad("open_cube_missing_top.stl"));
    nlohmann::json j = to_json(r);
    for (const char* key :
         {"model_volume_mm3", "triangles", "vertices", "bbox_min", "bbox_max", "size_mm", "closed",
          "open_edges", "nonmanifold_edges", "shells", "format", "warnings"})
        EXPECT_TRUE(j.contains(key)) << key;
    EXPECT_EQ(j["triangles"], 10);
    EXPECT_EQ(j["closed"], false);
    EXPECT_EQ(j["open_edges"], 4);
    EXPECT_EQ(j["bbox_max"][2], 20.0);
    EXPECT_EQ(j["size_mm"][0], 20.0);
    EXPECT_EQ(j["warnings"].size(), r.warnings.size());
    const std::string text = describe(r);
    EXPECT_NE(text.find("binary STL"), std::string::npos) << text;
    EXPECT_NE(text.find("20.00 x 20.00 x 20.00 mm"), std::string::npos) << text;
    EXPECT_NE(text.find("4 open edges"), std::string::npos) << text;
    EXPECT_NE(text.find("cm^3"), std::string::npos) << text;
}

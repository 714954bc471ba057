// Hostile input, round two (issue #38), the work bounded by the input: the vertex limits before
// any plane is chained. Every input is made by the test; no timings asserted.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "base/errors.hpp"
#include "support/carve_run.hpp"
#include "support/sanitizers.hpp"
#include "support/stl_boxes.hpp"

namespace fs = std::filesystem;
using namespace carve;
using namespace carve::test;

namespace {

// A comb `height` mm tall: `points` vertices along its toothed side (teeth 0.5 mm deep, 0.05 mm
// apart), a straight back, caps made of strips from each tooth to the back.
std::vector<StlTriangle> comb(int points, float height) {
    std::vector<StlTriangle> t;
    auto p = [&](int k, float z) {
        return std::array<float, 3>{0.05f * float(k), k % 2 ? 10.5f : 10.0f, z};
    };
    auto q = [&](int k, float z) { return std::array<float, 3>{0.05f * float(k), 0.0f, z}; };
    for (int k = 0; k + 1 < points; ++k) {
        t.push_back({p(k, 0), q(k, 0), p(k + 1, 0)});  // bottom, seen from below
        t.push_back({q(k, 0), q(k + 1, 0), p(k + 1, 0)});
        t.push_back({p(k, height), p(k + 1, height), q(k, height)});
        t.push_back({q(k, height), p(k + 1, height), q(k + 1, height)});
        t.push_back({p(k + 1, 0), p(k, 0), p(k, height)});  // toothed side
        t.push_back({p(k + 1, 0), p(k, height), p(k + 1, height)});
        t.push_back({q(k, 0), q(k + 1, 0), q(k + 1, height)});  // back
        t.push_back({q(k, 0), q(k + 1, height), q(k, height)});
    }
    const int e = points - 1;
    t.push_back({q(0, 0), p(0, 0), p(0, height)});
    t.push_back({q(0, 0), p(0, height), q(0, height)});
    t.push_back({p(e, 0), q(e, 0), q(e, height)});
    t.push_back({p(e, 0), q(e, height), p(e, height)});
    return t;
}

// A 40 mm cube whose six faces are each a fan of `per_face` slivers from one corner to the two
// far edges. The fans meet in T-junctions along the cube's edges: the mesh is open, and each
// plane cuts it into open chains that the slicer joins one into the next.
std::vector<StlTriangle> fanned_cube(int per_face) {
    using V = std::array<float, 3>;
    std::vector<StlTriangle> t;
    auto at = [](V o, V u, V v, float a, float b) {
        return V{o[0] + a * u[0] + b * v[0], o[1] + a * u[1] + b * v[1],
                 o[2] + a * u[2] + b * v[2]};
    };
    auto face = [&](V o, V u, V v) {
        const int half = per_face / 2;
        std::vector<V> far;  // o + u + s v, then o + (1 - s) u + v
        for (int k = 0; k <= half; ++k) far.push_back(at(o, u, v, 1, float(k) / half));
        for (int k = 1; k <= half; ++k) far.push_back(at(o, u, v, 1 - float(k) / half, 1));
        for (size_t k = 0; k + 1 < far.size(); ++k) t.push_back({o, far[k], far[k + 1]});
    };
    const float L = 40;
    const V z{0, 0, 0}, x{L, 0, 0}, y{0, L, 0}, up{0, 0, L};
    face(z, y, x);
    face(up, x, y);
    face(z, x, up);
    face(y, up, x);
    face(z, up, y);
    face(x, y, up);
    return t;
}

}  // namespace

TEST(HostileWork, OpenChainsJoinedOneIntoTheNextKeepNoCopies) {
    // Each chain absorbed into the next kept its storage in the slicer's pool, so the pool held
    // the chain's points once for every chain before it: 226 MB for this 40 mm cube (jemalloc's
    // heap profile, all of it in PlaneSlicer::finish); 17 MB now.
    SKIP_UNDER_ULIMIT_V();
    const fs::path stl = write_stl("fanned_cube.stl", fanned_cube(2000));
    const fs::path g = scratch() / "fanned_cube.gcode";
    const CarveRun r = run_carve("slice " + stl.string() + " -q --threads 1 -o " + g.string(),
                                 "ulimit -v 120000;");
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(fs::exists(g));
}

TEST(HostileWork, VertexLimitsStopAZigZagBeforeItsPlanesAreChained) {
    // 4,000 teeth points: each of the ten planes cuts 16,000 segments. Refused on the segments
    // counted from the triangles alone, more than twice the limits (the slice-by-slice guard
    // after the union words it otherwise): chaining, simplifying and uniting 800,000 such
    // points a plane ran for minutes each.
    const fs::path stl = write_stl("comb.stl", comb(4000, 2));
    const fs::path g = scratch() / "comb.gcode";
    CarveRun r = run_carve("slice " + stl.string() + " -q --max-vertices 50000 -o " + g.string());
    EXPECT_EQ(r.status, kExitBadInput) << r.err;
    EXPECT_NE(r.err.find("segments, more than twice the limit of 50000 contour vertices before any "
                         "simplification"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("the slices down to layer"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(g));
    r = run_carve("slice " + stl.string() + " -q --max-vertices-per-layer 7000 -o " + g.string());
    EXPECT_EQ(r.status, kExitBadInput) << r.err;
    EXPECT_NE(
        r.err.find("layer 9 (z = 1.90 mm) cuts 16000 segments, more than twice the limit of 7000"),
        std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(g));
}

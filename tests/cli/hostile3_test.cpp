// Hostile input, round two (issue #38), the work bounded by the input: the vertex limits before
// any plane is chained. Every input is made by the test; no timings asserted.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "base/errors.hpp"
#include "support/carve_run.hpp"
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

}  // namespace

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

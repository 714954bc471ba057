// Douglas-Peucker simplification (geometry/simplify.hpp): every dropped vertex stays within
// the tolerance, straight runs collapse to their ends, small contours are kept whole.
#include "geometry/simplify.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "support/shapes.hpp"

using namespace carve;
using carve::test::circle;

namespace {

constexpr Coord kMm = 1000;

}  // namespace

TEST(DouglasPeucker, CircleWithinTolerance) {
    const Path c = circle(0, 0, 10 * kMm, 2000);
    const Path s = douglas_peucker(c, true, 50);
    EXPECT_LT(s.size(), size_t(200));
    EXPECT_GT(s.size(), size_t(20));
    // Every original point lies within the tolerance of the simplified loop.
    double worst = 0;
    for (const Point& p : c) {
        double best = 1e18;
        for (size_t i = 0; i < s.size(); ++i)
            best = std::min(best, segment_distance(p, s[i], s[(i + 1) % s.size()]));
        worst = std::max(worst, best);
    }
    EXPECT_LE(worst, 50.0 + 1e-6);
}

TEST(DouglasPeucker, StraightLineCollapses) {
    Path line;
    for (int k = 0; k <= 100; ++k) line.push_back({k * 100, (k % 2) * 10});
    const Path s = douglas_peucker(line, false, 50);
    ASSERT_EQ(s.size(), size_t(2));
    EXPECT_EQ(s.front(), line.front());
    EXPECT_EQ(s.back(), line.back());
}

TEST(DouglasPeucker, TrianglesAndSegmentsAreKeptWhole) {
    const Path tri{{0, 0}, {1000, 1}, {0, 2}};
    EXPECT_EQ(douglas_peucker(tri, true, 50), tri);
    const Path seg{{0, 0}, {5, 5}};
    EXPECT_EQ(douglas_peucker(seg, false, 50), seg);
}

TEST(DouglasPeucker, ScratchBuffersGiveTheSameResult) {
    SimplifyScratch scratch;
    Path out;
    for (int n : {50, 500, 5}) {
        const Path c = circle(0, 0, 10 * kMm, n);
        douglas_peucker(c, true, 20, scratch, out);
        EXPECT_EQ(out, douglas_peucker(c, true, 20)) << n;
    }
}

TEST(DouglasPeucker, AZigZagWhoseTeethAllStayCostsABoundedAmount) {
    // Issue #38: every tooth is taller than the tolerance and each range splits next to its
    // end, so the plain algorithm measures some n^2 / 2 distances (800,000 vertices a slice ran
    // for hours). With the budget spent it keeps the rest whole, which drops nothing it must
    // keep; a contour that needs no more than an ordinary one is not affected.
    Path zigzag;
    for (int k = 0; k < 40000; ++k) zigzag.push_back({k, (k % 2) * 500});
    SimplifyScratch scratch;
    Path out;
    EXPECT_FALSE(douglas_peucker(zigzag, false, 100, scratch, out));
    EXPECT_EQ(out, zigzag);
    zigzag.push_back({40000, -100000});
    EXPECT_FALSE(douglas_peucker(zigzag, true, 100, scratch, out));
    EXPECT_EQ(out, zigzag);
    const Path c = circle(0, 0, 10 * kMm, 20000);
    EXPECT_TRUE(douglas_peucker(c, true, 50, scratch, out));
    EXPECT_LT(out.size(), size_t(200));
}

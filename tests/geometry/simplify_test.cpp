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

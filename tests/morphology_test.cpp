// Property tests of the 24-gon morphology on simple shapes.
#include <gtest/gtest.h>

#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"

using namespace carve;

namespace {
Paths square(Coord x0, Coord y0, Coord side) {
    return {{{x0, y0}, {x0 + side, y0}, {x0 + side, y0 + side}, {x0, y0 + side}}};
}
}  // namespace

TEST(Morphology, DilateSquareAddsBandAndRoundedCorners) {
    const Coord a = 10000, r = 1000;
    Paths d = dilate(square(0, 0, a), r);
    double expected = double(a) * a + 4.0 * a * r + area(Paths{disk(r)});
    EXPECT_NEAR(area(d), expected, expected * 1e-4);
}

TEST(Morphology, ErodeSquareShrinksBySharpInset) {
    const Coord a = 10000, r = 1000;
    Paths e = erode(square(0, 0, a), r);
    double expected = double(a - 2 * r) * (a - 2 * r);
    EXPECT_NEAR(area(e), expected, expected * 1e-3);
    EXPECT_NEAR(area(subtract(e, square(0, 0, a))), 0.0, 1.0);
}

// The skeleton's own circle-event formulas (skeleton/circle_events.hpp) against Boost's exact
// big-integer ones, on the events Boost's builder actually meets on thin shapes like the
// slices' seed regions: strips of random widths along random polylines and dilated polygons.
#include "skeleton/circle_events.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"
#include "support/test_rng.hpp"

using namespace carve;

namespace {

namespace bp = boost::polygon;

using skel::BoostPredicates;

struct Tally {
    long pss = 0, pss_ours = 0, sss = 0, sss_ours = 0, wrong = 0;
};
Tally tally;

// Within 64 units in the last place of Boost's exact result (converted to double).
bool agrees(double mine, double exact) {
    return std::abs(mine - exact) <= 64 * 0x1p-52 * std::abs(exact);
}

template <typename Site, typename Circle>
struct CheckedCircles {
    using Ours = skel::LocalCircles<Site, Circle>;
    typename Ours::Lazy lazy;
    typename BoostPredicates::template mp_circle_formation_functor<Site, Circle> exact;

    void compare(const Circle& mine, const Circle& reference) {
        if (!agrees(mine.x(), reference.x()) || !agrees(mine.y(), reference.y()) ||
            !agrees(mine.lower_x(), reference.lower_x()))
            ++tally.wrong;
    }
    void ppp(const Site& a, const Site& b, const Site& c, Circle& circle) {
        lazy.ppp(a, b, c, circle);
    }
    void pps(const Site& a, const Site& b, const Site& c, int index, Circle& circle) {
        lazy.pps(a, b, c, index, circle);
    }
    void pss(const Site& a, const Site& b, const Site& c, int index, Circle& circle) {
        exact.pss(a, b, c, index, circle);
        ++tally.pss;
        Circle mine = circle;
        if (Ours::at_endpoint(a, b, c, mine)) ++tally.pss_ours, compare(mine, circle);
    }
    void sss(const Site& a, const Site& b, const Site& c, Circle& circle) {
        exact.sss(a, b, c, circle);
        ++tally.sss;
        Circle mine = circle;
        if (Ours::three_lines(a, b, c, mine)) ++tally.sss_ours, compare(mine, circle);
    }
};

struct CheckedPredicates : BoostPredicates {
    template <typename Site, typename Circle>
    using circle_formation_predicate = BoostPredicates::circle_formation_predicate<
        Site, Circle, BoostPredicates::circle_existence_predicate<Site>,
        CheckedCircles<Site, Circle>>;
};

void build(const Paths& region) {
    bp::voronoi_builder<int32_t, bp::detail::voronoi_ctype_traits<int32_t>, CheckedPredicates>
        builder;
    for (const Path& c : region)
        for (size_t i = 0; i < c.size(); ++i) {
            const Point& a = c[i];
            const Point& b = c[(i + 1) % c.size()];
            builder.insert_segment(int32_t(a.X), int32_t(a.Y), int32_t(b.X), int32_t(b.Y));
        }
    bp::voronoi_diagram<double> diagram;
    builder.construct(&diagram);
}

}  // namespace

TEST(CircleEvents, AgreeWithBoostExactArithmeticOnThinShapes) {
    carve::test::Rng rng(11);
    // Far from the origin, as the builder's callers place sites (LocalCircles shifts them).
    const Coord off = 3'000'000;
    for (int round = 0; round < 40; ++round) {
        Path line;
        for (int k = 0; k < rng.integer(2, 8); ++k) {
            // One draw per statement: the order of a call's arguments is unspecified.
            const Coord x = off + Coord(rng.uniform(0, 30000));
            line.emplace_back(x, off + Coord(rng.uniform(0, 30000)));
        }
        build(dilate_lines({line}, Coord(rng.uniform(150, 1500))));
        Path poly;
        const int n = rng.integer(5, 12);
        for (int k = 0; k < n; ++k) {
            const double a = 2 * 3.141592653589793 * k / n, r = rng.uniform(3000, 15000);
            poly.emplace_back(off + Coord(r * std::cos(a)), off + Coord(r * std::sin(a)));
        }
        build(erode(dilate(unite({poly}), 2000), Coord(rng.uniform(1000, 4000))));
    }
    EXPECT_EQ(tally.wrong, 0);
    // The formulas must carry most events, or the exact path is doing the work after all.
    EXPECT_GT(tally.pss, 1000);
    EXPECT_GT(tally.sss, 1000);
    EXPECT_GT(tally.pss_ours, tally.pss / 2);
    EXPECT_GT(tally.sss_ours, tally.sss * 9 / 10);
    std::printf("PSS %ld (ours %ld), SSS %ld (ours %ld)\n", tally.pss, tally.pss_ours, tally.sss,
                tally.sss_ours);
}

// Overlap trimming of open lines (geometry/lines.hpp): what a line keeps lies at least the
// radius from the lines before it, what it loses lies within the radius of what was kept, and
// the plain cases (a line twice, a crossing, a half overlap) come out as drawn.
#include "geometry/lines.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "geometry/polygon.hpp"
#include "geometry/simplify.hpp"

using namespace carve;

namespace {

constexpr Coord kMm = 1000;

double distance_to(const Point& p, const Paths& lines) {
    double best = 1e18;
    for (const Path& l : lines)
        for (size_t k = 0; k + 1 < l.size(); ++k)
            best = std::min(best, segment_distance(p, l[k], l[k + 1]));
    return best;
}

// Points every `step` units along a polyline, its ends included.
std::vector<Point> samples(const Path& line, double step) {
    std::vector<Point> out;
    for (size_t k = 0; k + 1 < line.size(); ++k) {
        const double len = distance(line[k], line[k + 1]);
        const int n = std::max(1, int(len / step));
        for (int i = 0; i <= n; ++i) {
            const double t = double(i) / n;
            out.emplace_back(line[k].X + Coord(std::llround(t * (line[k + 1].X - line[k].X))),
                             line[k].Y + Coord(std::llround(t * (line[k + 1].Y - line[k].Y))));
        }
    }
    return out;
}

double total_length(const Paths& lines) {
    double sum = 0;
    for (const Path& l : lines)
        for (size_t k = 0; k + 1 < l.size(); ++k) sum += distance(l[k], l[k + 1]);
    return sum;
}

}  // namespace

TEST(TrimOverlaps, ALineTwiceIsPrintedOnce) {
    const Path a{{0, 0}, {10 * kMm, 0}};
    const Paths out = trim_overlaps({a, a, Path{a.back(), a.front()}}, 300, 400);
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0], a);
}

TEST(TrimOverlaps, ACrossingLineIsCutAtTheRadiusOnEachSide) {
    const Path a{{0, 0}, {10 * kMm, 0}};
    const Path b{{5 * kMm, -5 * kMm}, {5 * kMm, 5 * kMm}};
    const Paths out = trim_overlaps({a, b}, 300, 400);
    ASSERT_EQ(out.size(), 3u);
    for (size_t i = 1; i < 3; ++i) {
        EXPECT_NEAR(distance_to(out[i].front(), {a}), i == 1 ? 5000 : 300, 2);
        EXPECT_NEAR(distance_to(out[i].back(), {a}), i == 1 ? 300 : 5000, 2);
    }
}

TEST(TrimOverlaps, AHalfOverlapKeepsTheOtherHalf) {
    const Path a{{0, 0}, {10 * kMm, 0}};
    const Path b{{5 * kMm, 100}, {15 * kMm, 100}};  // 0.1 mm beside a, half along it
    const Paths out = trim_overlaps({a, b}, 300, 400);
    ASSERT_EQ(out.size(), 2u);
    const double kept = distance(out[1].front(), out[1].back());
    // From 10 mm plus what keeps it 0.3 mm from a's end (sqrt(0.3^2 - 0.1^2)) to 15 mm.
    EXPECT_NEAR(kept, 5000 - std::sqrt(300.0 * 300 - 100 * 100), 3);
}

TEST(TrimOverlaps, StubsAtFreeEndsGoPiecesBetweenCutsStay) {
    const Path a{{0, 0}, {10 * kMm, 0}};
    const Path c{{0, 1000}, {10 * kMm, 1000}};
    // Crosses a, 0.5 mm out on each side: stubs of 0.2 mm beyond the radius, both dropped.
    // Between a and c: a 0.4 mm piece joining them, kept though shorter than min_end.
    const Path stub{{3 * kMm, 500}, {3 * kMm, -500}};
    const Path join{{7 * kMm, 0}, {7 * kMm, 1000}};
    const Paths out = trim_overlaps({a, c, stub, join}, 300, 400);
    ASSERT_EQ(out.size(), 3u);
    EXPECT_EQ(out[2].front().X, 7 * kMm);
    EXPECT_NEAR(distance(out[2].front(), out[2].back()), 400, 2);
}

TEST(TrimOverlaps, RandomLinesKeepTheirDistanceAndLoseOnlyWhatIsCovered) {
    std::mt19937 rng(35);
    std::uniform_int_distribution<Coord> coord(0, 20 * kMm);
    std::uniform_int_distribution<int> bends(1, 3);
    const Coord radius = 315;
    for (int round = 0; round < 20; ++round) {
        Paths lines;
        for (int i = 0; i < 40; ++i) {
            Path l{{coord(rng), coord(rng)}};
            for (int k = bends(rng); k > 0; --k) {
                // Short steps, often along one axis, so that lines run along each other.
                const Point& p = l.back();
                const bool along_x = rng() % 2;
                const Coord d = coord(rng) / 4 - 2500;
                l.emplace_back(along_x ? p.X + d : p.X, along_x ? p.Y : p.Y + d);
            }
            lines.push_back(l);
        }
        LineSet set(radius, 0);
        Paths kept;
        for (const Path& l : lines) {
            const Paths mine = set.add(l);
            // What a line keeps stays the radius from every line kept before it.
            for (const Path& p : mine)
                for (const Point& q : samples(p, 50))
                    EXPECT_GE(distance_to(q, kept), radius - 2) << "round " << round;
            // What it loses lies within the radius of what was kept (itself included).
            Paths now = kept;
            now.insert(now.end(), mine.begin(), mine.end());
            for (const Point& q : samples(l, 50))
                EXPECT_LE(distance_to(q, now), radius + 2) << "round " << round;
            kept = std::move(now);
        }
        EXPECT_LE(total_length(kept), total_length(lines) + 1);
    }
}

// chords(): on random regions with holes and random directions, each interval lies inside the
// region (its middle is in it, and just past either end is out of it unless another interval
// starts there), the lengths agree with Clipper's clipping of the same line, and summed over
// lines a spacing apart they give the region's area.
TEST(Chords, IntervalsAreTheRegionOnEachLine) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> unit(0, 1);
    for (int round = 0; round < 20; ++round) {
        // A star-shaped outer contour and a smaller square hole inside it.
        Path outer;
        const int n = 7 + round % 9;
        for (int i = 0; i < n; ++i) {
            const double t = 2 * std::numbers::pi * i / n;
            const double r = (15 + 10 * unit(rng)) * kMm;
            outer.emplace_back(Coord(std::llround(r * std::cos(t))),
                               Coord(std::llround(r * std::sin(t))));
        }
        Path hole{
            {-4 * kMm, -4 * kMm}, {-4 * kMm, 4 * kMm}, {4 * kMm, 4 * kMm}, {4 * kMm, -4 * kMm}};
        const Paths region{outer, hole};
        const double angle = unit(rng) * std::numbers::pi;
        const double dx = std::cos(angle), dy = std::sin(angle);
        const double spacing = 250;
        std::vector<double> offsets;
        for (double s = -30 * kMm + unit(rng) * spacing; s < 30 * kMm; s += spacing)
            offsets.push_back(s);
        const auto found = chords(region, dx, dy, offsets);
        ASSERT_EQ(found.size(), offsets.size());
        double summed = 0;
        for (size_t k = 0; k < offsets.size(); ++k) {
            double along = 0;
            for (size_t i = 0; i < found[k].size(); ++i) {
                const Chord& c = found[k][i];
                ASSERT_LT(c.from, c.to);
                if (i > 0) {
                    EXPECT_GE(c.from, found[k][i - 1].to);
                }
                along += c.to - c.from;
                const Point mid = chord_point(dx, dy, offsets[k], (c.from + c.to) / 2);
                EXPECT_TRUE(point_in_region(mid, region)) << "round " << round;
                if (c.to - c.from < 50) continue;  // a graze: the rounded ends say nothing
                const bool next = i + 1 < found[k].size() && found[k][i + 1].from - c.to < 50;
                if (!next) {
                    EXPECT_FALSE(
                        point_in_region(chord_point(dx, dy, offsets[k], c.to + 20), region))
                        << "round " << round;
                }
            }
            // Clipper clips the same line, 100 mm long, to the same length (its ends rounded to
            // units tilt it: a few micrometres where it grazes an edge).
            const Path line{chord_point(dx, dy, offsets[k], -50 * kMm),
                            chord_point(dx, dy, offsets[k], 50 * kMm)};
            double clipped = 0;
            for (const Path& p : clip_lines(Paths{line}, region)) clipped += total_length({p});
            EXPECT_NEAR(along, clipped, 12.0) << "round " << round << " line " << k;
            summed += along * spacing;
        }
        const double a = area(region);
        EXPECT_NEAR(summed, a, 0.01 * a) << "round " << round;
    }
}

// Overlap trimming of open lines (lines.hpp).
//
// What lies nearer than a radius to a segment is a capsule, convex, so the part of a segment
// within it is one interval, found in closed form. A grid of cells holds the kept segments so that
// each new one meets its neighbours only.
#include "geometry/lines.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <unordered_map>
#include <utility>
#include <vector>

namespace carve {

namespace {

struct Segment {
    Point a, b;
};

struct DPoint {
    double x, y;
};

// Where a + t d (t real) lies strictly inside the disk of radius r about q: t in (lo, hi).
bool in_disk(DPoint a, DPoint d, DPoint q, double r2, double& lo, double& hi) {
    const double ex = a.x - q.x, ey = a.y - q.y;
    const double A = d.x * d.x + d.y * d.y, B = ex * d.x + ey * d.y, C = ex * ex + ey * ey - r2;
    const double disc = B * B - A * C;
    if (!(disc > 0) || !(A > 0)) return false;
    const double root = std::sqrt(disc);
    lo = (-B - root) / A;
    hi = (-B + root) / A;
    return true;
}

// Where the linear function v0 + t v1 lies in (lo_bound, hi_bound): t in (lo, hi).
bool in_band(double v0, double v1, double lo_bound, double hi_bound, double& lo, double& hi) {
    if (v1 == 0) {
        if (!(v0 > lo_bound && v0 < hi_bound)) return false;
        lo = -std::numeric_limits<double>::infinity();
        hi = std::numeric_limits<double>::infinity();
        return true;
    }
    lo = (lo_bound - v0) / v1;
    hi = (hi_bound - v0) / v1;
    if (lo > hi) std::swap(lo, hi);
    return true;
}

// The interval of t in [0, 1] where a + t (b - a) lies nearer than `radius` to `s`, if any.
// Nearer than the radius to a segment is a capsule: the band along it and the disks at its ends;
// the capsule is convex, so the line meets it in one interval, the hull of where it meets the
// three parts (it replaced a ternary search and two bisections, 200 distances a pair, which
// were a quarter of a wide cube's slicing time).
bool near_interval(const Segment& seg, const Segment& s, double radius, double& lo, double& hi) {
    const DPoint a{double(seg.a.X), double(seg.a.Y)};
    const DPoint d{double(seg.b.X) - a.x, double(seg.b.Y) - a.y};
    const DPoint p{double(s.a.X), double(s.a.Y)}, q{double(s.b.X), double(s.b.Y)};
    const double r2 = radius * radius;
    double l = std::numeric_limits<double>::infinity(), h = -l;
    auto hull = [&](double pl, double ph) {
        l = std::min(l, pl);
        h = std::max(h, ph);
    };
    double pl = 0, ph = 0;
    if (in_disk(a, d, p, r2, pl, ph)) hull(pl, ph);
    if (in_disk(a, d, q, r2, pl, ph)) hull(pl, ph);
    const double ex = q.x - p.x, ey = q.y - p.y, len2 = ex * ex + ey * ey;
    if (len2 > 0) {
        // Along s (0 .. len2 between its ends) and across it (within radius x its length).
        const double ax = a.x - p.x, ay = a.y - p.y, len = std::sqrt(len2);
        double al = 0, ah = 0, cl = 0, ch = 0;
        if (in_band(ax * ex + ay * ey, d.x * ex + d.y * ey, 0, len2, al, ah) &&
            in_band(ex * ay - ey * ax, ex * d.y - ey * d.x, -radius * len, radius * len, cl, ch) &&
            std::max(al, cl) < std::min(ah, ch))
            hull(std::max(al, cl), std::min(ah, ch));
    }
    lo = std::max(l, 0.0);
    hi = std::min(h, 1.0);
    return lo < hi;
}

class SegmentGrid {
  public:
    explicit SegmentGrid(Coord cell) : cell_(std::max<Coord>(cell, 1)) {}
    void add(const Segment& s, Coord grow) {
        const size_t id = segments_.size();
        segments_.push_back(s);
        for_cells(s, grow, [&](long long key) { cells_[key].push_back(id); });
    }
    // The kept segments that may lie within `grow` of s, each once.
    std::vector<size_t> near(const Segment& s, Coord grow) {
        std::vector<size_t> out;
        for_cells(s, grow, [&](long long key) {
            const auto it = cells_.find(key);
            if (it != cells_.end()) out.insert(out.end(), it->second.begin(), it->second.end());
        });
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
        return out;
    }
    const Segment& operator[](size_t i) const { return segments_[i]; }

  private:
    template <class F>
    void for_cells(const Segment& s, Coord grow, F&& f) const {
        const auto lo = [&](Coord v) { return (long long)std::floor(double(v - grow) / cell_); };
        const auto hi = [&](Coord v) { return (long long)std::floor(double(v + grow) / cell_); };
        for (long long i = lo(std::min(s.a.X, s.b.X)); i <= hi(std::max(s.a.X, s.b.X)); ++i)
            for (long long j = lo(std::min(s.a.Y, s.b.Y)); j <= hi(std::max(s.a.Y, s.b.Y)); ++j)
                f(i * 0x100000 + j);
    }
    Coord cell_;
    std::vector<Segment> segments_;
    std::unordered_map<long long, std::vector<size_t>> cells_;
};

Point lerp(const Segment& s, double t) {
    return Point(s.a.X + static_cast<Coord>(std::llround(t * double(s.b.X - s.a.X))),
                 s.a.Y + static_cast<Coord>(std::llround(t * double(s.b.Y - s.a.Y))));
}

}  // namespace

struct LineSet::Grid : SegmentGrid {
    using SegmentGrid::SegmentGrid;
};

LineSet::LineSet(Coord radius, Coord min_end)
    : radius_(radius),
      min_end_(min_end),
      kept_(std::make_unique<Grid>(std::max<Coord>(4 * radius, 1000))) {}
LineSet::~LineSet() = default;

Paths LineSet::add(const Path& line) {
    const Coord radius = radius_, min_end = min_end_;
    Grid& kept = *kept_;
    Paths out;
    {
        struct Piece {
            Path points;
            bool from_start = false;  // begins where the line begins
            bool to_end = false;      // ends where the line ends
        };
        std::vector<Piece> pieces;
        bool joined = false;  // the last piece reaches the end of the segment before
        const size_t last = line.size() < 2 ? 0 : line.size() - 2;
        for (size_t k = 0; k + 1 < line.size(); ++k) {
            const Segment seg{line[k], line[k + 1]};
            if (seg.a == seg.b) continue;
            // Against the lines kept before this one only: its own segments meet at its bends.
            std::vector<std::pair<double, double>> gone;
            for (size_t id : kept.near(seg, radius)) {
                double lo = 0, hi = 0;
                if (near_interval(seg, kept[id], double(radius), lo, hi)) gone.emplace_back(lo, hi);
            }
            std::sort(gone.begin(), gone.end());
            const bool carry = joined;
            joined = false;
            double t = 0;  // kept from t up to the next interval gone
            for (size_t g = 0; g <= gone.size(); ++g) {
                const double until = g < gone.size() ? gone[g].first : 1.0;
                if (until > t) {
                    if (!(carry && t == 0))
                        pieces.push_back({Path{lerp(seg, t)}, k == 0 && t == 0, false});
                    pieces.back().points.push_back(lerp(seg, until));
                    joined = until >= 1.0;
                    pieces.back().to_end = joined && k == last;
                }
                if (g < gone.size()) t = std::max(t, gone[g].second);
            }
        }
        const size_t first_new = out.size();
        for (Piece& piece : pieces) {
            if (piece.points.size() < 2) continue;
            double len = 0;
            for (size_t k = 0; k + 1 < piece.points.size(); ++k)
                len += distance(piece.points[k], piece.points[k + 1]);
            if (len <= 0) continue;
            // A stub at a free end of a cut line holds nothing; what lies between two cuts may
            // be what joins two lines.
            const bool whole = piece.from_start && piece.to_end;
            if (!whole && (piece.from_start || piece.to_end) && len < double(min_end)) continue;
            out.push_back(std::move(piece.points));
        }
        for (size_t i = first_new; i < out.size(); ++i)
            for (size_t k = 0; k + 1 < out[i].size(); ++k)
                kept.add(Segment{out[i][k], out[i][k + 1]}, radius);
    }
    return out;
}

void LineSet::keep(const Path& line) {
    for (size_t k = 0; k + 1 < line.size(); ++k)
        if (line[k] != line[k + 1]) kept_->add(Segment{line[k], line[k + 1]}, radius_);
}

Paths trim_overlaps(const Paths& lines, Coord radius, Coord min_end) {
    LineSet set(radius, min_end);
    Paths out;
    for (const Path& line : lines)
        for (Path& p : set.add(line)) out.push_back(std::move(p));
    return out;
}

std::vector<std::vector<Chord>> chords(const Paths& region, double dx, double dy,
                                       const std::vector<double>& offsets) {
    std::vector<std::vector<double>> crossings(offsets.size());
    const double nx = -dy, ny = dx;
    for (const Path& p : region) {
        const size_t n = p.size();
        for (size_t i = 0; i < n; ++i) {
            const Point& a = p[i];
            const Point& b = p[(i + 1) % n];
            const double sa = nx * double(a.X) + ny * double(a.Y);
            const double sb = nx * double(b.X) + ny * double(b.Y);
            if (sa == sb) continue;
            // Half-open in s, so a line through a vertex counts its two edges once.
            const double lo = std::min(sa, sb), hi = std::max(sa, sb);
            auto k = std::lower_bound(offsets.begin(), offsets.end(), lo);
            for (; k != offsets.end() && *k < hi; ++k) {
                const double t = (*k - sa) / (sb - sa);
                const double x = double(a.X) + t * double(b.X - a.X);
                const double y = double(a.Y) + t * double(b.Y - a.Y);
                crossings[size_t(k - offsets.begin())].push_back(dx * x + dy * y);
            }
        }
    }
    std::vector<std::vector<Chord>> out(offsets.size());
    for (size_t k = 0; k < offsets.size(); ++k) {
        std::vector<double>& c = crossings[k];
        std::sort(c.begin(), c.end());
        for (size_t i = 0; i + 1 < c.size(); i += 2)
            if (c[i + 1] > c[i]) out[k].push_back({c[i], c[i + 1]});
    }
    return out;
}

Point chord_point(double dx, double dy, double s, double along) {
    return Point(static_cast<Coord>(std::llround(dx * along - dy * s)),
                 static_cast<Coord>(std::llround(dy * along + dx * s)));
}

}  // namespace carve

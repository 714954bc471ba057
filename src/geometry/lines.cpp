// Overlap trimming of open lines (lines.hpp).
//
// The distance from a point moving along a segment to another segment is convex in the
// parameter, so the part of a segment nearer than a radius to another is one interval: found by
// a ternary search for the closest parameter, then a bisection on each side. A grid of cells
// holds the kept segments so that each new one meets its neighbours only.
#include "geometry/lines.hpp"

#include <algorithm>
#include <cmath>
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

double point_segment(DPoint p, const Segment& s) {
    const double ax = double(s.a.X), ay = double(s.a.Y);
    const double dx = double(s.b.X) - ax, dy = double(s.b.Y) - ay;
    const double len2 = dx * dx + dy * dy;
    double t = len2 > 0 ? ((p.x - ax) * dx + (p.y - ay) * dy) / len2 : 0;
    t = std::clamp(t, 0.0, 1.0);
    return std::hypot(p.x - (ax + t * dx), p.y - (ay + t * dy));
}

// The interval of t in [0, 1] where a + t (b - a) lies nearer than `radius` to `s`, if any.
bool near_interval(const Segment& seg, const Segment& s, double radius, double& lo, double& hi) {
    auto at = [&](double t) {
        return DPoint{double(seg.a.X) + t * double(seg.b.X - seg.a.X),
                      double(seg.a.Y) + t * double(seg.b.Y - seg.a.Y)};
    };
    auto f = [&](double t) { return point_segment(at(t), s); };
    double l = 0, h = 1;
    for (int i = 0; i < 60 && h - l > 1e-7; ++i) {
        const double m1 = l + (h - l) / 3, m2 = h - (h - l) / 3;
        if (f(m1) < f(m2))
            h = m2;
        else
            l = m1;
    }
    const double best = (l + h) / 2;
    if (f(best) >= radius) return false;
    auto edge = [&](double inside, double outside) {
        if (f(outside) < radius) return outside;
        for (int i = 0; i < 50 && std::abs(outside - inside) > 1e-7; ++i) {
            const double m = (inside + outside) / 2;
            (f(m) < radius ? inside : outside) = m;
        }
        return inside;
    };
    lo = edge(best, 0.0);
    hi = edge(best, 1.0);
    return true;
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

}  // namespace carve

// Restriction of cavity boundary loops to the restriction shape W, with extensions (report 4.3).
//
// Clipper clips the loops (as open polylines) against W; each resulting piece is then mapped
// back to an arc-length interval of the loop it came from. Working on intervals makes the rest
// simple and exact: the piece that Clipper splits at the loop's start point is merged again,
// the 1 mm extension is just a wider interval, and overlapping extensions merge.
#include "toolpath/walls.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "geometry/polygon.hpp"

namespace carve {

namespace {

struct Interval {
    double start = 0, end = 0;  // arc length, start in [0, L), end may pass L (wraps)
};

// Arc-length parametrisation of a set of closed loops, with a grid of their edges to find
// which loop (and where on it) a point of a clipped piece lies.
class LoopSet {
  public:
    explicit LoopSet(const Paths& loops) : loops_(loops) {
        size_t edges = 0;
        BBox2 box = bounds(loops);
        cum_.resize(loops.size());
        for (size_t i = 0; i < loops.size(); ++i) {
            const Path& l = loops[i];
            cum_[i].resize(l.size() + 1, 0.0);
            for (size_t e = 0; e < l.size(); ++e)
                cum_[i][e + 1] = cum_[i][e] + dist(l[e], l[(e + 1) % l.size()]);
            edges += l.size();
        }
        const double w = double(box.max_x - box.min_x) + 1, h = double(box.max_y - box.min_y) + 1;
        cell_ = std::max(50.0, std::sqrt(w * h / double(std::max<size_t>(edges, 1))) * 2.0);
        for (size_t i = 0; i < loops.size(); ++i) {
            const Path& l = loops[i];
            for (size_t e = 0; e < l.size(); ++e) {
                const Point& a = l[e];
                const Point& b = l[(e + 1) % l.size()];
                // Cells of samples no farther apart than half a cell: a query looking at the
                // 3 x 3 block around a point near the edge finds it.
                const int steps = 1 + static_cast<int>(dist(a, b) / (0.5 * cell_));
                long long last = std::numeric_limits<long long>::min();
                for (int k = 0; k <= steps; ++k) {
                    const double f = double(k) / steps;
                    const long long key = cell_key(double(a.X) + f * double(b.X - a.X),
                                                   double(a.Y) + f * double(b.Y - a.Y));
                    if (key == last) continue;
                    last = key;
                    auto& bucket = grid_[key];
                    if (bucket.empty() || bucket.back() != Ref{int(i), int(e)})
                        bucket.push_back({int(i), int(e)});
                }
            }
        }
    }

    double loop_length(int loop) const { return cum_[loop].back(); }

    // Loop and arc-length position of the boundary point nearest p.
    std::pair<int, double> locate(const Point& p) const {
        const long long cx = cell_index(double(p.X)), cy = cell_index(double(p.Y));
        double best = std::numeric_limits<double>::max();
        std::pair<int, double> found{-1, 0.0};
        for (long long dx = -1; dx <= 1; ++dx)
            for (long long dy = -1; dy <= 1; ++dy) {
                auto it = grid_.find(pack(cx + dx, cy + dy));
                if (it == grid_.end()) continue;
                for (const Ref& r : it->second) consider(r, p, best, found);
            }
        if (found.first < 0 || best > 25.0 * 25.0) {  // not expected: scan everything
            for (size_t i = 0; i < loops_.size(); ++i)
                for (size_t e = 0; e < loops_[i].size(); ++e)
                    consider({int(i), int(e)}, p, best, found);
        }
        return found;
    }

    // The polyline of `loop` between arc lengths a and b (b - a <= L, b may pass L).
    Path extract(int loop, double a, double b) const {
        const Path& l = loops_[loop];
        const double len = loop_length(loop);
        const size_t m = l.size();
        Path out;
        auto add = [&](const Point& p) {
            if (out.empty() || out.back() != p) out.push_back(p);
        };
        add(point_at(loop, a));
        // Vertices with arc length in (a, b), walking round at most once.
        size_t e = edge_at(loop, std::fmod(a, len));
        double base = a - std::fmod(a, len);
        for (size_t k = 1; k <= m + 1; ++k) {
            size_t v = e + k;
            double pos = base + (v >= m ? len * double(v / m) : 0.0) + cum_[loop][v % m];
            if (pos >= b) break;
            if (pos > a) add(l[v % m]);
        }
        add(point_at(loop, b));
        return out;
    }

  private:
    struct Ref {
        int loop, edge;
        bool operator!=(const Ref& o) const { return loop != o.loop || edge != o.edge; }
    };

    static double dist(const Point& a, const Point& b) {
        return std::hypot(double(b.X - a.X), double(b.Y - a.Y));
    }
    long long cell_index(double x) const { return static_cast<long long>(std::floor(x / cell_)); }
    static long long pack(long long cx, long long cy) { return (cx << 32) ^ (cy & 0xffffffffLL); }
    long long cell_key(double x, double y) const { return pack(cell_index(x), cell_index(y)); }

    void consider(const Ref& r, const Point& p, double& best, std::pair<int, double>& found) const {
        const Path& l = loops_[r.loop];
        const Point& a = l[r.edge];
        const Point& b = l[(r.edge + 1) % l.size()];
        const double dx = double(b.X - a.X), dy = double(b.Y - a.Y);
        const double len2 = dx * dx + dy * dy;
        double t = 0;
        if (len2 > 0) t = std::clamp(((p.X - a.X) * dx + (p.Y - a.Y) * dy) / len2, 0.0, 1.0);
        const double qx = double(a.X) + t * dx - double(p.X),
                     qy = double(a.Y) + t * dy - double(p.Y);
        const double d2 = qx * qx + qy * qy;
        if (d2 < best) {
            best = d2;
            double s = cum_[r.loop][r.edge] + t * (cum_[r.loop][r.edge + 1] - cum_[r.loop][r.edge]);
            if (s >= loop_length(r.loop)) s = 0;
            found = {r.loop, s};
        }
    }

    size_t edge_at(int loop, double s) const {
        const auto& c = cum_[loop];
        size_t e = static_cast<size_t>(std::upper_bound(c.begin(), c.end(), s) - c.begin());
        e = e == 0 ? 0 : e - 1;
        return std::min(e, loops_[loop].size() - 1);
    }

    Point point_at(int loop, double s) const {
        const double len = loop_length(loop);
        s = std::fmod(s, len);
        if (s < 0) s += len;
        const size_t e = edge_at(loop, s);
        const Path& l = loops_[loop];
        const Point& a = l[e];
        const Point& b = l[(e + 1) % l.size()];
        const double el = cum_[loop][e + 1] - cum_[loop][e];
        const double t = el > 0 ? (s - cum_[loop][e]) / el : 0.0;
        return Point(static_cast<Coord>(std::llround(double(a.X) + t * double(b.X - a.X))),
                     static_cast<Coord>(std::llround(double(a.Y) + t * double(b.Y - a.Y))));
    }

    const Paths& loops_;
    std::vector<std::vector<double>> cum_;
    double cell_ = 1000;
    std::unordered_map<long long, std::vector<Ref>> grid_;
};

// The point at arc length `at` along an open polyline.
Point along(const Path& p, double at) {
    for (size_t i = 1; i < p.size(); ++i) {
        const double d = std::hypot(double(p[i].X - p[i - 1].X), double(p[i].Y - p[i - 1].Y));
        if (at <= d && d > 0) {
            const double t = at / d;
            return Point(static_cast<Coord>(std::llround(p[i - 1].X + t * (p[i].X - p[i - 1].X))),
                         static_cast<Coord>(std::llround(p[i - 1].Y + t * (p[i].Y - p[i - 1].Y))));
        }
        at -= d;
    }
    return p.back();
}

// Merges intervals on a circle of circumference len; returns {} plus full = true when they
// cover it all.
std::vector<Interval> merge_circular(std::vector<Interval> iv, double len, double tol, bool& full) {
    full = false;
    for (const Interval& i : iv)
        if (i.end - i.start >= len - tol) full = true;
    if (full || iv.empty()) return {};
    std::sort(iv.begin(), iv.end(),
              [](const Interval& a, const Interval& b) { return a.start < b.start; });
    std::vector<Interval> merged;
    for (const Interval& i : iv) {
        if (!merged.empty() && i.start <= merged.back().end + tol)
            merged.back().end = std::max(merged.back().end, i.end);
        else
            merged.push_back(i);
    }
    // The last one may run past L into the first ones.
    while (merged.size() > 1 && merged.back().end + tol >= merged.front().start + len) {
        merged.back().end = std::max(merged.back().end, merged.front().end + len);
        merged.erase(merged.begin());
    }
    for (const Interval& i : merged)
        if (i.end - i.start >= len - tol) full = true;
    if (full) return {};
    return merged;
}

}  // namespace

std::vector<WallPiece> restrict_loops(const Paths& loops, const Paths& region, double extension,
                                      double min_length) {
    std::vector<WallPiece> out;
    if (loops.empty() || region.empty()) return out;
    Paths open;
    open.reserve(loops.size());
    for (const Path& l : loops) {
        if (l.size() < 2) continue;
        Path p = l;
        p.push_back(l.front());
        open.push_back(std::move(p));
    }
    const Paths pieces = clip_lines(open, region);
    if (pieces.empty()) return out;

    LoopSet set(loops);
    const double tol = 5.0;
    std::vector<std::vector<Interval>> per_loop(loops.size());
    for (const Path& piece : pieces) {
        if (piece.size() < 2) continue;
        const double lp = length(Paths{piece}, false);
        if (lp < min_length) continue;
        const auto [la, a] = set.locate(piece.front());
        const auto [lb, b] = set.locate(piece.back());
        const auto [lm, m] = set.locate(along(piece, 0.5 * lp));
        if (la < 0 || la != lb || la != lm) continue;  // not on a single loop: degenerate
        const double len = set.loop_length(la);
        if (len < min_length) continue;  // a speck of a loop
        if (lp >= len - tol) {
            per_loop[la].push_back({0, len});
            continue;
        }
        double f = b - a;
        if (f < 0) f += len;
        double fm = m - a;
        if (fm < 0) fm += len;
        if (fm <= f)
            per_loop[la].push_back({a, a + f});
        else
            per_loop[la].push_back({b, b + (len - f)});
    }

    for (size_t li = 0; li < loops.size(); ++li) {
        if (per_loop[li].empty()) continue;
        const double len = set.loop_length(int(li));
        bool full = false;
        std::vector<Interval> merged = merge_circular(per_loop[li], len, tol, full);
        if (!full) {
            std::vector<Interval> kept;
            for (Interval i : merged) {
                if (i.end - i.start < min_length) continue;
                i.start -= extension;
                i.end += extension;
                if (i.start < 0) i.start += len, i.end += len;
                kept.push_back(i);
            }
            merged = merge_circular(kept, len, tol, full);
        }
        if (full) {
            out.push_back({loops[li], true});
            continue;
        }
        for (const Interval& i : merged) {
            Path p = set.extract(int(li), i.start, i.end);
            if (p.size() >= 2) out.push_back({std::move(p), false});
        }
    }
    return out;
}

}  // namespace carve

// Restriction of cavity boundary loops to the restriction shape W = V ⊖ t, with extensions
// (report 4.3).
//
// A point of a loop lies in W when it is inside V and no closer than t to V's boundary, so W
// is never built: each loop edge meets the t-neighbourhood of each boundary edge near it (a
// capsule, convex) in one interval of its arc length, found in closed form. The loops sit
// inside V; eroding V and clipping the loops to it took two Clipper passes per cavity and
// slice, and then every clipped piece had to be found again on its loop. Here the pieces are
// arc-length intervals from the start, which makes the rest simple and exact: a piece through
// the loop's start point is one interval, the 1 mm extension is a wider interval, and
// overlapping extensions merge. The disk is a true disk, where an erosion would use the
// 24-gon of the morphology (up to 0.9 % of t narrower).
#include "toolpath/walls.hpp"

#include <algorithm>
#include <cmath>

#include "geometry/polygon.hpp"

namespace carve {

namespace {

struct Interval {
    double start = 0, end = 0;  // arc length, start in [0, L), end may pass L (wraps)
};

// std::hypot guards against overflow that micrometre coordinates never reach, at several
// times the cost.
double dist(const Point& a, const Point& b) {
    const double dx = double(b.X - a.X), dy = double(b.Y - a.Y);
    return std::sqrt(dx * dx + dy * dy);
}

// Arc-length parametrisation of a set of closed loops.
class LoopArcs {
  public:
    explicit LoopArcs(const Paths& loops) : loops_(loops), cum_(loops.size()) {
        for (size_t i = 0; i < loops.size(); ++i) {
            const Path& l = loops[i];
            cum_[i].resize(l.size() + 1, 0.0);
            for (size_t e = 0; e < l.size(); ++e)
                cum_[i][e + 1] = cum_[i][e] + dist(l[e], l[(e + 1) % l.size()]);
        }
    }

    double loop_length(size_t loop) const { return cum_[loop].back(); }
    double at_vertex(size_t loop, size_t v) const { return cum_[loop][v]; }

    // The polyline of `loop` between arc lengths a and b (b - a <= L, b may pass L).
    Path extract(size_t loop, double a, double b) const {
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

    Point point_at(size_t loop, double s) const {
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

  private:
    size_t edge_at(size_t loop, double s) const {
        const auto& c = cum_[loop];
        size_t e = static_cast<size_t>(std::upper_bound(c.begin(), c.end(), s) - c.begin());
        e = e == 0 ? 0 : e - 1;
        return std::min(e, loops_[loop].size() - 1);
    }

    const Paths& loops_;
    std::vector<std::vector<double>> cum_;
};

// The boundary edges of a region in a uniform grid of cells, each edge listed in every cell its
// box grown by `reach` meets: the edges within `reach` of a point are in the point's cell.
class EdgeGrid {
  public:
    struct Edge {
        Point a, b;
        BBox2 reach;    // its box grown by the reach
        double ux, uy;  // unit direction (0, 0 if a == b)
        double length;
    };

    EdgeGrid(const Paths& region, Coord reach) {
        size_t n = 0;
        for (const Path& p : region) n += p.size();
        box_ = bounds(region);
        box_.min_x -= reach, box_.min_y -= reach, box_.max_x += reach, box_.max_y += reach;
        const double w = double(box_.max_x - box_.min_x) + 1,
                     h = double(box_.max_y - box_.min_y) + 1;
        // About one edge per cell, but no smaller than the reach: a query then reads 3 x 3
        // cells at most.
        cell_ =
            std::max({2.0 * double(reach), std::sqrt(w * h / double(std::max<size_t>(n, 1))), 1.0});
        nx_ = static_cast<long long>(w / cell_) + 1;
        ny_ = static_cast<long long>(h / cell_) + 1;
        edges_.reserve(n);
        for (const Path& p : region)
            for (size_t i = 0; i < p.size(); ++i) {
                const Point& a = p[i];
                const Point& b = p[(i + 1) % p.size()];
                const double l = dist(a, b);
                edges_.push_back({a,
                                  b,
                                  {std::min(a.X, b.X) - reach, std::min(a.Y, b.Y) - reach,
                                   std::max(a.X, b.X) + reach, std::max(a.Y, b.Y) + reach, false},
                                  l > 0 ? double(b.X - a.X) / l : 0,
                                  l > 0 ? double(b.Y - a.Y) / l : 0,
                                  l});
            }
        // Counting sort of (cell, edge) pairs into one array.
        start_.assign(size_t(nx_ * ny_) + 1, 0);
        for (int pass = 0; pass < 2; ++pass) {
            std::vector<size_t> next;
            if (pass == 1) {
                for (size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
                next.assign(start_.begin(), start_.end() - 1);
                members_.resize(start_.back());
            }
            for (size_t e = 0; e < edges_.size(); ++e) {
                const Edge& s = edges_[e];
                const auto [x0, x1] = span(s.reach.min_x, s.reach.max_x, box_.min_x, nx_);
                const auto [y0, y1] = span(s.reach.min_y, s.reach.max_y, box_.min_y, ny_);
                for (long long y = y0; y <= y1; ++y)
                    for (long long x = x0; x <= x1; ++x) {
                        const size_t c = size_t(y * nx_ + x);
                        if (pass == 0)
                            ++start_[c + 1];
                        else
                            members_[next[c]++] = e;
                    }
            }
        }
    }

    // Calls f(edge) for each edge whose grown box meets the box [x0, x1] x [y0, y1] (an edge
    // may come more than once).
    template <typename F>
    void near(Coord x0, Coord y0, Coord x1, Coord y1, F f) const {
        if (edges_.empty() || x1 < box_.min_x || x0 > box_.max_x || y1 < box_.min_y ||
            y0 > box_.max_y)
            return;
        const auto [cx0, cx1] = span(x0, x1, box_.min_x, nx_);
        const auto [cy0, cy1] = span(y0, y1, box_.min_y, ny_);
        for (long long y = cy0; y <= cy1; ++y)
            for (long long x = cx0; x <= cx1; ++x) {
                const size_t c = size_t(y * nx_ + x);
                for (size_t k = start_[c]; k < start_[c + 1]; ++k) {
                    const Edge& e = edges_[members_[k]];
                    if (e.reach.max_x >= x0 && e.reach.min_x <= x1 && e.reach.max_y >= y0 &&
                        e.reach.min_y <= y1)
                        f(e);
                }
            }
    }

  private:
    std::pair<long long, long long> span(Coord lo, Coord hi, Coord origin, long long n) const {
        auto cell = [&](Coord v) {
            return std::clamp(static_cast<long long>(std::floor(double(v - origin) / cell_)), 0LL,
                              n - 1);
        };
        return {cell(lo), cell(hi)};
    }

    BBox2 box_;
    double cell_ = 1;
    long long nx_ = 1, ny_ = 1;
    std::vector<Edge> edges_;
    std::vector<size_t> start_, members_;
};

// The parameters u in [0, len] where a + u d (d a unit vector) is closer than t to edge e:
// the line through a capsule, so one interval (empty if start >= end).
Interval within(double ax, double ay, double dx, double dy, double len, const EdgeGrid::Edge& e,
                double t) {
    double lo = len, hi = 0;  // empty
    auto take = [&](double u0, double u1) {
        u0 = std::max(u0, 0.0), u1 = std::min(u1, len);
        if (u0 < u1) lo = std::min(lo, u0), hi = std::max(hi, u1);
    };
    // The disks at both ends: |a + u d - c|^2 < t^2.
    for (const Point& c : {e.a, e.b}) {
        const double fx = ax - double(c.X), fy = ay - double(c.Y);
        const double b = dx * fx + dy * fy;
        const double disc = b * b - (fx * fx + fy * fy - t * t);
        if (disc > 0) {
            const double r = std::sqrt(disc);
            take(-b - r, -b + r);
        }
    }
    // The band: projection on the edge within it, distance to its line below t.
    if (e.length > 0) {
        double u0 = 0, u1 = len;
        // c0 + u c1 in (lo_c, hi_c)
        auto keep = [&](double c0, double c1, double lo_c, double hi_c) {
            if (c1 == 0) {
                if (!(c0 > lo_c && c0 < hi_c)) u1 = -1;
                return;
            }
            double v0 = (lo_c - c0) / c1, v1 = (hi_c - c0) / c1;
            if (v0 > v1) std::swap(v0, v1);
            u0 = std::max(u0, v0), u1 = std::min(u1, v1);
        };
        const double fx = ax - double(e.a.X), fy = ay - double(e.a.Y);
        keep(fx * e.ux + fy * e.uy, dx * e.ux + dy * e.uy, 0, e.length);
        keep(fx * -e.uy + fy * e.ux, dx * -e.uy + dy * e.ux, -t, t);
        take(u0, u1);
    }
    return {lo, hi};
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

// The parts of a loop of length len left by `removed` (intervals within [0, len]), as
// intervals that may pass len; full = true when nothing was removed.
std::vector<Interval> complement(std::vector<Interval> removed, double len, bool& full) {
    full = removed.empty();
    if (full) return {};
    std::sort(removed.begin(), removed.end(),
              [](const Interval& a, const Interval& b) { return a.start < b.start; });
    std::vector<Interval> kept;
    double at = removed.front().start;  // the gap before the first one wraps round to here
    double end = at;
    for (const Interval& r : removed) {
        if (r.start > end) kept.push_back({end, r.start});
        end = std::max(end, r.end);
    }
    if (end < at + len) kept.push_back({end, at + len});
    for (Interval& k : kept)
        if (k.start >= len) k.start -= len, k.end -= len;
    return kept;
}

}  // namespace

std::vector<WallPiece> loops_inside_erosion(const Paths& loops, const Paths& region, Coord depth,
                                            double extension, double min_length) {
    std::vector<WallPiece> out;
    if (loops.empty() || region.empty()) return out;
    const EdgeGrid grid(region, depth);
    const LoopArcs arcs(loops);
    const double t = double(depth), tol = 5.0;
    std::vector<Interval> removed, kept;
    for (size_t li = 0; li < loops.size(); ++li) {
        const Path& l = loops[li];
        const double len = l.size() < 2 ? 0 : arcs.loop_length(li);
        if (len < min_length || len <= 0) continue;  // a speck of a loop
        removed.clear();
        for (size_t i = 0; i < l.size(); ++i) {
            const Point& a = l[i];
            const Point& b = l[(i + 1) % l.size()];
            const double el = dist(a, b);
            if (el <= 0) continue;
            const double s0 = arcs.at_vertex(li, i);
            const double dx = double(b.X - a.X) / el, dy = double(b.Y - a.Y) / el;
            grid.near(std::min(a.X, b.X), std::min(a.Y, b.Y), std::max(a.X, b.X),
                      std::max(a.Y, b.Y), [&](const EdgeGrid::Edge& e) {
                          const Interval u = within(double(a.X), double(a.Y), dx, dy, el, e, t);
                          if (u.start < u.end) removed.push_back({s0 + u.start, s0 + u.end});
                      });
        }
        // Gaps closer than tol are rounding; then what is left is at least t from the
        // boundary, so wholly inside or outside the region.
        bool full = false;
        kept = complement(removed, len, full);
        if (!full) kept = merge_circular(kept, len, tol, full);
        if (full) {
            if (point_in_region(l.front(), region)) out.push_back({l, true});
            continue;
        }
        std::vector<Interval> pieces;
        for (Interval k : kept) {
            if (k.end - k.start < min_length) continue;
            if (!point_in_region(arcs.point_at(li, (k.start + k.end) / 2), region)) continue;
            k.start -= extension;
            k.end += extension;
            if (k.start < 0) k.start += len, k.end += len;
            pieces.push_back(k);
        }
        const std::vector<Interval> merged = merge_circular(pieces, len, tol, full);
        if (full) {
            out.push_back({l, true});
            continue;
        }
        for (const Interval& k : merged) {
            Path p = arcs.extract(li, k.start, k.end);
            if (p.size() >= 2) out.push_back({std::move(p), false});
        }
    }
    return out;
}

}  // namespace carve

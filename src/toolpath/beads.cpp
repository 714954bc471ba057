// Beads along a medial axis: see beads.hpp.
#include "toolpath/beads.hpp"

#include <algorithm>
#include <cmath>

namespace carve {

namespace {

void add_sample(Path& path, const Point& p) {
    if (path.empty() || path.back() != p) path.push_back(p);
}

uint64_t cell_key(Coord x, Coord y) {
    return (uint64_t(uint32_t(int32_t(x))) << 32) | uint32_t(int32_t(y));
}

double edge_distance(const Point& p, const std::pair<Point, Point>& s) {
    const double ax = double(s.first.X), ay = double(s.first.Y);
    const double dx = double(s.second.X) - ax, dy = double(s.second.Y) - ay;
    const double px = double(p.X) - ax, py = double(p.Y) - ay;
    const double l2 = dx * dx + dy * dy;
    const double t = l2 > 0 ? std::clamp((px * dx + py * dy) / l2, 0.0, 1.0) : 0.0;
    return std::hypot(px - t * dx, py - t * dy);
}

}  // namespace

EdgeDistance::EdgeDistance(const Paths& region, Coord cap)
    : cap_(double(cap)), cell_(std::max<Coord>(cap, 1)) {
    for (const Path& c : region)
        for (size_t i = 0; i < c.size(); ++i) {
            const Point& a = c[i];
            const Point& b = c[(i + 1) % c.size()];
            const int e = static_cast<int>(edges_.size());
            edges_.push_back({a, b});
            for (Coord x = cell_of(std::min(a.X, b.X)); x <= cell_of(std::max(a.X, b.X)); ++x)
                for (Coord y = cell_of(std::min(a.Y, b.Y)); y <= cell_of(std::max(a.Y, b.Y)); ++y)
                    grid_[cell_key(x, y)].push_back(e);
        }
}

double EdgeDistance::operator()(const Point& p) const {
    double best = cap_;
    const Coord cx = cell_of(p.X), cy = cell_of(p.Y);
    for (Coord x = cx - 1; x <= cx + 1; ++x)
        for (Coord y = cy - 1; y <= cy + 1; ++y) {
            const auto it = grid_.find(cell_key(x, y));
            if (it == grid_.end()) continue;
            for (int e : it->second) best = std::min(best, edge_distance(p, edges_[e]));
        }
    return best;
}

Path extended_axis(const Path& axis, const std::function<bool(const Point&, const Point&)>& keep,
                   double stride, double back) {
    Path out = axis;
    if (axis.size() < 2 || axis.front() == axis.back()) return out;
    auto extend = [&](Path& p) {  // extends p at its end
        const Point e = p.back();
        Point from = e;
        for (size_t i = p.size() - 1; i-- > 0;) {
            from = p[i];
            if (std::hypot(double(e.X - from.X), double(e.Y - from.Y)) >= back) break;
        }
        const double dx = double(e.X - from.X), dy = double(e.Y - from.Y);
        const double len = std::hypot(dx, dy);
        if (len <= 0) return;
        const double ux = dx / len, uy = dy / len;
        Point last = e;
        for (int k = 1; k <= 64; ++k) {
            const Point q(e.X + static_cast<Coord>(std::llround(ux * stride * k)),
                          e.Y + static_cast<Coord>(std::llround(uy * stride * k)));
            if (!keep(e, q)) break;
            last = q;
        }
        if (last != e) p.push_back(last);
    };
    extend(out);
    std::reverse(out.begin(), out.end());
    extend(out);
    std::reverse(out.begin(), out.end());
    return out;
}

std::vector<Bead> axis_beads(const Path& axis, const std::function<double(const Point&)>& width_at,
                             double step, double tolerance, double min_width) {
    std::vector<Bead> out;
    if (axis.size() < 2) return out;
    Path pts{axis.front()};
    for (size_t i = 1; i < axis.size(); ++i) {
        const Point& a = axis[i - 1];
        const Point& b = axis[i];
        const double len = std::hypot(double(b.X - a.X), double(b.Y - a.Y));
        const int parts = std::max(1, static_cast<int>(std::ceil(len / step)));
        for (int k = 1; k <= parts; ++k) {
            const double t = double(k) / parts;
            add_sample(pts, Point(a.X + static_cast<Coord>(std::llround(t * double(b.X - a.X))),
                                  a.Y + static_cast<Coord>(std::llround(t * double(b.Y - a.Y)))));
        }
    }
    std::vector<double> width(pts.size());
    for (size_t i = 0; i < pts.size(); ++i) width[i] = width_at(pts[i]);
    Path run;
    double ref = 0, sum = 0, sum_len = 0;
    auto flush = [&] {
        if (run.size() >= 2 && sum_len > 0) out.push_back({std::move(run), sum / sum_len});
        run.clear();
        sum = sum_len = 0;
    };
    for (size_t i = 0; i + 1 < pts.size(); ++i) {
        const double ws = 0.5 * (width[i] + width[i + 1]);
        if (std::max(width[i], width[i + 1]) < min_width) {
            flush();
            continue;
        }
        if (!run.empty() && std::abs(ws - ref) > tolerance) flush();
        if (run.empty()) {
            run.push_back(pts[i]);
            ref = ws;
        }
        run.push_back(pts[i + 1]);
        const double len =
            std::hypot(double(pts[i + 1].X - pts[i].X), double(pts[i + 1].Y - pts[i].Y));
        sum += ws * len;
        sum_len += len;
    }
    flush();
    return out;
}

}  // namespace carve

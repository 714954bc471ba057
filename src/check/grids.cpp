// Grids over a region's boundary (see grids.hpp).
#include "check/grids.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numbers>

#include "geometry/simplify.hpp"

namespace carve::check {

CellFrame::CellFrame(const Paths& region, double cell_units) : cell(cell_units) {
    double max_x = std::numeric_limits<double>::lowest(), max_y = max_x;
    min_x = min_y = std::numeric_limits<double>::max();
    bool any = false;
    for (const Path& p : region) {
        for (const Point& q : p) {
            min_x = std::min(min_x, double(q.X));
            min_y = std::min(min_y, double(q.Y));
            max_x = std::max(max_x, double(q.X));
            max_y = std::max(max_y, double(q.Y));
            any = true;
        }
    }
    if (!any) return;
    nx = static_cast<long>((max_x - min_x) / cell) + 1;
    ny = static_cast<long>((max_y - min_y) / cell) + 1;
}

long CellFrame::column(double x) const {
    return std::clamp(static_cast<long>((x - min_x) / cell), 0L, std::max(0L, nx - 1));
}

long CellFrame::row(double y) const {
    return std::clamp(static_cast<long>((y - min_y) / cell), 0L, std::max(0L, ny - 1));
}

NearMap::NearMap(const Paths& region, double cell_units) : frame_(region, cell_units) {
    if (frame_.empty()) return;
    marked_.assign(static_cast<size_t>(frame_.nx * frame_.ny), 0);
    // Points every half cell along each edge: each marks a cell that truly holds boundary.
    for (const Path& p : region) {
        for (size_t i = 0; i < p.size(); ++i) {
            const Point& a = p[i];
            const Point& b = p[(i + 1) % p.size()];
            const double dx = double(b.X - a.X), dy = double(b.Y - a.Y);
            const int n =
                std::max(1, static_cast<int>(std::ceil(2 * std::hypot(dx, dy) / frame_.cell)));
            for (int k = 0; k <= n; ++k)
                marked_[frame_.index(frame_.column(a.X + dx * k / n),
                                     frame_.row(a.Y + dy * k / n))] = 1;
        }
    }
}

bool NearMap::within(double x, double y, double radius) const {
    if (marked_.empty()) return false;
    const double cell = frame_.cell;
    const long rings = static_cast<long>(std::floor(radius / (cell * std::numbers::sqrt2))) - 1;
    const long cx = static_cast<long>(std::floor((x - frame_.min_x) / cell));
    const long cy = static_cast<long>(std::floor((y - frame_.min_y) / cell));
    for (long ring = 0; ring <= rings; ++ring) {
        for (long j = cy - ring; j <= cy + ring; ++j) {
            if (j < 0 || j >= frame_.ny) continue;
            const bool edge_row = j == cy - ring || j == cy + ring;
            for (long i = cx - ring; i <= cx + ring; i += edge_row ? 1 : 2 * ring) {
                if (i >= 0 && i < frame_.nx && marked_[frame_.index(i, j)]) return true;
                if (ring == 0) break;
            }
        }
    }
    return false;
}

EdgeGrid::EdgeGrid(const Paths& region, double cell_units) : frame_(region, cell_units) {
    for (const Path& p : region)
        for (size_t i = 0; i < p.size(); ++i) edges_.push_back({p[i], p[(i + 1) % p.size()]});
    if (edges_.empty()) return;
    cells_.assign(static_cast<size_t>(frame_.nx * frame_.ny), {});
    for (size_t k = 0; k < edges_.size(); ++k) {
        const auto [a, b] = edges_[k];
        const long x0 = frame_.column(double(std::min(a.X, b.X)));
        const long x1 = frame_.column(double(std::max(a.X, b.X)));
        const long y0 = frame_.row(double(std::min(a.Y, b.Y)));
        const long y1 = frame_.row(double(std::max(a.Y, b.Y)));
        for (long y = y0; y <= y1; ++y)
            for (long x = x0; x <= x1; ++x) cells_[frame_.index(x, y)].push_back(k);
    }
}

double EdgeGrid::distance(const Point& p) const {
    if (edges_.empty()) return std::numeric_limits<double>::infinity();
    const long px = frame_.column(double(p.X)), py = frame_.row(double(p.Y));
    double best = std::numeric_limits<double>::infinity();
    for (long ring = 0;; ++ring) {
        for (long y = py - ring; y <= py + ring; ++y) {
            for (long x = px - ring; x <= px + ring; ++x) {
                if (std::max(std::labs(x - px), std::labs(y - py)) != ring) continue;
                if (x < 0 || y < 0 || x >= frame_.nx || y >= frame_.ny) continue;
                for (size_t k : cells_[frame_.index(x, y)])
                    best = std::min(best, segment_distance(p, edges_[k].first, edges_[k].second));
            }
        }
        // Every edge not yet seen lies at least `ring` whole cells away.
        if (best <= ring * frame_.cell) break;
        if (ring > frame_.nx + frame_.ny + 2) break;
    }
    return best;
}

}  // namespace carve::check

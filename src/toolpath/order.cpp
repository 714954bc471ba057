// Greedy nearest-neighbour ordering with a uniform grid of entry points.
//
// Every query searches rings of cells around the nozzle until no unvisited entry point can be
// nearer than the best one found; a chosen path's entry points are removed from their cells,
// so the cost per layer stays close to linear in the number of points.
#include "toolpath/order.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace carve {

namespace {

struct Entry {
    Point p;
    int path;
    int vertex;
};

double dist2(const Point& a, const Point& b) {
    const double dx = double(a.X - b.X), dy = double(a.Y - b.Y);
    return dx * dx + dy * dy;
}

class EntryGrid {
  public:
    explicit EntryGrid(std::vector<Entry> entries) : remaining_(entries.size()) {
        Coord x0 = std::numeric_limits<Coord>::max(), y0 = x0;
        Coord x1 = std::numeric_limits<Coord>::lowest(), y1 = x1;
        for (const Entry& e : entries) {
            x0 = std::min(x0, e.p.X), y0 = std::min(y0, e.p.Y);
            x1 = std::max(x1, e.p.X), y1 = std::max(y1, e.p.Y);
        }
        x0_ = x0, y0_ = y0;
        const double w = double(x1 - x0) + 1, h = double(y1 - y0) + 1;
        // About four points per cell.
        cell_ =
            std::max(100.0, std::sqrt(w * h * 4.0 / double(std::max<size_t>(entries.size(), 1))));
        nx_ = static_cast<int>(w / cell_) + 1;
        ny_ = static_cast<int>(h / cell_) + 1;
        cells_.resize(size_t(nx_) * size_t(ny_));
        for (const Entry& e : entries) cells_[index(cx(e.p.X), cy(e.p.Y))].push_back(e);
    }

    bool empty() const { return remaining_ == 0; }

    // The nearest remaining entry point to p.
    Entry nearest(const Point& p) const {
        const int px = cx(p.X), py = cy(p.Y);
        // Distance from p to its (clamped) centre cell: rings beyond are bounded from there.
        const double cell_x0 = x0_ + px * cell_, cell_y0 = y0_ + py * cell_;
        const double ox = std::max({0.0, cell_x0 - double(p.X), double(p.X) - (cell_x0 + cell_)});
        const double oy = std::max({0.0, cell_y0 - double(p.Y), double(p.Y) - (cell_y0 + cell_)});
        const double outside = std::hypot(ox, oy);
        double best = std::numeric_limits<double>::max();
        Entry found{};
        const int max_ring = std::max(nx_, ny_);
        for (int r = 0; r <= max_ring; ++r) {
            const double bound = (r - 1) * cell_ - outside;
            if (bound > 0 && bound * bound > best) break;
            for (int x = px - r; x <= px + r; ++x) {
                if (x < 0 || x >= nx_) continue;
                const bool edge_col = (x == px - r || x == px + r);
                for (int y = py - r; y <= py + r; y += (edge_col || r == 0) ? 1 : 2 * r) {
                    if (y < 0 || y >= ny_) continue;
                    for (const Entry& e : cells_[index(x, y)]) {
                        const double d = dist2(e.p, p);
                        if (d < best) best = d, found = e;
                    }
                }
            }
        }
        return found;
    }

    void remove_path(const std::vector<Entry>& entries) {
        for (const Entry& e : entries) {
            auto& cell = cells_[index(cx(e.p.X), cy(e.p.Y))];
            for (size_t i = 0; i < cell.size(); ++i)
                if (cell[i].path == e.path && cell[i].vertex == e.vertex) {
                    cell[i] = cell.back();
                    cell.pop_back();
                    --remaining_;
                    break;
                }
        }
    }

  private:
    int cx(Coord x) const {
        return std::clamp(static_cast<int>(std::floor((double(x) - double(x0_)) / cell_)), 0,
                          nx_ - 1);
    }
    int cy(Coord y) const {
        return std::clamp(static_cast<int>(std::floor((double(y) - double(y0_)) / cell_)), 0,
                          ny_ - 1);
    }
    size_t index(int x, int y) const { return size_t(y) * size_t(nx_) + size_t(x); }

    Coord x0_ = 0, y0_ = 0;
    double cell_ = 1000;
    int nx_ = 1, ny_ = 1;
    std::vector<std::vector<Entry>> cells_;
    size_t remaining_ = 0;
};

}  // namespace

void order_nearest(std::vector<Extrusion>& paths, Point& pos, bool keep_loop_starts) {
    if (paths.empty()) return;
    std::vector<std::vector<Entry>> entries(paths.size());
    std::vector<Entry> all;
    for (size_t i = 0; i < paths.size(); ++i) {
        const Path& p = paths[i].points;
        if (p.empty()) continue;
        if (paths[i].closed) {
            for (size_t v = 0; v < (keep_loop_starts ? 1 : p.size()); ++v)
                entries[i].push_back({p[v], int(i), int(v)});
        } else {
            entries[i].push_back({p.front(), int(i), 0});
            if (p.size() > 1) entries[i].push_back({p.back(), int(i), int(p.size() - 1)});
        }
        all.insert(all.end(), entries[i].begin(), entries[i].end());
    }
    EntryGrid grid(std::move(all));
    std::vector<Extrusion> ordered;
    ordered.reserve(paths.size());
    while (!grid.empty()) {
        const Entry e = grid.nearest(pos);
        grid.remove_path(entries[e.path]);
        Extrusion ex = std::move(paths[e.path]);
        if (ex.closed) {
            std::rotate(ex.points.begin(), ex.points.begin() + e.vertex, ex.points.end());
            pos = ex.points.front();
        } else {
            if (e.vertex != 0) std::reverse(ex.points.begin(), ex.points.end());
            pos = ex.points.back();
        }
        ordered.push_back(std::move(ex));
    }
    paths = std::move(ordered);
}

void improve_order(std::vector<Extrusion>& paths, const Point& start, Point& pos,
                   bool keep_loop_starts) {
    const size_t n = paths.size();
    if (n == 0) return;
    auto entry = [&](size_t k) { return paths[k].points.front(); };
    auto exit = [&](size_t k) {
        return paths[k].closed ? paths[k].points.front() : paths[k].points.back();
    };
    auto d = [](const Point& a, const Point& b) { return std::sqrt(dist2(a, b)); };
    // Reversing paths[i..j] changes only the travel into i and out of j: the travel between
    // two reversed neighbours is the same segment the other way round.
    constexpr size_t kWindow = 24;
    for (int pass = 0; pass < 2 && n >= 2; ++pass) {
        bool improved = false;
        for (size_t i = 0; i + 1 < n; ++i) {
            for (size_t j = i + 1; j < n && j < i + kWindow; ++j) {
                const Point before = i == 0 ? start : exit(i - 1);
                const bool tail = j + 1 < n;
                const double now = d(before, entry(i)) + (tail ? d(exit(j), entry(j + 1)) : 0);
                const double then = d(before, exit(j)) + (tail ? d(entry(i), entry(j + 1)) : 0);
                if (then < now - 1.0) {  // a micrometre: no endless swaps of equals
                    std::reverse(paths.begin() + static_cast<std::ptrdiff_t>(i),
                                 paths.begin() + static_cast<std::ptrdiff_t>(j) + 1);
                    for (size_t k = i; k <= j; ++k)
                        if (!paths[k].closed)
                            std::reverse(paths[k].points.begin(), paths[k].points.end());
                    improved = true;
                }
            }
        }
        if (!improved) break;
    }
    // Each loop starts at the vertex that makes the travel into it and out of it (to the next
    // path's start as it stands) shortest: with a loop ending where it starts, the nearest
    // vertex to the nozzle alone could lengthen the travel after it.
    Point at = start;
    for (size_t k = 0; k < n; ++k) {
        Extrusion& e = paths[k];
        if (e.closed && !keep_loop_starts && e.points.size() > 1) {
            auto cost = [&](const Point& v) {
                return d(at, v) + (k + 1 < n ? d(v, paths[k + 1].points.front()) : 0.0);
            };
            size_t best = 0;
            double best_cost = cost(e.points[0]);
            for (size_t v = 1; v < e.points.size(); ++v)
                if (const double c = cost(e.points[v]); c < best_cost) best_cost = c, best = v;
            std::rotate(e.points.begin(), e.points.begin() + static_cast<std::ptrdiff_t>(best),
                        e.points.end());
        }
        at = e.closed ? e.points.front() : e.points.back();
    }
    pos = at;
}

}  // namespace carve

// The voxel grid of carve check --strength (see voxels.hpp).
#include "check/voxels.hpp"

#include <algorithm>
#include <cmath>

namespace carve::check {

namespace {

// Rows sampled across a voxel column: the footprint's area is measured exactly along x and
// sampled along y at this spacing at most (a 0.45 mm bead is crossed by 7 rows).
constexpr double kRowMm = 0.0625;
constexpr int kMinRows = 8;
// Voxel columns across one layer's footprint, at most: a wider layer coarsens the grid first,
// so that one layer's raster stays within 1024 x 1024 columns (8 MB) whatever the file holds.
constexpr double kMaxColumns = 1024;

long floor_div(long a, long b) {
    return a >= 0 ? a / b : -((-a + b - 1) / b);
}

}  // namespace

VoxelGrid::VoxelGrid(double cell_mm, size_t max_cells) : cell_(cell_mm), max_cells_(max_cells) {}

VoxelGrid::Columns VoxelGrid::rasterise(const Paths& footprint) const {
    const double a = cell_;
    const int rows_per_cell = std::max(kMinRows, static_cast<int>(std::ceil(a / kRowMm)));
    const double dy = a / rows_per_cell;
    Columns c;
    double min_x = 1e300, min_y = 1e300, max_x = -1e300, max_y = -1e300;
    for (const Path& p : footprint)
        for (const Point& q : p) {
            min_x = std::min(min_x, to_mm(q.X)), max_x = std::max(max_x, to_mm(q.X));
            min_y = std::min(min_y, to_mm(q.Y)), max_y = std::max(max_y, to_mm(q.Y));
        }
    if (min_x > max_x) return c;
    c.i0 = static_cast<long>(std::floor(min_x / a));
    c.j0 = static_cast<long>(std::floor(min_y / a));
    c.nx = static_cast<long>(std::floor(max_x / a)) - c.i0 + 1;
    c.ny = static_cast<long>(std::floor(max_y / a)) - c.j0 + 1;
    c.area.assign(static_cast<size_t>(c.nx * c.ny), 0.0);
    // Where each edge crosses the rows (at y = (r + 1/2) dy), with its winding: the footprint
    // is the non-zero region, as Clipper's union leaves it.
    struct Crossing {
        long row;
        double x;
        int winding;
        bool operator<(const Crossing& o) const { return row != o.row ? row < o.row : x < o.x; }
    };
    std::vector<Crossing> crossings;
    for (const Path& p : footprint) {
        for (size_t n = 0; n < p.size(); ++n) {
            const Point& s = p[n];
            const Point& e = p[(n + 1) % p.size()];
            if (s.Y == e.Y) continue;
            const double x1 = to_mm(s.X), y1 = to_mm(s.Y);
            const double x2 = to_mm(e.X), y2 = to_mm(e.Y);
            const double lo = std::min(y1, y2), hi = std::max(y1, y2);
            const long r0 = static_cast<long>(std::ceil(lo / dy - 0.5));
            const long r1 = static_cast<long>(std::ceil(hi / dy - 0.5)) - 1;
            for (long r = r0; r <= r1; ++r) {
                const double y = (static_cast<double>(r) + 0.5) * dy;
                crossings.push_back({r, x1 + (y - y1) * (x2 - x1) / (y2 - y1), y2 > y1 ? 1 : -1});
            }
        }
    }
    std::sort(crossings.begin(), crossings.end());
    auto add_span = [&](long row, double xa, double xb) {
        const long j = floor_div(row, rows_per_cell) - c.j0;
        if (j < 0 || j >= c.ny) return;
        long i = std::clamp(static_cast<long>(std::floor(xa / a)) - c.i0, 0L, c.nx - 1);
        for (double x = xa; x < xb && i < c.nx; ++i) {
            const double end = std::min(xb, static_cast<double>(c.i0 + i + 1) * a);
            c.area[static_cast<size_t>(j * c.nx + i)] += (end - x) * dy;
            x = end;
        }
    };
    int winding = 0;
    for (size_t n = 0; n < crossings.size(); ++n) {
        if (n > 0 && crossings[n].row != crossings[n - 1].row) winding = 0;
        if (winding != 0) add_span(crossings[n].row, crossings[n - 1].x, crossings[n].x);
        winding += crossings[n].winding;
    }
    return c;
}

void VoxelGrid::add_layer(const Paths& footprint, double z_top_mm, double height_mm) {
    if (footprint.empty() || !(height_mm > 0)) return;
    Coord lo_x = footprint[0].empty() ? 0 : footprint[0][0].X, hi_x = lo_x;
    Coord lo_y = footprint[0].empty() ? 0 : footprint[0][0].Y, hi_y = lo_y;
    for (const Path& p : footprint)
        for (const Point& q : p) {
            lo_x = std::min(lo_x, q.X), hi_x = std::max(hi_x, q.X);
            lo_y = std::min(lo_y, q.Y), hi_y = std::max(hi_y, q.Y);
        }
    const double extent = to_mm(std::max(hi_x - lo_x, hi_y - lo_y));
    while (extent / cell_ > kMaxColumns) coarsen();
    const Columns c = rasterise(footprint);
    const double a = cell_;
    const double z0 = z_top_mm - height_mm;
    const int k0 = static_cast<int>(std::floor(z0 / a));
    const int k1 = static_cast<int>(std::floor(z_top_mm / a - 1e-9));
    for (int k = k0; k <= k1; ++k) {
        const double share = std::min(z_top_mm, (k + 1) * a) - std::max(z0, k * a);
        if (share <= 0) continue;
        for (long j = 0; j < c.ny; ++j)
            for (long i = 0; i < c.nx; ++i) {
                const double area = c.area[static_cast<size_t>(j * c.nx + i)];
                if (area <= 0) continue;
                volume_[{static_cast<int>(c.i0 + i), static_cast<int>(c.j0 + j), k}] +=
                    area * share;
            }
    }
    while (volume_.size() > max_cells_) coarsen();
}

void VoxelGrid::coarsen() {
    std::unordered_map<Key, double, KeyHash> coarse;
    coarse.reserve(volume_.size() / 4 + 1);
    for (const auto& [key, v] : volume_)
        coarse[{static_cast<int>(floor_div(key.i, 2)), static_cast<int>(floor_div(key.j, 2)),
                static_cast<int>(floor_div(key.k, 2))}] += v;
    volume_ = std::move(coarse);
    cell_ *= 2;
    ++coarsenings_;
}

std::vector<Voxel> VoxelGrid::voxels() const {
    std::vector<Voxel> out;
    out.reserve(volume_.size());
    const double cell_volume = cell_ * cell_ * cell_;
    for (const auto& [key, v] : volume_)
        out.push_back({key.i, key.j, key.k, std::min(1.0, v / cell_volume)});
    // In a fixed order, so that the solver's sums (and the figures) do not depend on hashing.
    std::sort(out.begin(), out.end(), [](const Voxel& p, const Voxel& q) {
        return p.k != q.k ? p.k < q.k : p.j != q.j ? p.j < q.j : p.i < q.i;
    });
    return out;
}

}  // namespace carve::check

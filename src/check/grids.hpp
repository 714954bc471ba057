// Uniform grids over a region's boundary, for carve check's distance questions: NearMap proves
// cheaply that a point lies near the boundary, EdgeGrid measures the distance exactly. Both
// stand on one CellFrame, the grid's placement over the region's bounding box.
#pragma once

#include <vector>

#include "geometry/types.hpp"

namespace carve::check {

struct CellFrame {
    double cell = 1;              // units
    double min_x = 0, min_y = 0;  // units, the region's lowest corner
    long nx = 0, ny = 0;          // 0 for an empty region

    CellFrame(const Paths& region, double cell_units);
    bool empty() const { return nx == 0; }
    long column(double x) const;  // clamped to the grid
    long row(double y) const;
    size_t index(long column, long row) const { return static_cast<size_t>(row * nx + column); }
};

// Cells of a coarse grid that hold a point of a region's boundary: a cheap, conservative proof
// that a point lies within some distance of the region.
class NearMap {
  public:
    NearMap(const Paths& region, double cell_units);
    // True only if (x, y) is proven within `radius` of the region's boundary.
    bool within(double x, double y, double radius) const;

  private:
    CellFrame frame_;
    std::vector<unsigned char> marked_;
};

// The region's edges binned by cell, for distances from many points to its boundary.
class EdgeGrid {
  public:
    explicit EdgeGrid(const Paths& region, double cell_units = 1000.0);
    // Distance in units from p to the nearest edge; infinity if the region is empty.
    double distance(const Point& p) const;

  private:
    CellFrame frame_;
    std::vector<std::pair<Point, Point>> edges_;
    std::vector<std::vector<size_t>> cells_;
};

}  // namespace carve::check

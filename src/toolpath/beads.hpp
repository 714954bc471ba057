// Beads along a medial axis (private to the toolpath stage): one line down the middle of a strip
// too narrow for two, as wide as the strip where it runs. The cover bands' thin strips
// (fill_thin) and the model's own thin walls (thin_walls.hpp) are printed this way.
#pragma once

#include <cstdint>
#include <functional>
#include <unordered_map>
#include <utility>
#include <vector>

#include "geometry/types.hpp"

namespace carve {

// Distance from a point to the nearest edge of a region, up to a cap, through a grid of the
// edges (a strip along a whole layer's outline has thousands of them).
class EdgeDistance {
  public:
    EdgeDistance(const Paths& region, Coord cap);
    double operator()(const Point& p) const;

  private:
    Coord cell_of(Coord v) const { return v >= 0 ? v / cell_ : -((-v + cell_ - 1) / cell_); }
    double cap_;
    Coord cell_;
    std::vector<std::pair<Point, Point>> edges_;
    std::unordered_map<uint64_t, std::vector<int>> grid_;
};

// The axis of a strip stops short of its ends (the pruned branches went to the corners there):
// each open end goes on straight, in the direction of its last `back` of axis, in steps of
// `stride` (at most 64), while keep(end, next point) holds. A closed axis is returned as it is.
Path extended_axis(const Path& axis, const std::function<bool(const Point&, const Point&)>& keep,
                   double stride, double back);

// A run of the axis printed as one extrusion, and its mean width.
struct Bead {
    Path points;
    double width = 0;
};

// The beads along one medial axis: sampled every `step`, the width at each sample width_at(it),
// cut where the width leaves the run's first by more than `tolerance` or falls under
// `min_width` at both ends of a step. A dip at one sample (a corner of the strip's outline)
// does not cut the line.
std::vector<Bead> axis_beads(const Path& axis, const std::function<double(const Point&)>& width_at,
                             double step, double tolerance, double min_width);

}  // namespace carve

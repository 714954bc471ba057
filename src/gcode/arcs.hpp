// Arc fitting: runs of a path's points that lie on one circle become a single G2/G3 move.
//
// carve's cavity walls are long smooth curves sampled every few tenths of a millimetre, so most
// of a file's lines are short G1 chords; printers and hosts that read G2/G3 (Marlin with
// ARC_SUPPORT, Prusa firmware, RepRapFirmware, Klipper with [gcode_arcs]) take fewer, shorter
// lines. A run becomes an arc only when every point of it and every chord between them stays
// within the tolerance of the arc, so the printed path moves by no more than that.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "geometry/types.hpp"

namespace carve {

struct Arc {
    size_t last = 0;        // index of the run's last point (the first is the caller's)
    double cx = 0, cy = 0;  // centre, units
    bool counter_clockwise = true;
    double length = 0;  // along the arc, units
};

// The longest arc from points[first] that passes within `tolerance` (units) of points
// first..last, with at least `min_points` points and a radius in [min_radius, max_radius];
// nothing when no such run exists.
std::optional<Arc> fit_arc(const std::vector<Point>& points, size_t first, double tolerance,
                           size_t min_points = 4, double min_radius = 500,
                           double max_radius = 1'000'000);

}  // namespace carve

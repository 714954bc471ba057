// Douglas-Peucker simplification of one contour or polyline: every dropped vertex lies within
// `tolerance` (units) of the result. The skeleton thins its Voronoi input with it (the builder's
// cost is per segment) and the HTML report its drawings. Regions that must stay valid polygons
// for booleans use simplify() of polygon.hpp instead, which only drops nearly straight points.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "geometry/types.hpp"

namespace carve {

// Distance from p to the segment [a, b].
double segment_distance(const Point& p, const Point& a, const Point& b);

// Buffers reused between calls, for callers that simplify many contours in a row.
struct SimplifyScratch {
    std::vector<std::pair<size_t, size_t>> stack;
    std::vector<uint8_t> keep;
};

// A closed contour (the loop back to its first vertex counts; contours of 3 vertices or fewer
// are kept whole) or an open polyline (both ends kept), written to `out`. The work is bounded
// by about n (32 + 4 log2 n) point-to-segment distances: where a pathological input (a
// zig-zag) would need more, the parts not yet examined are kept whole and the result is false.
bool douglas_peucker(const Path& path, bool closed, double tolerance, SimplifyScratch& scratch,
                     Path& out);
Path douglas_peucker(const Path& path, bool closed, double tolerance);

}  // namespace carve

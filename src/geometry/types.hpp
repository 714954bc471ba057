// Value types shared by every stage: integer points and polygons in micrometres.
//
// A slice is a set of closed contours, outer contours counter-clockwise and holes clockwise,
// stored as Clipper paths so that booleans need no conversion. 1 unit = 1 um; int64 gives room
// for any printer, and Boost's Voronoi (int32) still covers +-2 km.
#pragma once

#include <cmath>
#include <cstdint>
#include <polyclipping/clipper.hpp>
#include <vector>

namespace carve {

using Coord = ClipperLib::cInt;
using Point = ClipperLib::IntPoint;
using Path = ClipperLib::Path;    // a closed contour, or an open polyline where said so
using Paths = ClipperLib::Paths;  // a planar region (contours with holes) or a set of polylines

constexpr double kUnitsPerMm = 1000.0;

inline Coord to_units(double mm) {
    return static_cast<Coord>(std::llround(mm * kUnitsPerMm));
}
inline double to_mm(Coord units) {
    return static_cast<double>(units) / kUnitsPerMm;
}

// Units between two points.
inline double distance(const Point& a, const Point& b) {
    return std::hypot(double(a.X - b.X), double(a.Y - b.Y));
}

struct Vec3 {
    double x = 0, y = 0, z = 0;
};

struct BBox3 {
    Vec3 min{}, max{};
};

struct BBox2 {
    Coord min_x = 0, min_y = 0, max_x = 0, max_y = 0;
    bool empty = true;
};

}  // namespace carve

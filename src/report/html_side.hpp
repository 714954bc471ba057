// The HTML report's side view of the tallest internal support: carve's ribs chained over the
// layers, seen across the vertical plane through the tallest chain's lowest and highest piece,
// with the model's section in that plane behind it. Private to src/report.
#pragma once

#include <string>
#include <vector>

#include "geometry/types.hpp"

namespace carve::html {

// One rib piece as the report received it.
struct RibPiece {
    int layer = 0;  // index, bottom up
    double z = 0;   // top of its layer, mm
    Path points;
};

// What the side view knows of each layer: its z, and the model's outline simplified.
struct SideLayer {
    int index = 0;
    double z = 0;
    Paths outline;
};

struct TallestSupport {
    int layers = 0;  // 0: no ribs
    double z_from = 0, z_to = 0, height_mm = 0;
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // its lowest and highest piece's centre, mm
};

// The tallest chain of rib pieces, one a layer, each standing on one of the layer below whose
// box (grown by half a line width) meets its own, and its side view as an SVG element; an
// empty string when there are no ribs.
std::string tallest_support_svg(const std::vector<RibPiece>& ribs,
                                const std::vector<SideLayer>& layers, double layer_height,
                                double line_width, TallestSupport& found);

}  // namespace carve::html

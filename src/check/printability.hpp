// Whether a print will build, read from its G-code against the model's slices (issue 35's
// definitions, so that figures compare between slicers):
//
// - Free-standing thin columns. Each layer's footprint is cut into connected pieces. A piece is
//   thin when its area is under 3 mm2 or the narrow side of its minimum-area rotated rectangle
//   is under 2 mm, interior when it keeps more than 0.3 mm from the model's slice boundary (it
//   lies inside the slice eroded by 0.3 mm: it is not the outer wall nor held by it). Thin
//   interior pieces of consecutive layers whose footprints overlap chain into a column; its
//   height is the sum of its layers' heights (layers x layer height).
// - Skin left open. The top region of layer k is the model's slice k minus what lies inside
//   both slices k+1 and k+2; the bottom region likewise with k-1 and k-2 (the first 2 layers are
//   all bottom). Open = region minus footprint, opened by 0.1 mm (slivers under 0.2 mm do not
//   count); a hole is a connected open piece.
//
// Internal to src/check: the analyser feeds it each layer that prints the object.
#pragma once

#include <deque>
#include <vector>

#include "check/gcode_analysis.hpp"

namespace carve::check {

// The narrow side (units) of the minimum-area rectangle around the points, any rotation.
double narrow_side(const Path& points);

// Connected pieces of a region: each outer contour with the holes directly inside it.
std::vector<Paths> connected_pieces(const Paths& region);

// Shrinks (delta < 0) or grows a region with round joins.
Paths offset_round(const Paths& region, Coord delta);
// Morphological opening by r: what a disk of radius r can sweep.
Paths opening(const Paths& region, Coord r);

class PrintabilityMeter {
  public:
    // One layer of the object, bottom up: its top z, its height, its footprint and the model's
    // slice for it.
    void layer(double z, double height, const Paths& footprint, const Paths& model);
    // Measures what waits for the layers above (the last two layers' top regions).
    void finish();
    const PrintabilityFigures& figures() const { return figures_; }

  private:
    struct Layer {
        double z = 0, height = 0;
        Paths footprint, model;
    };
    // A thin interior piece of the layer below, for chaining.
    struct Piece {
        Paths shape;
        Coord min_x, min_y, max_x, max_y;
        size_t node;
    };
    struct Node {
        size_t parent;
        int layer;
        double z, height, width, x, y;
    };

    void columns(const Layer& l);
    void skin(const Paths& region, const Paths& footprint, double z, SkinFigures& out);
    size_t root(size_t n);

    PrintabilityFigures figures_;
    std::deque<Layer> window_;  // the last three layers
    Paths both_above_;          // the part common to the last two slices
    int index_ = 0;
    std::vector<Piece> below_;
    std::vector<Node> nodes_;
};

// Of the layer's extruding moves (the polylines' segments), the longest stretch of one move that
// lies over `unsupported` (its footprint farther than the support radius from the layer below),
// held at both ends: both ends of the stretch are inside the move, where the layer below is
// within reach again. Its length in mm, and its middle.
struct Bridge {
    double length_mm = 0, x_mm = 0, y_mm = 0;
};
Bridge longest_bridge(const std::vector<Path>& polylines, const Paths& unsupported);

}  // namespace carve::check

// What of the model a print leaves out (issue 47), read from its G-code against the model's
// slices, with the same definition for every slicer:
//
// - The measured slice of a layer is the model's slice at the layer's middle shrunk by 0.1 mm
//   (faceting and the bead's rounding at the surface are not a missing part). Uncovered is that
//   minus the layer's whole footprint (every extruding move widened to its line width; skirt,
//   brim and supports included: they lie outside the model and can only cover more).
// - Only what is open to the model's surface counts: a connected uncovered piece that reaches
//   the measured slice's boundary. A piece enclosed by printed lines all round is the interior
//   the print leaves empty on purpose (a hollow print's cavity, the cells of sparse infill); it
//   is reported apart as enclosed. A fin, a flange or an ear that no line reaches is open. A
//   piece in a hole of the footprint that reaches the boundary only where the model's outside
//   is narrower than two lines (the end of a slit, closed over by the wall) is interior too: see
//   InteriorTest.
// - An open piece counts within 1 mm of where it meets the measured slice's boundary: a gap in a
//   wall opens the interior behind it (two shells pinched together, where a slicer's loop
//   passes twice and leaves the sliver between), and the interior is still not the model left
//   out. A missing part up to 2 mm wide counts whole, a wider one by its 1 mm rim; what lies
//   beyond is reported apart as deep.
// - The model's layers above the G-code's last layer (at its layer height) are uncovered whole.
// - A piece is wide when it holds a disk whose diameter is a line width: 1.125 x the nozzle the
//   G-code's header names (0.45 mm at 0.4), else the mean line width measured up to that layer.
//   That is, something is left after eroding the piece by half the width (0.0001 mm2 or more:
//   less is Clipper's rounding of a piece exactly as wide). `carve check --strict` fails on any.
//
// Internal to src/check: the analyser feeds it each layer that prints the object.
#pragma once

#include <vector>

#include "check/gcode_analysis.hpp"

namespace carve::check {

class UncoveredMeter {
  public:
    // One layer of the object: its index among the G-code's layers, its top z, the model's
    // slice, the layer's footprint, and the disk's diameter (mm) for the wide test. Returns the
    // layer's uncovered area (mm2).
    double layer(int index, double z, const Paths& model, const Paths& footprint, double width_mm);
    const UncoveredFigures& figures() const { return figures_; }
    void count_layer_above_print() { ++figures_.layers_above_print; }
    // How the width was settled (UncoveredFigures::line_width_source).
    void set_width_source(const char* source) { figures_.line_width_source = source; }

  private:
    UncoveredFigures figures_;
};

// A piece of `uncovered` (connected: its outer contour with its holes) that reaches the boundary
// of the slice, and a point where it does.
struct OpenPiece {
    Paths piece;
    Point contact;
    Paths meets;  // the parts of it within 5 um of the boundary
};
// The pieces of `uncovered` that reach the boundary of `slice`, of which `uncovered` is a part.
std::vector<OpenPiece> open_pieces(const Paths& slice, const Paths& uncovered);

// Whether `q` (not in the footprint) lies in the print's interior: in a hole of the footprint
// of which nothing outside the model holds a disk two lines (2 x `width`) wide. A hole that holds
// one is the model's own hole (the inside of a tube, the gap between two walls), which a slicer
// walls in, open to the model's surface. A narrower gap of the model's outside that a slicer
// closed over (a slit whose end lies inside the wall, two shells pinched together) does not make
// the interior beside it open.
class InteriorTest {
  public:
    InteriorTest(const Paths& footprint, const Paths& model, Coord width);
    bool operator()(const Point& q);

  private:
    struct Hole {
        Path contour;
        Coord min_x, min_y, max_x, max_y;
        double area;
        int interior = -1;  // not yet known
    };
    std::vector<Hole> holes_;
    const Paths& model_;
    Coord width_;
};

// Area (mm2, holes subtracted) and centroid (mm) of a piece.
UncoveredPiece measure_piece(const Paths& piece);

// Whether the piece holds a disk of diameter `width` (units): something of it is left after an
// erosion by width / 2.
bool holds_disk(const Paths& piece, Coord width);

}  // namespace carve::check

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
//   is reported apart as enclosed. A fin, a flange or an ear that no line reaches is open.
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
    // How the width was settled (UncoveredFigures::line_width_source).
    void set_width_source(const char* source) { figures_.line_width_source = source; }

  private:
    UncoveredFigures figures_;
};

// The pieces of `uncovered` (connected, each its outer contour with its holes) that reach the
// boundary of `slice`, of which `uncovered` is a part.
std::vector<Paths> open_pieces(const Paths& slice, const Paths& uncovered);

// Area (mm2, holes subtracted) and centroid (mm) of a piece.
UncoveredPiece measure_piece(const Paths& piece);

// Whether the piece holds a disk of diameter `width` (units): something of it is left after an
// erosion by width / 2.
bool holds_disk(const Paths& piece, Coord width);

}  // namespace carve::check

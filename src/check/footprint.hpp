// What carve check measures on a layer, seen from above: the footprint of its beads, how far it
// lies from the layer below, its travel against the model's slice. Internal to src/check.
//
// ClipperOffset is used here on purpose: this is a measuring tool, independent of the slicing
// stages' own morphology, and round-capped offsets of open polylines are the natural model of a
// bead seen from above.
#pragma once

#include <vector>

#include "check/gcode_analysis.hpp"

namespace carve::check {

constexpr double kArcToleranceUnits = 5.0;  // 5 um: a 2 mm disk gets ~44 sides, a bead cap ~14

double region_area_mm2(const Paths& region);
Paths dilate_round(const Paths& region, Coord delta);
Paths difference(const Paths& a, const Paths& b);
Paths intersection(const Paths& a, const Paths& b);
// The parts of open polylines inside a closed region (`inside`) or outside it.
Paths clip_open(const Paths& lines, const Paths& region, bool inside);
// Total length of open paths, mm.
double open_length_mm(const Paths& paths);

// Consecutive extruding moves of one width, drawn without a travel in between.
struct Polyline {
    Path points;
    double e = 0;          // filament mm
    double length = 0;     // mm
    bool support = false;  // drawn under a ;TYPE: naming support (any slicer's words)
    double height = 0;     // mm, from a ;HEIGHT: comment; 0 = the layer's z step
    bool object = true;    // the object's own: not custom G-code, a tower, a purge
};

// Width of a bead that lays `volume_per_mm` (mm^3 per mm) at layer height `height`.
double line_width(double volume_per_mm, double height, BeadModel bead);
// The footprint of the polylines, each widened to the width its E implies.
Paths widen(const std::vector<Polyline>& lines, double height_mm, double filament_area,
            BeadModel bead);

// The part of `unsupported` farther than far_units from `below` (the previous layer's footprint).
Paths far_region(const Paths& unsupported, const Paths& below, Coord far_units);

struct TravelFigures {
    double inside_mm = 0, outside_mm = 0;
    long long wall_crossings = 0;
};
// A layer's travel paths against the model's slice grown by the outside tolerance.
TravelFigures measure_travel(const Paths& travel, const Paths& grown);

// Farthest distance (mm) from the model's boundary of a footprint point outside the model; 0
// when none is outside, infinity when the model is empty.
double max_distance_outside(const Paths& footprint, const Paths& model);

}  // namespace carve::check

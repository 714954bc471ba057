// Thin walls (issue #47): the parts of a slice too narrow for two outer lines side by side, a
// fin, a rim, the edge of a leaf, a stroke of lettering, printed as one line along their medial
// axis as wide as the part (PrusaSlicer's Arachne does the same). In a hollow print the outer
// wall is the whole part: what it drops is missing from the print.
//
// The outer wall's centreline runs at s inside the slice, so a part narrower than 2 s has no
// wall at all, and a part narrower than 2 w gets a wall loop doubling back on itself, two lines
// over each other's half. Both are the parts of the slice that a disk of radius w (two lines
// side by side) cannot reach: O \ open(O, w). Each such piece that is a strip (its pruned
// medial axis is longer than the line is wide) is cut out of the wall's region and printed as
// beads along its axis; a piece that is not (the tip of a blunt corner) stays with the wall.
#pragma once

#include <string>
#include <vector>

#include "config/settings.hpp"
#include "toolpath/toolpath.hpp"

namespace carve {

struct ThinWalls {
    std::vector<Extrusion> beads;  // Feature::OuterWall, each of one width (its flow)
    Paths wall_region;             // the outer wall's centreline region less the thin parts
    // Where the nozzle may travel along the beads without leaving the part: a fin narrower
    // than 2 s has no wall region to comb through, and a travel off a bead's tip would
    // otherwise retract.
    Paths corridors;
    // What of the slice is narrower than --min-feature-size (with --no-thin-walls: what no
    // wall loop reaches, the parts narrower than 2 s): printed by nothing, reported.
    double unprinted_mm2 = 0;
};

// `wall_region`: the slice eroded by s (the outer wall's centreline region, covers.cpp).
ThinWalls thin_walls(const Paths& outline, const Paths& wall_region, const Settings& settings);

// The unprinted area per layer in layer order, and the warning a user needs before printing.
class UnprintedTally {
  public:
    void add(int layer, double z, double unprinted_mm2);
    double area_mm2() const { return area_mm2_; }
    int layers() const { return layers_; }
    // Empty when nothing worth naming is left out; otherwise one sentence with the area, the
    // layers and the option that decides it (--min-feature-size, or --no-thin-walls when set).
    std::string warning(const Settings& settings) const;

  private:
    double area_mm2_ = 0;
    int layers_ = 0;
    int first_ = 0, last_ = 0;
    double z_first_ = 0, z_last_ = 0;
};

}  // namespace carve

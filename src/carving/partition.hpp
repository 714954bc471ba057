// The per-slice result of carving: a partition of the model's slice O_i, shared by the
// toolpath stage, the previews and the report.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "geometry/types.hpp"

namespace carve {

// A bridge over a local minimum (report 4.4): parallel lines across `region`, anchored on the
// cavity boundary at both ends.
struct Bridge {
    int cavity = 0;  // j of the cavity C^j whose slice holds the minimum
    Paths region;    // area that needs support (the filled hole / unsupported strip)
    Paths lines;     // open polylines, printed in this order
    double angle_deg = 0;
    bool island = true;  // island minimum (true) or edge-like minimum (false)
    // A cover of this slice over a cavity of the slice below (a ceiling carved whole): the
    // lines replace the cover's solid lines there.
    bool cover = false;
};

// A minimum the bridges left without a printable support (its region on this slice), kept for
// the ribs stage, which may hold it from below.
struct UnheldMinimum {
    Paths region;
    bool ceiling = false;  // a cover over a cavity below
};

struct LayerPartition {
    int index = 0;  // i, bottom-up
    double z = 0;   // cut height in mm, model coordinates
    Paths outline;  // O_i: the model's slice
    // The region bounded by the outer wall's centreline, O_i eroded by s. Its boundary is the
    // print path of C^0. In single-filament mode cavities are modelled inside it so that every
    // cavity boundary is a print path too.
    Paths wall_region;
    Paths shell_paths_region;     // inside the extra shells (== wall_region when shells = 0)
    Paths carvable;               // O'_i = V^0_i: no cover near, inside the shells
    Paths covers;                 // shell_paths_region minus carvable: printed solid
    std::vector<Paths> cavities;  // C^1_i .. C^k_i, pairwise disjoint, inside carvable
    Paths remainder;              // V^k_i
    // What a stage gave up on in this layer, in words with the place (shown to the user as
    // warnings when the layer reaches the end of the pipeline).
    std::vector<std::string> warnings;
    // V^0_i .. V^{k-1}_i, what was left before each iteration, as the sweep computed them and
    // the bridges updated them: the toolpath stage restricts the walls of C^j to V^{j-1} and
    // need not redo the differences. Empty when unknown (a hand-made layer).
    std::vector<Paths> uncarved;
    std::vector<Bridge> bridges;  // filled in by the supports stage
    // Supports for the model's own overhangs (supports/support_volume.hpp), outside the model:
    // the support's region in this layer and, within it, the part printed dense under an
    // overhang (its interface). Empty without --support.
    Paths support;
    Paths support_interface;
    Paths support_walls;  // single walls below the region (open polylines), outside it
    // Local minima of this slice (cavity minima and ceilings over a cavity below) the supports
    // stage found, and how many of them it left without a support that prints: a bridge whose
    // lines would be longer than the printable span.
    int minima_found = 0;
    int minima_unsupported = 0;
    int minima_held_by_wall = 0;  // no bridge, but within a line width of the wall below
    int ceilings_found = 0;       // of them, covers over a cavity below
    int ceilings_unsupported = 0;
    std::vector<UnheldMinimum> unheld;  // the minima counted unsupported above
    // Ribs (supports/ribs.hpp): short open lines inside the cavities, each on a rib that holds
    // what the slices above would leave hanging.
    Paths ribs;
    // Of the slice above's unsupported minima, those the ribs printed on this slice hold.
    int minima_held_by_ribs = 0;
    int ceilings_held_by_ribs = 0;
};

// A stage that hands out layers one at a time, top down (the sweep, a queue between threads).
class LayerSource {
  public:
    virtual ~LayerSource() = default;
    virtual std::optional<LayerPartition> next() = 0;
};

}  // namespace carve

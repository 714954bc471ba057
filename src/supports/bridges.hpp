// Local minima and bridges (report section 4.4), as a stage between the carving sweep and the
// toolpaths. A minimum at slice i is only known once slice i - 1 is carved, so the stage holds
// one slice back: two slices of state, like the sweep.
//
// What needs support at slice i in cavity j is what would be printed above empty space: the
// part of slice i outside C^j_i that lies deeper than r inside C^j_{i-1},
//   U = erode(C^j_{i-1}, r) \ C^j_i, within the carvable region,
// (nothing at slice i - 1 is printed inside a cavity, so no wall below reaches it). Its
// components that are holes of C^j_i are the report's islands; the others are edge-like minima.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "carving/carving.hpp"
#include "carving/layer.hpp"

namespace carve {

struct BridgeOptions {
    Coord line_width = 400;     // w: spacing of the bridge lines
    Coord dilation = 200;       // r
    double angle_step_deg = 5;  // the report hops around the circle by 5 degrees
    double min_area_r2 = 4;     // regions below this multiple of r^2 are spikes, not minima
    bool prune = true;          // drop minima smaller than two line widths across
    Coord max_length = 10000;   // longest line a bridge may span, wall to wall
    // With pruning, an edge-like minimum (not a hole of the cavity: a narrow concavity the
    // cavity below closes, report 4.4.1) no deeper than this inside the cavity below is held
    // by the wall below it and gets no bridge: --rib-reach, the depth from which the ribs hold
    // what the slice above prints (and below carve check's 2 mm). 0: every one is bridged.
    Coord edge_hold = 0;
};

BridgeOptions bridge_options(const Settings& settings);

// Regions of slice i that cavity j leaves without support: U above, small spikes dropped.
std::vector<Paths> unsupported_regions(const Paths& cavity_here, const Paths& cavity_below,
                                       const Paths& carvable_here, const BridgeOptions& options);

// Parallel lines spaced w that cover `need`, each running across `span` (the cavity with the
// minimum filled) from boundary to boundary, at the angle of the step that minimises their
// total length.
// With `shortest_spans`, the angle minimises the sum of the squared line lengths instead.
Bridge plan_bridge(const Paths& need, const Paths& span, const BridgeOptions& options,
                   bool shortest_spans = false);

// plan_bridge, and where a line would span more than max_length, the minimum cut into pieces
// half a span wide, each bridged on its own. Pieces no line within max_length reaches are
// left out; `whole` says whether every part of the minimum got a bridge.
std::vector<Bridge> plan_bridges(const Paths& need, const Paths& span, const BridgeOptions& options,
                                 bool& whole);

// The bridges of slice i as carved, given slice i - 1 as carved (nullptr at layer 0), and the
// partition with the bridged minima joined to their cavities. The carved slices are only read.
BridgedPartition bridge_layer(const LayerPartition& layer, const LayerPartition* below,
                              const BridgeOptions& options);

// The carved layers of `input` going down, each with its bridges.
class BridgeStage {
  public:
    BridgeStage(LayerSource& input, const Settings& settings);
    std::optional<LayerRecord> next();

  private:
    LayerSource& input_;
    BridgeOptions options_;
    std::shared_ptr<const LayerPartition> pending_;  // slice i, waiting for slice i - 1
    bool started_ = false;
};

}  // namespace carve

// Ribs: thin columns inside the cavities that hold what the bridges and minima of the slice
// above would leave hanging (issue #23). The carving makes every wall self-supporting, but a
// bridge line longer than about 4 mm, or a minimum no printable bridge reaches, has parts more
// than 2 mm from anything printed on the layer below. A rib is seeded under each such part and
// grown downwards through the cavity, leaning at most r per layer towards the nearest thing
// printed, until it stands on it (the idea of lightning infill, used inside a cavity).
//
// The planner sees the layers top down, each once, after its bridges are placed: a rib printed
// on slice i only depends on slices i and above, so nothing is held back, and the state is the
// ribs' current positions plus the previous slice's empty region (memory flat in the height).
#pragma once

#include <vector>

#include "carving/layer.hpp"
#include "config/settings.hpp"

namespace carve {

struct RibOptions {
    bool enabled = true;
    Coord line_width = 400;  // w
    Coord lean = 200;        // r: how far a rib may move from one layer to the next
    Coord reach = 1600;      // what lies deeper than this inside the cavity below gets a rib
    Coord spacing = 2600;    // the lattice ribs are seeded on
    Coord piece = 800;       // length of the short line a rib prints on each layer
    Coord attract = 7800;    // ribs nearer each other than this and than any wall pair up
};

RibOptions rib_options(const Settings& settings);

// What the planner needs of one slice that depends on that slice alone, worked out ahead of the
// serial add() (in the pipeline's parallel filter: it was most of the ribs' serial time).
struct RibSlice {
    Paths empty;    // nothing is printed in it: the cavities less half a line, less bridge lines
    Paths deep;     // deeper than `reach` inside `empty`
    Paths printed;  // the outline less `empty`: what the slice below's new ribs hold
};
RibSlice rib_slice(const LayerRecord& layer, const RibOptions& options);

class RibPlanner {
  public:
    explicit RibPlanner(const RibOptions& options);
    // The next slice going down (index one less than the previous call's), its bridges already
    // placed: its ribs, and the minima of the slice above that they hold.
    LayerRibs add(const LayerRecord& layer, RibSlice slice);
    LayerRibs add(const LayerRecord& layer) { return add(layer, rib_slice(layer, options_)); }
    size_t active() const { return nodes_.size(); }  // ribs still to stand on something

  private:
    struct Node {
        Point at;
        Point dir;  // unit-ish direction of its printed piece (scaled to 1024)
    };
    RibOptions options_;
    std::vector<Node> nodes_;  // where each rib is on the slice last added
    Paths printed_above_;      // the slice above: what it prints
    std::vector<UnheldMinimum> unheld_above_;
    bool has_above_ = false;
};

}  // namespace carve

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

#include <memory>
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
    // Filled by rib_overlap(): what the slice above prints, and each of its unheld minima, met
    // with `deep`. Booleans of two slices' own regions, not of the ribs: they need not wait for
    // the serial add().
    Paths hang;
    std::vector<UnheldMinimum> unheld_deep;
};
RibSlice rib_slice(const LayerRecord& layer, const RibOptions& options);

// What a slice hands the one below it for rib_overlap(): a serial link passes it down in
// order, then the overlap runs on any thread. `above` is false for the top slice.
struct RibAbove {
    bool above = false;
    std::shared_ptr<const Paths> printed;
    std::vector<UnheldMinimum> unheld;
};
void rib_overlap(RibSlice& slice, const RibAbove& above);

// The ribs' pieces as add() placed them, stopped at the walls they near (a piece must not
// double a wall's line). Reads the slice and the pieces only: run after add(), on any thread.
LayerRibs clip_ribs(LayerRibs ribs, const RibSlice& slice, const RibOptions& options);

class RibPlanner {
  public:
    explicit RibPlanner(const RibOptions& options);
    // The next slice going down (index one less than the previous call's), its bridges already
    // placed and `slice` overlapped with the slice above: its ribs' pieces, unclipped
    // (clip_ribs() finishes them), and the minima of the slice above that they hold.
    LayerRibs add(const LayerRecord& layer, const RibSlice& slice);
    // All of it at once, for a caller that walks the slices on one thread.
    LayerRibs add(const LayerRecord& layer);
    size_t active() const { return nodes_.size(); }  // ribs still to stand on something

  private:
    struct Node {
        Point at;
        Point dir;  // unit-ish direction of its printed piece (scaled to 1024)
    };
    RibOptions options_;
    std::vector<Node> nodes_;  // where each rib is on the slice last added
    RibAbove above_;           // the slice above, for add(layer) alone
    bool has_above_ = false;
};

}  // namespace carve

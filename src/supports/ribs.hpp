// Ribs: what holds up, inside the cavities, what the bridges and minima of the slice above
// would leave hanging (issue #23). The carving makes every wall self-supporting, but a bridge
// line longer than about 4 mm, or a minimum no printable bridge reaches, has parts more than
// 2 mm from anything printed on the layer below. A rib is seeded under each such part and grown
// downwards through the cavity, leaning at most r per layer towards the nearest thing printed,
// until it stands on it (the idea of lightning infill, used inside a cavity).
//
// A rib is never a free-standing strand (issue #35: a 0.45 mm line 40 mm tall is pushed over by
// the nozzle). On every slice it prints a short piece and a tie from the piece to the nearest
// thing printed there: the wall, or the tie or piece of a rib nearer the wall, so that the ribs
// of a slice are a forest rooted on the walls, as lightning infill's branches are. A tie that
// cannot go on below (its rib merged, stood, or tied elsewhere) fades: its far end closes on the
// rib by r a slice, a web whose edge leans like a cavity's wall, so each tie stands on the slice
// below.
//
// The planner sees the layers top down, each once, after its bridges are placed: a rib printed
// on slice i only depends on slices i and above, so nothing is held back, and the state is the
// ribs' current positions and ties plus the previous slice's empty region (memory flat in the
// height).
#pragma once

#include <memory>
#include <vector>

#include "carving/layer.hpp"
#include "config/settings.hpp"
#include "supports/vaults.hpp"

namespace carve {

struct RibOptions {
    bool enabled = true;
    Coord line_width = 400;  // w
    Coord lean = 200;        // r: how far a rib may move from one layer to the next
    Coord reach = 1600;      // what lies deeper than this inside the cavity below gets a rib
    Coord spacing = 2600;    // the lattice ribs are seeded on
    Coord piece = 800;       // length of the short line a rib prints on each layer
    Coord attract = 7800;    // ribs nearer each other than this and than any wall pair up
    VaultOptions vaults;     // under the wide parts of what would hang
};

RibOptions rib_options(const Settings& settings);

// What the planner needs of one slice that depends on that slice alone, worked out ahead of the
// serial add() (in the pipeline's parallel filter: it was most of the ribs' serial time).
struct RibSlice {
    Paths empty;      // nothing is printed in it: the cavities less half a line, less bridge lines
    Paths unbridged;  // `empty` before the bridge lines were taken out, when there are any
    const Paths& tie_region() const { return unbridged.empty() ? empty : unbridged; }
    Paths deep;       // deeper than `reach` inside `empty`
    Paths printed;    // the outline less `empty`: what the slice below's new ribs hold
    Paths wall_line;  // the outline less half a line: inside the outer wall's centre line
    // Filled by rib_overlap(): what the slice above prints, and each of its unheld minima, met
    // with `deep`. Booleans of two slices' own regions, not of the ribs: they need not wait for
    // the serial add().
    Paths hang;
    std::vector<UnheldMinimum> unheld_deep;
    std::vector<BridgeAbove> bridges_above;  // the slice above's bridges near `hang`
};
RibSlice rib_slice(const LayerRecord& layer, const RibOptions& options);

// What a slice hands the one below it for rib_overlap(): a serial link passes it down in
// order, then the overlap runs on any thread. `above` is false for the top slice.
struct RibAbove {
    bool above = false;
    std::shared_ptr<const Paths> printed;
    std::vector<UnheldMinimum> unheld;
    std::vector<BridgeAbove> bridges;
};
// What the ribs of the slice below need of this slice's bridges.
std::vector<BridgeAbove> bridges_above(const BridgedPartition& bridged);
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
    static constexpr long long kUntied = -2;  // a rib seeded on this slice
    static constexpr long long kWall = -1;    // tied to the region's boundary
    struct Node {
        long long id = 0;
        Point at;
        Point dir;                   // unit-ish direction of its printed piece (scaled to 1024)
        long long target = kUntied;  // what its tie meets: the wall or another rib's id
        Point anchor;                // where its tie meets it
        Point tied_from;             // where the rib was when tied (the slice above, until tie())
        bool fading = false;         // a tie alone, closing on its anchor (no piece, holds nothing)
        double fade_length = 0;      // a fading tie's length on the slice last added
    };
    Path piece_of(const Node& n) const;
    // The node's tie as it was, on the next slice down: its free end r nearer its anchor, or
    // nothing when it is that short.
    bool fade_step(Node& n) const;
    // A tie given up: from `free_end` it closes on `fixed`, which follows the wall (kWall) or
    // the rib `follow`.
    void start_fade(const Point& free_end, const Point& fixed, long long follow,
                    std::vector<Node>& fading) const;
    // Whether an anchor that slid from `before` to `after` stays on the same wall.
    bool follows(const Point& before, const Point& after) const;
    void follow_wall(Node& n, const class WallBoundary& walls) const;
    void tie(std::vector<Node>& nodes, const class WallBoundary& boundary,
             std::vector<Node>& fading) const;
    // add()'s phases and what they share (ribs.cpp).
    struct Descent;
    RibOptions options_;
    VaultPlanner vaults_;
    std::vector<Node> nodes_;  // where each rib is on the slice last added
    RibAbove above_;           // the slice above, for add(layer) alone
    bool has_above_ = false;
    long long next_id_ = 0;
};

}  // namespace carve

// One layer as the toolpaths and the outputs read it: the carving's partition and, beside it,
// what each later stage made of that layer, each record made whole by its own stage and only
// read after it. The bridge stage's minima join their cavities in a partition of its own, so
// the carving's stays as it was carved: the bridges of the slice above read it while this
// slice's bridges are planned, and the toolpaths need no second way to find V^j.
//
// The records live here, below supports, because the toolpaths, the resin images and the
// reports read them and may not include supports.
#pragma once

#include <memory>
#include <vector>

#include "carving/partition.hpp"

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

// The bridge stage's record (supports/bridges.hpp): the partition with each bridged minimum
// joined to its cavity, the bridges, and the minima it found.
struct BridgedPartition {
    std::vector<Paths> cavities;  // C^1_i .. C^k_i with their bridged minima
    Paths remainder;              // V^k_i less the bridged minima
    // V^0_i .. V^{k-1}_i, each with the minima of C^j .. C^k; past them `remainder` is V^k,
    // but for a layer made by hand, which carries V^k here too (unbridged()).
    std::vector<Paths> uncarved;
    std::vector<Bridge> bridges;
    // Local minima of this slice (cavity minima and ceilings over a cavity below), and how
    // many of them got no support that prints: a bridge whose lines would be longer than the
    // printable span.
    int minima_found = 0;
    int minima_unsupported = 0;
    int minima_held_by_wall = 0;  // no bridge, but within a line width of the wall below
    int ceilings_found = 0;       // of them, covers over a cavity below
    int ceilings_unsupported = 0;
    std::vector<UnheldMinimum> unheld;  // the minima counted unsupported above
};

// The partition as carved, nothing bridged; V^0 .. V^k from its cavities when the layer was made
// by hand without them.
BridgedPartition unbridged(const LayerPartition& carved);

// Supports for the model's own overhangs (supports/support_volume.hpp), outside the model.
// Empty without --support.
struct LayerSupport {
    Paths region;     // the support's region in this layer
    Paths interface;  // within it, the part printed dense under an overhang
    Paths walls;      // single walls below the region (open polylines), outside it
};

// The ribs stage's record (supports/ribs.hpp).
struct LayerRibs {
    Paths lines;  // short open lines inside the cavities, each on a rib
    // One line a rib, from its piece to the nearest thing printed on the same slice (a wall, a
    // bridge line): a rib is never a free-standing strand, it leans on a web joined to the wall
    // in every layer, as lightning infill's branches are (issue #35).
    Paths ties;
    // Under a wide ceiling: lines wall to wall across the cavity, merging in pairs going down
    // (supports/vaults.hpp).
    Paths vaults;
    // Of the slice above's unsupported minima, those the ribs printed on this slice hold.
    int minima_held = 0;
    int ceilings_held = 0;
};

struct LayerRecord {
    LayerRecord() : carved(std::make_shared<const LayerPartition>()) {}
    // A layer no later stage has seen: a partition made by hand (tests, tools), or carved.
    LayerRecord(LayerPartition partition)
        : carved(std::make_shared<const LayerPartition>(std::move(partition))),
          bridged(unbridged(*carved)) {}

    std::shared_ptr<const LayerPartition> carved;  // shared with the bridges of the slice above
    BridgedPartition bridged;
    LayerSupport support;
    LayerRibs ribs;

    const LayerPartition& partition() const { return *carved; }
};

}  // namespace carve

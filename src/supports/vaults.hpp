// Vaults: what holds a wide ceiling from below. A rib lattice under an 80 x 80 mm ceiling ties
// every rib to the wall in every layer, and the ties cost more than lightning infill's trees
// (issue #35's flat box: 5.9 cm3 of ribs). Under a part of a ceiling wide enough, the planner
// prints instead a family of parallel lines across the cavity, wall to wall, at right angles to
// the ceiling's bridge lines and close enough that every point of the ceiling lies within the
// ribs' reach of one. Each line is a single-filament wall joined to the cavity's walls at both
// ends in every layer, never a free-standing strand. Going down, neighbouring lines lean
// together by at most r a layer and merge in pairs (1, 2, 4, ... lattice lines become one, a
// vault over each pair), so a family thins out as fast as the overhang angle allows.
//
// Like the ribs, the planner sees the slices top down, each once: the state is the lines'
// offsets and the chords they printed on the slice above (memory flat in the height).
#pragma once

#include <limits>
#include <map>
#include <vector>

#include "geometry/lines.hpp"
#include "geometry/types.hpp"

namespace carve {

struct VaultOptions {
    bool enabled = true;
    Coord line_width = 400;  // w
    Coord lean = 200;        // r: how far a line moves from one layer to the next
    Coord hold = 1838;       // what lies within this of a line's centre is held by it
    Coord wide = 2600;       // parts of the hang holding a disk of this radius may get vaults
    // The ribs' lattice and piece: a part gets a vault only where its lines would print less
    // than the ribs, a piece and a tie a lattice cell.
    Coord rib_spacing = 2600;
    Coord rib_piece = 800;
    Coord spacing() const { return 2 * hold; }
};

// A bridge of the slice above: where it is and which way its lines run.
struct BridgeAbove {
    Paths region;
    double dx = 1, dy = 0;  // unit direction of its lines
};

// What the vault lines of a slice need of it.
struct VaultRegion {
    const Paths& room;       // where a line may run: the cavities less half a line
    const Paths& wall_line;  // inside the outer wall's centre line, for ends past an unprinted band
};

// A line's end at `edge`, where it leaves the empty region coming from `inside`, carried on into
// what is printed there so that the two fuse: half a line width, or on to the outer wall's line
// across a band that prints nothing (a cover band too narrow to fill), at most 1.5 mm.
Point past_the_edge(const Point& inside, const Point& edge, const Paths& wall_line, Coord w);

class VaultPlanner {
  public:
    explicit VaultPlanner(const VaultOptions& options) : options_(options) {}
    // The lines of the slice above carried down one slice: merging pairs lean together, each
    // line keeps the chords of the cavity that continue those it printed above. Returns them as
    // printed (ends carried into the walls).
    Paths carry(const VaultRegion& slice);
    // New families under the parts of `hang` that hold a disk of `wide`: returns their lines
    // on this slice. `above` orients each family across the bridges it holds.
    Paths seed(const VaultRegion& slice, const Paths& hang, const std::vector<BridgeAbove>& above);
    void clear() { lines_.clear(), families_.clear(); }
    size_t active() const { return lines_.size(); }

  private:
    struct Family {
        double dx = 1, dy = 0;          // the lines' direction
        double base = 0;                // offset of lattice index 0
        std::vector<long long> seeded;  // lattice indices seeded, ascending
        std::map<std::pair<long long, long long>, double> settled;  // block -> where it merges
    };
    // A line stands for the lattice indices [lo, hi) of its family, an aligned block of a power
    // of two: its two halves' lines merged into it.
    struct Line {
        size_t family = 0;
        long long lo = 0, hi = 1;
        double at = 0;              // offset along the family's normal
        std::vector<Chord> extent;  // the chords it printed on the slice above
    };
    struct WallDistance {  // along the normal, below and above the line's offset
        double minus = std::numeric_limits<double>::max();
        double plus = std::numeric_limits<double>::max();
    };
    std::vector<WallDistance> wall_distances(const VaultRegion& slice) const;
    double settled(Family& f, long long lo, long long hi) const;
    Paths print(const VaultRegion& slice, std::vector<Line>& lines) const;
    VaultOptions options_;
    std::vector<Family> families_;
    std::vector<Line> lines_;
};

}  // namespace carve

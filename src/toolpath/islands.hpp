// A layer's paths island by island (private to src/toolpath, for plan_layer): an island is a
// connected piece of the model's slice O_i. Which island each path belongs to, the order the
// islands are printed in, and the order of the paths within one.
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include "carving/layer.hpp"
#include "geometry/types.hpp"
#include "toolpath/comb.hpp"
#include "toolpath/toolpath.hpp"

namespace carve {

// One island's paths by group, printed in this order (print_island).
struct Island {
    std::vector<Extrusion> outer, shells, covers, solid, ribs;
    std::vector<std::vector<Extrusion>> cavities;  // C^1 .. C^k
    std::vector<Bridge> bridges;
};

// The islands of a layer's outline `shape` and the paths sorted into them by where each
// starts (within `w` of an island); the last island holds the paths of no island.
class LayerIslands {
  public:
    LayerIslands(const Paths& shape, Coord w, size_t cavity_count);
    // Moves the paths of `group` that have points into their islands' `member`.
    void distribute(std::vector<Extrusion>& group, std::vector<Extrusion> Island::*member);
    // Cavity walls: group j into each island's cavities[j].
    void distribute_cavity_walls(std::vector<std::vector<Extrusion>>& cavity_walls);
    // A bridge goes where its first line starts.
    void distribute_bridges(const std::vector<Bridge>& bridges);
    // The islands that have paths, in the order that crosses the least outside the model,
    // from the end nearer `pos`.
    std::vector<size_t> print_order(const Point& pos) const;
    Island& operator[](size_t k) { return islands_[k]; }
    Island& unplaced() { return islands_.back(); }

  private:
    size_t island_at(const Point& p) const;
    // The islands order[0..k) (indices into islands_) nearest gap first from order[0].
    std::vector<size_t> nearest_island_tour(const std::vector<size_t>& order) const;
    // Most layers are one island: then no index is built and nothing is looked up.
    std::optional<Comber> index_;
    Coord w_;
    std::vector<Island> islands_;  // the last: unplaced
};

// Appends groups of paths to a layer's print order (`out`), each group ordered from where the
// nozzle is: nearest neighbour, then improved.
class PathSequence {
  public:
    PathSequence(Point start, std::vector<Extrusion>& out) : pos_(start), out_(out) {}
    // A path of fewer than two points prints nothing (the G-code stage skipped it); gone,
    // an island's first path is one that prints.
    void append(std::vector<Extrusion>& group, bool keep_loop_starts = false);
    // An island's groups in the report's order C^0, C^1 .. C^k; the outer wall keeps its loops'
    // starts if `placed_seams`.
    void print_island(Island& isl, bool placed_seams, double bridge_flow);
    const Point& pos() const { return pos_; }  // where the last path ends
    size_t size() const { return out_.size(); }

  private:
    Point pos_;
    std::vector<Extrusion>& out_;
};

// Prints every island in print_order(), recording where each starts in `island_starts` (none
// for fewer than two islands that print), then the paths of no island.
void print_islands(LayerIslands& islands, PathSequence& sequence,
                   std::vector<size_t>& island_starts, bool placed_seams, double bridge_flow);

// Distance from `pos` to where an island would start: its outer wall's seams if it has an
// outer wall, else its first path.
double entry_distance(const Island& isl, const Point& pos);

}  // namespace carve

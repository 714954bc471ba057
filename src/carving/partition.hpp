// The per-slice result of carving: a partition of the model's slice O_i. Once carved it is
// only read: the later stages put what they make of it in records of their own (layer.hpp).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "geometry/types.hpp"

namespace carve {

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
    // V^0_i .. V^{k-1}_i, what was left before each iteration, as the sweep computed them: the
    // toolpath stage restricts the walls of C^j to V^{j-1} and need not redo the differences.
    // Empty when unknown (a hand-made layer).
    std::vector<Paths> uncarved;
};

// A stage that hands out layers one at a time, top down (the sweep, a queue between threads).
class LayerSource {
  public:
    virtual ~LayerSource() = default;
    virtual std::optional<LayerPartition> next() = 0;
};

}  // namespace carve

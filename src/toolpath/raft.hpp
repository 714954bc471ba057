// The raft (PrusaSlicer's raft_layers): layers printed under the model, wider than its first
// layer, for parts whose own footprint holds the bed poorly (carve's thin single outer wall on a
// tall part) or whose bottom is rough. Its first layer is the print's first layer (its height,
// width, speed and temperatures), raft_first_layer_expansion wider than the rest and filled at
// 90 %; the layers above it are lines 2 mm apart, each across the one below; its top layer is
// solid, across the one below, and the model's first layer is printed raft_contact_distance
// above it. Every raft line lies within 1 mm of a line of the layer below, so nothing of it
// hangs by `carve check`'s measure. Skirt and brim go around the raft's first layer.
#pragma once

#include <vector>

#include "config/settings.hpp"
#include "geometry/types.hpp"
#include "toolpath/toolpath.hpp"

namespace carve {

struct Raft {
    std::vector<LayerToolpaths> layers;  // indices first_print_layer() .. -1, bottom first
    Paths footprint;                     // the raft's first layer: the skirt and brim go round it
};

// From the model's first-layer slice (every part and copy); empty when settings.raft_layers is 0.
Raft plan_raft(const Paths& first_slice, const Settings& settings);

}  // namespace carve

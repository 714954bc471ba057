// Skirt and brim, as PrusaSlicer names and draws them. The brim: loops around each part's
// outside on the first layer, brim_separation from it, brim_width wide (the brims of two parts
// or copies become one only where they touch). The skirt: loops around the whole first layer
// (brims included) following its convex hull, skirt_distance from it, on the first
// skirt_height layers; it primes the nozzle before the part.
#pragma once

#include "config/settings.hpp"
#include "geometry/types.hpp"
#include "toolpath/toolpath.hpp"

namespace carve {

struct FirstLayerLoops {
    Paths skirt;  // closed loops, model coordinates (um), outermost first
    Paths brim;   // closed loops, outermost first
    bool empty() const { return skirt.empty() && brim.empty(); }
};

// From the first layer's slice (every part and copy; the raft's first layer when there is a
// raft), with the settings' skirt and brim. A skirt taller than that layer rises beside the
// model's next layers too: `above` holds points of the model up to the skirt's top (the run
// gives its vertices and where its edges cross that height), and the skirt follows the convex
// hull of them and the first layer, so that it stays clear of every layer it rises beside
// (PrusaSlicer's draft shield; issue #52).
FirstLayerLoops plan_skirt_and_brim(const Paths& first_slice, const Settings& settings,
                                    const std::vector<Point>& above = {});

// The skirt (the print's first skirt_height layers) and the brim (its first layer, the raft's
// when there is one) printed before the layer's own
// paths: the nozzle is primed before it reaches the part. The layer is then printed in the
// order planned (its islands are not reordered).
void add_skirt_and_brim(LayerToolpaths& layer, const FirstLayerLoops& loops,
                        const Settings& settings);

}  // namespace carve

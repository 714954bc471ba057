// ITERATIVECARVING (report section 3) as one top-down sweep.
//
// For iteration j = 1..k at slice i, with V^0_i = O'_i:
//   G = dilate(C^j_{i+1}, r), S = SKEL(V^{j-1}_i),
//   C^j_i = (G ∪ S) ∩ V^{j-1}_i,  V^j_i = V^{j-1}_i \ C^j_i.
// All k iterations advance together; the only state is C^j_{i+1} for each j.
#pragma once

#include <optional>
#include <vector>

#include "carving/covers.hpp"

namespace carve {

class CarvingSweep : public LayerSource {
public:
    CarvingSweep(LayerSource& input, const Settings& settings);
    // The next layer going down with cavities and remainder filled in.
    std::optional<LayerPartition> next() override;
    int iterations() const { return static_cast<int>(previous_.size()); }

private:
    LayerSource& input_;
    const Settings& settings_;
    std::vector<Paths> previous_;  // C^j_{i+1}, j = 1..k
};

// Computes the medial axis of V^0_i for the first iteration's seed of each layer as it passes: it needs no
// carving state, so it can run on the slicing thread while the sweep works on the layer above.
class SeedAhead : public LayerSource {
public:
    SeedAhead(LayerSource& input, const Settings& settings);
    std::optional<LayerPartition> next() override;

private:
    LayerSource& input_;
    const Settings& settings_;
};

}  // namespace carve

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
    CarvingSweep(CarvableStream& input, const Settings& settings);
    // The next layer going down with cavities and remainder filled in.
    std::optional<LayerPartition> next() override;
    int iterations() const { return static_cast<int>(previous_.size()); }

private:
    CarvableStream& input_;
    const Settings& settings_;
    std::vector<Paths> previous_;  // C^j_{i+1}, j = 1..k
};

}  // namespace carve

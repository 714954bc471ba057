// ITERATIVECARVING (report section 3) as one top-down sweep.
//
// For iteration j = 1..k at slice i, with V^0_i = O'_i:
//   G = dilate(C^j_{i+1}, r), S = SKEL(V^{j-1}_i),
//   C^j_i = (G ∪ S) ∩ V^{j-1}_i,  V^j_i = V^{j-1}_i \ C^j_i.
// All k iterations advance together; the only state is C^j_{i+1} for each j. Iteration j at
// slice i needs C^j_{i+1} and V^{j-1}_i only, so the iterations can be split into stages in a
// chain (a wavefront): one stage works on C^1 of a slice while the next works on C^2..C^k of
// the slice above.
#pragma once

#include <optional>
#include <vector>

#include "carving/covers.hpp"

namespace carve {

// k, the number of carving iterations the settings ask for (--cavities auto: an upper bound).
int sweep_iterations(const Settings& settings);

class CarvingSweep : public LayerSource {
  public:
    // Runs iterations first+1 .. first+count (all from `first` on when count < 0). A stage with
    // first > 0 continues from the remainder V^first_i its input left in the layer.
    CarvingSweep(LayerSource& input, const Settings& settings, int first = 0, int count = -1);
    // The next layer going down with its cavities appended and its remainder updated.
    std::optional<LayerPartition> next() override;

  private:
    LayerSource& input_;
    const Settings& settings_;
    int first_;
    std::vector<Paths> previous_;       // C^j_{i+1}, j = first+1 .. first+count
    std::vector<Paths> left_previous_;  // V^j_{i+1}, with a whole width only
    Paths carvable_above_;              // O'_{i+1}, with a whole width only
};

}  // namespace carve

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

#include <atomic>
#include <cstdint>
#include <optional>
#include <vector>

#include "carving/covers.hpp"
#include "skeleton/skeleton_detail.hpp"

namespace carve {

// V^0_i .. V^k_i of a layer the sweep did not make (one made by hand, in tests and tools):
// V^0 = O', V^j = V^{j-1} \ C^j. A swept layer carries V^0 .. V^{k-1} in `uncarved` and V^k in
// `remainder` (with its specks, which this does not know).
std::vector<Paths> uncarved_levels(const LayerPartition& layer);

// k, the number of carving iterations the settings ask for (--cavities auto: an upper bound).
int sweep_iterations(const Settings& settings);

// What iteration j at slice i can work out from V^{j-1}_i alone (and from O'_{i+1}, an input,
// not sweep state) before the slice above is carved: the specks, the components, which
// components are carved whole and the medial axis of the others, on the guess that the cavity
// above leaves a part of every component uncovered; and each component's axis, for when it
// leaves some covered. The medial axis and the whole-width erosions are most of the sweep's
// work: with this half run beside other slices (in parallel), what waits for the slice above is
// the booleans with the propagated cavity. The carving takes what it needs from here, so the
// result is the same as from one pass.
struct IterationPrep {
    Paths remainder;              // V^{j-1}_i without its specks
    Paths specks;                 // passed on to V^j as they are
    const Paths* carvable_above;  // O'_{i+1}, or null at the top
    bool seed = false;            // a new cavity may start (--cavities auto: V holds a disk of w)
    std::vector<Paths> comps;     // components of `remainder`, when seeding
    // Without a tear limit, when seeding: the components of every component of V together,
    // whether each is carved whole, the whole ones together, and the axis of the others
    // (`known` keeps it per cleaned component).
    bool guessed = false;
    std::vector<Paths> parts;
    std::vector<char> whole;
    Paths whole_parts;
    bool all_whole = false;  // no part needs an axis
    Paths lines;
    int abandoned = 0;  // components whose axis could not be built
    skel::AxisMemo known;
};

class CarvingSweep : public LayerSource {
  public:
    // Runs iterations first+1 .. first+count (all from `first` on when count < 0). A stage with
    // first > 0 continues from the remainder V^first_i its input left in the layer.
    CarvingSweep(LayerSource& input, const Settings& settings, int first = 0, int count = -1);
    // Without an input: a stage that is handed its layers, through prepare() and carve().
    CarvingSweep(const Settings& settings, int first, int count);
    // The next layer going down with its cavities appended and its remainder updated.
    std::optional<LayerPartition> next() override;

    // The two halves of the sweep's iteration first+1+j on one layer. prepare() reads only the
    // layer (it takes V^{first+j} out of it and records it in `uncarved`) and the sweep's
    // settings: it may run on any thread, for several layers at once. carve() appends C and
    // leaves V^{first+j+1} in the layer: it must see the layers in order, top down, each after
    // its prepare(). `carvable_above` (O'_{i+1}, null for the top layer) must outlive carve().
    IterationPrep prepare(LayerPartition& layer, const Paths* carvable_above, size_t j = 0) const;
    void carve(LayerPartition& layer, IterationPrep prep, size_t j = 0);

  private:
    LayerSource* input_;
    const Settings& settings_;
    int first_;
    std::vector<Paths> previous_;       // C^j_{i+1}, j = first+1 .. first+count
    std::vector<Paths> left_previous_;  // V^j_{i+1}, with a whole width only
    Paths carvable_above_;              // O'_{i+1}, with a whole width only (next() alone)
    // 2 i + 1 when carve() found V^{j-1}_i all under the propagated cavity (no seed needed),
    // 2 i when not. Then likely none is needed in slice i - 1 either, and prepare() does not
    // guess for it; not for slices further down, whose guess may run long before carve()
    // reaches them (on one thread, carve() is always one slice ahead). A hint only: carve()
    // works out whatever the guess does not give.
    std::atomic<int64_t> covered_ = 0;
};

}  // namespace carve

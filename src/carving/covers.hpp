// Covers and shells: the carvable part O'_i of each slice, from a fixed window of slices.
//
// A point of slice i may be carved only when the slices i - covers .. i + covers all contain it
// (no top or bottom surface near) and it lies inside the extra shells. The stream pulls slices
// from the top-down slicer and keeps 2 * covers + 1 of them: memory does not grow with height.
#pragma once

#include <deque>
#include <optional>
#include <vector>

#include "carving/partition.hpp"
#include "config/settings.hpp"
#include "slice/slicer.hpp"

namespace carve {

// A slice with the erosions every layer of its window needs, made once when it enters.
struct CoverSlice {
    Slice slice;
    Paths wall_region;         // O_k eroded by s
    Paths shell_paths_region;  // ... and by the extra shells
    Paths carvable_region;     // ... less what is narrower than --solid-below
};

// The two steps of the stream as functions of their inputs alone, so that a scheduler may run
// them for several slices at once: the erosions of one slice, and layer i from the slices of
// its window (those with index i - covers .. i + covers, top down; others are ignored).
CoverSlice cover_slice(Slice slice, const Settings& settings);
// Slice `index`'s region as it is printed: grown (shrunk if negative) by --xy-size-compensation,
// and the first layer's shrunk by --elephant-foot-compensation. cover_slice() applies it; the
// skirt and brim are planned around it too.
Paths compensated_slice(Paths region, int index, const Settings& settings);
LayerPartition carvable_layer(int i, const std::vector<const CoverSlice*>& window,
                              const Settings& settings);

class CarvableStream : public LayerSource {
  public:
    CarvableStream(TopDownSlicer& slicer, const Settings& settings);
    // The next layer going down with outline, wall_region, shell_paths_region, carvable and
    // covers filled in; nothing after layer 0.
    std::optional<LayerPartition> next() override;

  private:
    TopDownSlicer& slicer_;
    const Settings& settings_;
    std::deque<CoverSlice> window_;  // slices i + covers (front) .. i - covers (back), top-down
    int next_index_ = 0;             // index of the next layer to emit
    bool exhausted_ = false;
};

}  // namespace carve

// Covers and shells from a sliding window of 2 * covers + 1 slices.
#include "carving/covers.hpp"

#include <iterator>

#include "base/stage_timer.hpp"
#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"

namespace carve {

Paths compensated_slice(Paths region, int index, const Settings& settings) {
    // PrusaSlicer's order: the whole slice by xy_size_compensation, then the first layer's by
    // elefant_foot_compensation.
    Coord grow = to_units(settings.xy_size_compensation);
    // The print's first layer alone: above a raft the model's first layer is not squashed.
    if (index == settings.first_print_layer())
        grow -= to_units(settings.elephant_foot_compensation);
    if (grow > 0) return dilate(region, grow);
    if (grow < 0) return erode(region, -grow);
    return region;
}

CoverSlice cover_slice(Slice slice, const Settings& settings) {
    StageTimer timer(Stage::kCovers);
    const Coord s = settings.nozzle_radius();
    const Coord w = settings.line_width();
    slice.region = compensated_slice(std::move(slice.region), slice.index, settings);
    CoverSlice e{std::move(slice), {}, {}, {}};
    // The outer wall's centreline runs at s inside the model's outline, so that the printed
    // wall fills the outline exactly; each extra shell sits one line width further in.
    e.wall_region = erode(e.slice.region, s);
    e.shell_paths_region =
        settings.shells > 0 ? erode(e.wall_region, w * settings.shells) : e.wall_region;
    // --solid-below: what an opening of that width removes stays solid (covers fill it).
    const Coord solid = to_units(settings.solid_below);
    e.carvable_region = solid > 0 ? open(e.shell_paths_region, solid / 2) : e.shell_paths_region;
    // --solid-below-area: an island smaller than that is left to the covers whole.
    if (const double limit = settings.solid_below_area * kUnitsPerMm * kUnitsPerMm;
        limit > 0 && !e.carvable_region.empty()) {
        Paths small;
        for (Paths& island : components(e.slice.region))
            if (area(island) < limit)
                std::move(island.begin(), island.end(), std::back_inserter(small));
        if (!small.empty()) e.carvable_region = subtract(e.carvable_region, small);
    }
    // A hole narrower than a line (a sliver void, a slit between two shells) still gets its
    // wall, s out from its edge, but its cover (the hole grown by s) holds no line: where the hole
    // starts over a cavity, the covers below it would print nothing and the wall would start on
    // nothing. Keeping a line's width beyond the wall uncarved gives the covers under it, and the
    // wall beside it, room for a line.
    if (e.carvable_region.empty()) return e;
    if (const Paths narrow = narrow_holes(e.slice.region, s); !narrow.empty())
        e.carvable_region = subtract(e.carvable_region, dilate(narrow, s + w));
    return e;
}

LayerPartition carvable_layer(int i, const std::vector<const CoverSlice*>& window,
                              const Settings& settings) {
    StageTimer timer(Stage::kCovers);
    const int c = std::max(0, settings.covers);
    LayerPartition layer;
    const CoverSlice* own = nullptr;
    int in_range = 0;
    for (const CoverSlice* e : window) {
        if (e->slice.index < i - c || e->slice.index > i + c) continue;
        ++in_range;
        if (e->slice.index == i) own = e;
    }
    layer.index = i;
    if (!own) return layer;  // an empty layer (a gap in the model): nothing to print
    layer.z = own->slice.z;
    layer.outline = own->slice.region;
    layer.wall_region = own->wall_region;
    layer.shell_paths_region = own->shell_paths_region;

    // Carvable: inside the innermost shell centreline of every slice of the window. A slice
    // missing from the window (above the top or below the bottom) means a surface within
    // `covers` layers, so nothing is carvable. Erosion distributes over intersection, so the
    // intersection of the slices' own eroded regions (made once per slice) is the erosion of
    // the window's common outline. With --solid-below each slice's own part wide enough to carve
    // takes the place of its eroded region.
    if (in_range == 2 * c + 1) {
        layer.carvable = own->carvable_region;
        for (const CoverSlice* other : window) {
            if (other == own || other->slice.index < i - c || other->slice.index > i + c) continue;
            if (layer.carvable.empty()) break;
            layer.carvable = intersect(layer.carvable, other->carvable_region);
        }
    }
    layer.covers = subtract(layer.shell_paths_region, layer.carvable);
    return layer;
}

CarvableStream::CarvableStream(TopDownSlicer& slicer, const Settings& settings)
    : slicer_(slicer), settings_(settings), next_index_(slicer.layer_count() - 1) {}

std::optional<LayerPartition> CarvableStream::next() {
    if (next_index_ < 0) return std::nullopt;
    const int i = next_index_--;
    const int c = std::max(0, settings_.covers);
    // Pull slices down to i - c (the window's lowest); slices above i + c fall out.
    while (!exhausted_ && (window_.empty() || window_.back().slice.index > i - c)) {
        auto slice = slicer_.next();
        if (!slice) {
            exhausted_ = true;
            break;
        }
        window_.push_back(cover_slice(std::move(*slice), settings_));
    }
    while (!window_.empty() && window_.front().slice.index > i + c) window_.pop_front();
    std::vector<const CoverSlice*> window;
    for (const CoverSlice& e : window_) window.push_back(&e);
    return carvable_layer(i, window, settings_);
}

}  // namespace carve

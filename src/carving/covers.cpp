// Covers and shells from a sliding window of 2 * covers + 1 slices.
#include "carving/covers.hpp"

#include "core/stage_timer.hpp"

#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"

namespace carve {

CarvableStream::CarvableStream(TopDownSlicer& slicer, const Settings& settings)
    : slicer_(slicer), settings_(settings), next_index_(slicer.layer_count() - 1) {}

std::optional<LayerPartition> CarvableStream::next() {
    if (next_index_ < 0) return std::nullopt;
    const int i = next_index_--;
    const int c = std::max(0, settings_.covers);

    // Pull slices down to i - c (the window's lowest); slices above i + c fall out.
    while (!exhausted_ && (window_.empty() || window_.back().index > i - c)) {
        auto s = slicer_.next();
        if (!s) {
            exhausted_ = true;
            break;
        }
        window_.push_back(std::move(*s));
    }
    while (!window_.empty() && window_.front().index > i + c) window_.pop_front();

    StageTimer timer(Stage::kCovers);
    LayerPartition layer;
    const Slice* own = nullptr;
    int in_range = 0;
    for (const Slice& s : window_) {
        if (s.index < i - c || s.index > i + c) continue;
        ++in_range;
        if (s.index == i) own = &s;
    }
    layer.index = i;
    if (!own) return layer;  // an empty layer (a gap in the model): nothing to print
    layer.z = own->z;
    layer.outline = own->region;

    const Coord s = settings_.nozzle_radius();
    const Coord w = settings_.line_width();
    // The outer wall's centreline runs at s inside the model's outline, so that the printed
    // wall fills the outline exactly; each extra shell sits one line width further in.
    layer.wall_region = erode(layer.outline, s);
    layer.shell_paths_region = settings_.shells > 0 ? erode(layer.wall_region, w * settings_.shells)
                                                    : layer.wall_region;

    // Carvable: inside the innermost shell centreline of every slice of the window. A slice
    // missing from the window (above the top or below the bottom) means a surface within
    // `covers` layers, so nothing is carvable. Erosion commutes with intersection, so one
    // erosion of the window's common outline does for all.
    if (in_range == 2 * c + 1) {
        Paths common = layer.outline;
        for (const Slice& other : window_) {
            if (other.index == i || other.index < i - c || other.index > i + c) continue;
            if (common.empty()) break;
            common = intersect(common, other.region);
        }
        layer.carvable = c == 0 ? layer.shell_paths_region : erode(common, s + w * settings_.shells);
    }
    layer.covers = subtract(layer.shell_paths_region, layer.carvable);
    return layer;
}

}  // namespace carve

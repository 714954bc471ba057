// Raft layers (raft.hpp).
#include "toolpath/raft.hpp"

#include <algorithm>

#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"
#include "toolpath/fill.hpp"

namespace carve {

namespace {

// Lines of the raft's middle layers: 2 mm apart (PrusaSlicer's support spacing is 2.5), so that
// a line of the layer above, laid across them, is never more than 1 mm from one.
constexpr double kBaseSpacingMm = 2.0;
// The first layer's fill, PrusaSlicer's raft_first_layer_density default: dense enough to hold
// the bed, with room for the squashed lines to spread.
constexpr double kFirstLayerDensity = 0.9;

}  // namespace

Raft plan_raft(const Paths& first_slice, const Settings& s) {
    Raft raft;
    const int n = s.raft_layers;
    const Paths parts = without_holes(first_slice);
    if (n <= 0 || parts.empty()) return raft;
    // The raft's outline: one region under parts that its expansion joins.
    const Paths body = without_holes(dilate(parts, to_units(s.raft_expansion)));
    raft.footprint = without_holes(dilate(body, to_units(s.raft_first_layer_expansion)));
    for (int k = 0; k < n; ++k) {
        const int index = s.first_print_layer() + k;
        const Paths& outline = k == 0 ? raft.footprint : body;
        const Coord w = to_units(s.layer_width_mm(index));
        LayerToolpaths layer;
        layer.index = index;
        layer.z = s.layer_top_mm(index);
        layer.comb_region = outline;  // the nozzle may cross the raft without retracting
        for (const Path& loop : erode(outline, w / 2)) {
            if (loop.size() < 3) continue;
            Extrusion e;
            e.feature = Feature::Support;
            e.points = loop;
            e.closed = true;
            layer.extrusions.push_back(std::move(e));
        }
        // The top layer solid (the model's bottom lies on it), the first at 90 %, the others
        // sparse; each across the one below.
        const bool top = k == n - 1;
        const double spacing_mm = top      ? s.layer_width_mm(index)
                                  : k == 0 ? s.layer_width_mm(index) / kFirstLayerDensity
                                           : kBaseSpacingMm;
        const double angle = (n - 1 - k) % 2 == 0 ? 45.0 : 135.0;
        for (Extrusion& e : fill_solid(erode(outline, w), angle, to_units(spacing_mm),
                                       top ? Feature::SupportInterface : Feature::Support))
            layer.extrusions.push_back(std::move(e));
        raft.layers.push_back(std::move(layer));
    }
    return raft;
}

}  // namespace carve

// External overhang per layer and the warning built from it.
#include "supports/overhang.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"

namespace carve {

Paths external_overhang(const Paths& outline, const Paths* below, Coord support) {
    if (!below || outline.empty()) return {};
    if (below->empty()) return outline;
    // The dilation is read unresolved: its union would be a second Clipper pass on every layer.
    return subtract_positive(outline, dilation(*below, support));
}

LayerOverhang measure_overhang(const Paths& outline, const Paths* below, Coord support, Coord far) {
    LayerOverhang out;
    const Paths beyond = external_overhang(outline, below, support);
    if (beyond.empty()) return out;  // most layers: one dilation and nothing more
    out.area_mm2 = area_mm2(beyond);
    const Paths far_beyond =
        far > support ? (below->empty() ? beyond : subtract_positive(beyond, dilation(*below, far)))
                      : beyond;
    out.far_area_mm2 = area_mm2(far_beyond);
    return out;
}

void OverhangTally::add(int layer, double z, const LayerOverhang& overhang) {
    area_mm2_ += overhang.area_mm2;
    far_area_mm2_ += overhang.far_area_mm2;
    // Specks (a sliver at a facet's tip) are not worth naming a layer for.
    if (overhang.far_area_mm2 < 0.05) return;
    // Layers come top down or bottom up; a run absorbs a neighbour up to two layers away.
    if (!runs_.empty() && std::abs(layer - runs_.back().last) <= 3) {
        Run& r = runs_.back();
        r.last = layer;
        r.z_last = z;
        r.far_mm2 += overhang.far_area_mm2;
        return;
    }
    runs_.push_back({layer, layer, z, z, overhang.far_area_mm2});
}

std::string OverhangTally::warning() const {
    if (far_area_mm2_ <= warn_mm2_) return {};
    std::vector<Run> runs = runs_;
    std::sort(runs.begin(), runs.end(),
              [](const Run& a, const Run& b) { return a.far_mm2 > b.far_mm2; });
    std::string where;
    const size_t shown = std::min<size_t>(3, runs.size());
    for (size_t i = 0; i < shown; ++i) {
        const Run& r = runs[i];
        const int lo = std::min(r.first, r.last), hi = std::max(r.first, r.last);
        const double zlo = std::min(r.z_first, r.z_last), zhi = std::max(r.z_first, r.z_last);
        const std::string area =
            r.far_mm2 < 10 ? fmt::format("{:.1f}", r.far_mm2) : fmt::format("{:.0f}", r.far_mm2);
        const std::string at =
            lo == hi ? fmt::format("layer {} (z {:.2f} mm)", lo + 1, zlo)
                     : fmt::format("layers {}-{} (z {:.2f}-{:.2f} mm)", lo + 1, hi + 1, zlo, zhi);
        where += fmt::format("{}{} mm2 at {}", i ? ", " : "", area, at);
    }
    if (runs.size() > shown) where += fmt::format(" and {} more places", runs.size() - shown);
    return fmt::format(
        "{:.0f} mm2 of the model's own overhang lies more than 2 mm beyond the layer below and "
        "will hang without supports (--support auto holds it): {}",
        far_area_mm2_, where);
}

}  // namespace carve

// The figures of the run summed layer by layer (see layer_figures.hpp).
#include "run/layer_figures.hpp"

#include "geometry/polygon.hpp"

namespace carve {

std::vector<double> extrusion_volumes_mm3(const LayerToolpaths& paths, const Settings& settings) {
    std::vector<double> v;
    v.reserve(paths.extrusions.size());
    // The layer's own line width and thickness (the first layer's may differ), and the flow
    // the G-code extrudes (--extrusion-multiplier): the material is what the E words feed.
    const double w = settings.layer_width_mm(paths.index);
    const double h = settings.layer_thickness_mm(paths.index);
    for (const Extrusion& e : paths.extrusions)
        v.push_back(to_mm(static_cast<Coord>(length(Paths{e.points}, e.closed))) * w * h * e.flow *
                    settings.extrusion_multiplier);
    return v;
}

void add_layer_figures(const Token& t, const Settings& settings, RunResult& result,
                       double& sliced_volume, OverhangTally& overhangs) {
    const LayerPartition& layer = t.record.partition();
    const double h = settings.model_layer_mm(layer.index);
    const BridgedPartition& bridged = t.record.bridged;
    sliced_volume += area_mm2(layer.outline) * h;
    result.carvable_volume_mm3 += area_mm2(layer.carvable) * h;
    for (size_t j = 0; j < bridged.cavities.size(); ++j)
        result.cavity_volume_mm3[j] += area_mm2(bridged.cavities[j]) * h;
    result.remainder_volume_mm3 += area_mm2(bridged.remainder) * h;
    result.cover_volume_mm3 += area_mm2(layer.covers) * h;
    result.layer_material_mm3[layer.index] = t.material;
    overhangs.add(layer.index, settings.layer_top_mm(layer.index), t.overhang);  // as the G-code
    result.supported_area_mm2 += t.support_new_mm2;
    if (const Paths& support = t.record.support.region; !support.empty())
        result.support_region_volume_mm3 += area_mm2(support) * h;
    result.minima_found += bridged.minima_found;
    result.minima_unsupported += bridged.minima_unsupported;
    result.minima_held_by_wall += bridged.minima_held_by_wall;
    // Ribs on this slice hold minima of the slice above, already counted unsupported.
    const LayerRibs& ribbed = t.record.ribs;
    result.minima_unsupported -= ribbed.minima_held;
    result.minima_held_by_ribs += ribbed.minima_held;
    result.ceilings_unsupported -= ribbed.ceilings_held;
    result.ceilings_held_by_ribs += ribbed.ceilings_held;
    result.ribs += static_cast<int>(ribbed.lines.size());
    result.ceilings_found += bridged.ceilings_found;
    result.ceilings_unsupported += bridged.ceilings_unsupported;
    for (size_t i = 0; i < t.paths.extrusions.size(); ++i) {
        const Extrusion& e = t.paths.extrusions[i];
        const double v = t.volumes[i];
        int f = static_cast<int>(e.feature);
        if (e.feature == Feature::CavityWall) {
            if (result.cavity_wall_mm3.size() <= size_t(e.cavity))
                result.cavity_wall_mm3.resize(e.cavity + 1, 0.0);
            result.cavity_wall_mm3[e.cavity] += v;
        }
        if (e.feature == Feature::Cover && e.cavity < 0) f = -1;
        if (f >= 0)
            result.feature_mm3[f] += v;
        else
            result.remainder_fill_mm3 += v;
    }
    for (const Bridge& b : bridged.bridges) {
        ++result.bridges;
        if (b.cover) ++result.cover_bridges;
        const double mm = to_mm(static_cast<Coord>(length(b.lines, false)));
        result.bridge_length_mm += mm;
        if (b.island && !b.cover) ++result.island_bridges, result.island_bridge_length_mm += mm;
    }
}

}  // namespace carve

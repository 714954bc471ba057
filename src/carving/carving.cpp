// The iterative carving sweep: k cavities advance together, top down, one slice at a time.
#include "carving/carving.hpp"

#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"
#include "skeleton/skeleton.hpp"

namespace carve {

namespace {

// With --cavities auto the sweep carries up to this many cavities and stops seeding new ones
// in a slice once its remainder erodes away at the line width.
constexpr int kAutoMaxCavities = 12;

SkeletonOptions seed_options(const Settings& settings) {
    SkeletonOptions o;
    o.prune_threshold = settings.line_width();
    o.thickness = settings.nozzle_radius();
    // The seed is thickened by s = 200 um and pruned at w, so a 25 um contour simplification
    // changes nothing printable while it cuts the Voronoi input (the sweep's hot spot) by ~40 %.
    o.max_arc_error = 25;
    return o;
}

// SKEL(V) restricted to the components of V that the propagated cavity G does not already
// cover: where G covers a component, (G ∪ S) ∩ V = V whatever S is, so its axis is not needed.
Paths seeds(const Paths& remainder, const Paths& propagated, const SkeletonOptions& options) {
    if (propagated.empty()) return skeleton(remainder, options);
    Paths uncovered = subtract(remainder, propagated);
    if (uncovered.empty()) return {};
    Paths out;
    for (const Paths& comp : components(remainder)) {
        if (intersect(comp, uncovered).empty()) continue;
        Paths s = skeleton(comp, options);
        out.insert(out.end(), s.begin(), s.end());
    }
    return out;
}

}  // namespace

CarvingSweep::CarvingSweep(LayerSource& input, const Settings& settings)
    : input_(input),
      settings_(settings),
      previous_(settings.cavities_auto ? kAutoMaxCavities : std::max(0, settings.cavities)) {}

std::optional<LayerPartition> CarvingSweep::next() {
    auto layer = input_.next();
    if (!layer) return std::nullopt;

    const Coord r = settings_.dilation_per_layer();
    const Coord w = settings_.line_width();
    const SkeletonOptions options = seed_options(settings_);

    Paths remainder = layer->carvable;  // V^{j-1}_i
    layer->cavities.reserve(previous_.size());
    for (size_t j = 0; j < previous_.size(); ++j) {
        Paths& above = previous_[j];  // C^j_{i+1}, replaced by C^j_i
        Paths cavity;
        if (!remainder.empty()) {
            Paths propagated = above.empty() ? Paths{} : dilate(above, r);  // G
            const bool seed = !settings_.cavities_auto || !erode(remainder, w).empty();
            Paths s;
            if (seed && j == 0 && layer->first_seed)
                s = *layer->first_seed;
            else if (seed)
                s = seeds(remainder, propagated, options);
            cavity = intersect(unite(propagated, s), remainder);
            remainder = subtract(remainder, cavity);
        }
        layer->cavities.push_back(cavity);
        above = std::move(cavity);
    }
    layer->remainder = std::move(remainder);
    layer->first_seed.reset();
    return layer;
}

SeedAhead::SeedAhead(LayerSource& input, const Settings& settings)
    : input_(input), settings_(settings) {}

std::optional<LayerPartition> SeedAhead::next() {
    auto layer = input_.next();
    if (layer && settings_.cavities != 0 && !layer->carvable.empty() &&
        (!settings_.cavities_auto || !erode(layer->carvable, settings_.line_width()).empty()))
        layer->first_seed = skeleton(layer->carvable, seed_options(settings_));
    return layer;
}

}  // namespace carve

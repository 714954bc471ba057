// Local minima and their bridges (see bridges.hpp): the unsupported regions of a slice, a
// minimum cut into pieces a printable span wide, cover bridges over the cavity below, and the
// minima joining their cavities once bridged. The direction of a bridge's lines is found by
// bridge_scan.cpp.
#include "supports/bridges.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "base/error.hpp"
#include "base/stage_timer.hpp"
#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"

namespace carve {

namespace {

// The paths of `region` whose boxes meet `box`. A path wholly outside the box, outer or hole,
// changes no winding inside it, so a boolean whose result lies within the box may leave it out:
// Clipper's cost grows with every path it is given, and a cavity has dozens of pieces.
Paths paths_meeting(const Paths& region, const std::vector<BBox2>& boxes, const BBox2& box) {
    Paths out;
    for (size_t i = 0; i < region.size(); ++i)
        if (overlap(boxes[i], box)) out.push_back(region[i]);
    return out;
}

std::vector<BBox2> path_bounds(const Paths& region) {
    std::vector<BBox2> boxes;
    boxes.reserve(region.size());
    for (const Path& p : region) boxes.push_back(bounds(p));
    return boxes;
}

// Splits a normalised region into the paths a boolean with the minima in `boxes` may change
// and the others: paths whose boxes meet a minimum's box, then, transitively, every path whose
// box meets one of those. An outer's holes lie in its box and a hole lies in its outer's box,
// so the second part keeps each piece whole, and nothing of it comes near a minimum: the
// boolean on the first part plus the second part untouched is the boolean on the region.
// Clipper's cost grows with all it is given, and cavities have dozens of pieces.
std::pair<Paths, Paths> split_near(const Paths& region, const std::vector<BBox2>& boxes) {
    const std::vector<BBox2> own = path_bounds(region);
    std::vector<char> near(region.size(), 0);
    std::vector<size_t> todo;
    for (size_t i = 0; i < region.size(); ++i)
        if (std::any_of(boxes.begin(), boxes.end(),
                        [&](const BBox2& b) { return overlap(own[i], b); })) {
            near[i] = 1;
            todo.push_back(i);
        }
    while (!todo.empty()) {
        const size_t i = todo.back();
        todo.pop_back();
        for (size_t j = 0; j < region.size(); ++j)
            if (!near[j] && overlap(own[i], own[j])) {
                near[j] = 1;
                todo.push_back(j);
            }
    }
    std::pair<Paths, Paths> out;
    for (size_t i = 0; i < region.size(); ++i)
        (near[i] ? out.first : out.second).push_back(region[i]);
    return out;
}

// `op` applied to the part of `region` near the minima in `boxes`, the rest of it kept as is.
template <typename Op>
Paths near_minima(const Paths& region, const std::vector<BBox2>& boxes, Op op) {
    auto [near, far] = split_near(region, boxes);
    if (far.empty()) return op(region);
    Paths out = op(near);
    out.insert(out.end(), std::make_move_iterator(far.begin()), std::make_move_iterator(far.end()));
    return out;
}

double longest_line(const Paths& lines) {
    double best = 0;
    for (const Path& l : lines) best = std::max(best, length(Paths{l}, false));
    return best;
}

}  // namespace

BridgeOptions bridge_options(const Settings& settings) {
    BridgeOptions o;
    o.line_width = settings.line_width();
    o.dilation = settings.dilation_per_layer();
    o.angle_step_deg = settings.bridge_angle_step;
    o.prune = settings.prune_bridges;
    o.max_length = to_units(settings.max_bridge_length);
    o.edge_hold =
        settings.prune_bridges && settings.rib_reach > 0 ? to_units(settings.rib_reach) : 0;
    return o;
}

std::vector<Paths> unsupported_regions(const Paths& cavity_here, const Paths& cavity_below,
                                       const Paths& carvable_here, const BridgeOptions& options) {
    std::vector<Paths> out;
    if (cavity_below.empty() || carvable_here.empty()) return out;
    // Used once: the subtraction resolves the erosion's crossings in its own pass.
    const PositiveRegion deep_below = erosion(simplify(cavity_below, kSimplify), options.dilation);
    if (deep_below.contours.empty()) return out;
    Paths u = intersect(subtract(deep_below, cavity_here), carvable_here);
    const double r2 = double(options.dilation) * options.dilation;
    // One PolyTree pass both splits U and drops what is too small to matter: outlines and
    // holes under min_area_r2 * r^2 are spikes and slivers, not minima.
    for (Paths& all : components(u)) {
        const double min_area = options.min_area_r2 * r2;
        if (std::abs(area(all.front())) < min_area) continue;
        Paths comp{all.front()};
        for (size_t h = 1; h < all.size(); ++h)
            if (std::abs(area(all[h])) >= min_area) comp.push_back(std::move(all[h]));
        // A speck that fits within a couple of line widths is held by the filament around it:
        // printed over it, nothing hangs further than a line width from support.
        if (options.prune) {
            const BBox2 b = bounds(comp);
            if (std::hypot(double(b.max_x - b.min_x), double(b.max_y - b.min_y)) <
                2.0 * options.line_width)
                continue;
        }
        out.push_back(std::move(comp));
    }
    return out;
}

std::vector<Bridge> plan_bridges(const Paths& need, const Paths& span, const BridgeOptions& options,
                                 bool& whole) {
    std::vector<Bridge> out;
    whole = true;
    Bridge b = plan_bridge(need, span, options);
    if (!options.prune ||
        (!b.lines.empty() && longest_line(b.lines) <= double(options.max_length))) {
        if (!b.lines.empty())
            out.push_back(std::move(b));
        else
            whole = false;
        return out;
    }
    // One direction for a long or bent minimum makes some of its lines cross the cavity the
    // long way. Cut into cells half a span wide, each piece finds its own direction, most
    // often across the narrow cavity around it; a cell that still finds none is cut in four,
    // down to cells four line widths wide (at the corner of an L-shaped corridor no direction
    // is short: only a small piece there is left out).
    const Coord smallest = 4 * options.line_width;
    // The pieces are mostly slivers along a wall, from a tear a little faster than r: bridged
    // at up to max_length, each got a fan of long lines whose middles hang further from any
    // support than the sliver itself (skull x1.43: 848 mm^2 of filament more than 2 mm from
    // anything below, against 56 with pieces held to 4 mm, and 4.37 against 4.24 % material).
    // A piece is bridged only within 4 mm: no line more than 2 mm from an anchor.
    const double split_span = std::min(double(options.max_length), 10.0 * options.line_width);
    const double min_area =
        options.min_area_r2 * double(options.dilation) * double(options.dilation);
    std::vector<std::pair<BBox2, Coord>> cells;
    const BBox2 box = bounds(need);
    const Coord first = std::max<Coord>(options.max_length / 2, smallest);
    for (Coord y = box.min_y; y < box.max_y; y += first)
        for (Coord x = box.min_x; x < box.max_x; x += first)
            cells.push_back({{x, y, x + first, y + first, false}, first});
    while (!cells.empty()) {
        const auto [c, size] = cells.back();
        cells.pop_back();
        const Paths piece = clip_to_box(need, c);
        if (std::abs(area(piece)) < min_area) continue;
        Bridge p = plan_bridge(piece, span, options);
        if (!p.lines.empty() && longest_line(p.lines) <= split_span) {
            out.push_back(std::move(p));
            continue;
        }
        if (size / 2 < smallest) {
            whole = false;
            continue;
        }
        const Coord h = size / 2;
        for (int k = 0; k < 4; ++k) {
            const Coord x = c.min_x + (k % 2) * h, y = c.min_y + (k / 2) * h;
            cells.push_back({{x, y, k % 2 ? c.max_x : x + h, k / 2 ? c.max_y : y + h, false}, h});
        }
    }
    return out;
}

namespace {

// The minima of one slice given a bridge, cavity by cavity (M_j), with a box per minimum.
class BridgedMinima {
  public:
    explicit BridgedMinima(size_t cavities) : of_(cavities) {}

    void add(size_t cavity, const Paths& minimum) {
        Cavity& c = of_[cavity];
        c.paths.insert(c.paths.end(), minimum.begin(), minimum.end());
        c.boxes.push_back(bounds(minimum));
        c.ends.push_back(c.paths.size());
        all_boxes_.push_back(c.boxes.back());
    }
    bool empty() const { return all_boxes_.empty(); }
    const std::vector<BBox2>& boxes() const { return all_boxes_; }

    // The minima whose boxes meet `box`, of the cavities `from` <= c < `to` or, if not
    // `inside`, of all the others, as one region: the minima of different cavities are
    // disjoint, each lying in the erosion of its own cavity below, and those of one cavity
    // are components of one region.
    Paths near(const BBox2& box, size_t from, size_t to, bool inside = true) const {
        Paths out;
        for (size_t c = 0; c < of_.size(); ++c) {
            if ((c >= from && c < to) != inside) continue;
            const Cavity& m = of_[c];
            for (size_t n = 0, begin = 0; n < m.boxes.size(); begin = m.ends[n++])
                if (overlap(m.boxes[n], box))
                    out.insert(out.end(), m.paths.begin() + begin, m.paths.begin() + m.ends[n]);
        }
        return out;
    }

  private:
    struct Cavity {
        Paths paths;
        std::vector<BBox2> boxes;
        std::vector<size_t> ends;  // where each minimum's paths end in `paths`
    };
    std::vector<Cavity> of_;
    std::vector<BBox2> all_boxes_;
};

// The region with the minima of cavities [gain_from, gain_to) added and all the others taken
// out, in one boolean on its part near them.
Paths exchange(const Paths& region, const BridgedMinima& minima, size_t gain_from, size_t gain_to) {
    return near_minima(region, minima.boxes(), [&](const Paths& part) {
        const BBox2 box = bounds(part);
        const Paths lost = minima.near(box, gain_from, gain_to, false);
        const Paths gained = minima.near(box, gain_from, gain_to);
        if (gained.empty()) return subtract(part, lost);
        if (lost.empty()) return unite(part, gained);
        // The part and the minima it gains touch without overlapping, so their contours
        // together under non-zero fill are their union: one pass does both.
        Paths both = part;
        both.insert(both.end(), gained.begin(), gained.end());
        return subtract_from_union(both, lost);
    });
}

// Covers of slice i over the cavities of slice i - 1: where a part of the volume was carved
// whole (CarvingSweep, whole_width) its ceiling is the cover above it, which has nothing under
// it but the cavity. Those parts of the cover, deeper than a line width inside the cavity
// below (a cover line overhanging a wall by less than that is held by it), are printed as
// bridges across the cavity below, wall to wall. Bands narrower than a line width (the edge
// of a cover over a sloping ceiling, overhanging the cover below) are left to the solid lines.
void add_cover_bridges(BridgedPartition& out, const LayerPartition& layer,
                       const LayerPartition& below, const BridgeOptions& options) {
    if (layer.covers.empty()) return;
    const Coord w = options.line_width;
    const BBox2 cover_box = bounds(layer.covers);
    Paths covers_near;  // the covers grown by w: the lines end on the walls below them
    for (size_t j = 0; j < below.cavities.size(); ++j) {
        const Paths& cavity = below.cavities[j];
        if (cavity.empty() || !overlap(bounds(cavity), cover_box)) continue;
        const Paths deep = intersect(erode(cavity, w), layer.covers);
        if (deep.empty()) continue;
        const Paths need_all = open(deep, w / 2);
        if (need_all.empty()) continue;
        if (covers_near.empty()) covers_near = dilate(layer.covers, w);
        const double min_area = options.min_area_r2 * double(options.dilation) * options.dilation;
        const std::vector<BBox2> piece_boxes = path_bounds(cavity);
        for (Paths& need : components(need_all)) {
            if (std::abs(area(need)) < min_area) continue;
            const BBox2 b0 = bounds(need);
            if (std::hypot(double(b0.max_x - b0.min_x), double(b0.max_y - b0.min_y)) < 2.0 * w)
                continue;
            const Coord m = options.max_length;
            const BBox2 win{b0.min_x - m, b0.min_y - m, b0.max_x + m, b0.max_y + m, false};
            const Paths span = unite(
                intersect(clip_to_box(paths_meeting(cavity, piece_boxes, win), win), covers_near),
                need);
            // Over a cavity filled wall to wall every direction has about the same total
            // length (the area over the spacing), so the plain total cannot tell an 8 mm span
            // from a 40 mm one: the sum of squared spans can (a line sags with its span).
            Bridge br = plan_bridge(need, span, options, true);
            ++out.minima_found;
            ++out.ceilings_found;
            // Kept even when a line is longer than a printable span: solid lines in its place
            // would hang over the cavity all the same. Counted as unsupported.
            if (br.lines.empty() || longest_line(br.lines) > double(options.max_length)) {
                ++out.minima_unsupported;
                ++out.ceilings_unsupported;
                out.unheld.push_back({need, true});
            }
            if (br.lines.empty()) continue;
            br.cavity = static_cast<int>(j) + 1;
            br.island = false;
            br.cover = true;
            out.bridges.push_back(std::move(br));
        }
    }
}

}  // namespace

constexpr size_t kMaxMinimaPerLayer = 10000;

BridgedPartition bridge_layer(const LayerPartition& layer, const LayerPartition* below,
                              const BridgeOptions& options) {
    BridgedPartition out = unbridged(layer);
    if (!below) return out;
    const size_t k = std::min(layer.cavities.size(), below->cavities.size());
    BridgedMinima bridged(out.cavities.size());
    size_t minima = 0;
    for (size_t j = 0; j < k; ++j) {
        const std::vector<Paths> needs =
            unsupported_regions(layer.cavities[j], below->cavities[j], layer.carvable, options);
        if (needs.empty()) continue;
        // Resource guard: big real slices hold hundreds of minima; each costs a scan at every
        // bridge angle. Tens of thousands come from hostile or broken meshes only.
        minima += needs.size();
        if (minima > kMaxMinimaPerLayer)
            throw InputError(fmt::format(
                "layer {} (z = {:.2f} mm): more than {} local minima of the cavities need "
                "bridges; the mesh is too finely broken up to carve (simplify or repair it)",
                layer.index, layer.z, kMaxMinimaPerLayer));
        // The minima of the cavities before this one leave it first: its bridges span it
        // without them. (Its minima do not depend on it: they lie in the erosion of C^j
        // below, which theirs do not meet.) The others leave it at the end.
        if (!bridged.empty()) out.cavities[j] = exchange(out.cavities[j], bridged, j, j);
        const Paths holes = empty_holes(out.cavities[j]);
        const std::vector<BBox2> piece_boxes = path_bounds(out.cavities[j]);
        for (const Paths& need : needs) {
            // The report bridges its islands only, and says the edge-like minima, narrow strips
            // reaching into the cavity, seldom endanger a print. One that stays within
            // edge_hold of the cavity's wall below hangs no further from it than the ribs let
            // anything hang: no bridge (on the skull x1.43, report scheme, 97 % of 7,198
            // bridges were edge-like).
            if (options.edge_hold > 0 &&
                std::abs(area(intersect(need, holes))) <= 0.5 * std::abs(area(need))) {
                const BBox2 b = bounds(need);
                const Coord m = options.edge_hold + options.line_width;
                const BBox2 near{b.min_x - m, b.min_y - m, b.max_x + m, b.max_y + m, false};
                const Paths below_near = clip_to_box(
                    paths_meeting(below->cavities[j], path_bounds(below->cavities[j]), near), near);
                const Paths deep = intersect(need, erode(below_near, options.edge_hold));
                if (std::abs(area(deep)) <
                    options.min_area_r2 * double(options.dilation) * double(options.dilation)) {
                    ++out.minima_found;
                    ++out.minima_held_by_wall;
                    continue;
                }
            }
            // The lines run across the cavity with the minimum filled in, wall to wall. Lines
            // longer than max_length are dropped anyway, so the scan only needs the part of the
            // cavity around the minimum: large cavities would make every angle costly. The
            // cavity is cut to that window by a box clip rather than a boolean.
            const BBox2 b0 = bounds(need);
            const Coord m = options.max_length;
            const BBox2 w{b0.min_x - m, b0.min_y - m, b0.max_x + m, b0.max_y + m, false};
            const Paths span =
                unite(options.prune ? clip_to_box(paths_meeting(out.cavities[j], piece_boxes, w), w)
                                    : out.cavities[j],
                      need);
            ++out.minima_found;
            bool whole = true;
            for (Bridge& b : plan_bridges(need, span, options, whole)) {
                b.cavity = static_cast<int>(j) + 1;
                // An island fills (mostly) an empty hole of C^j; an edge-like minimum does not.
                b.island =
                    std::abs(area(intersect(b.region, holes))) > 0.5 * std::abs(area(b.region));
                bridged.add(j, b.region);
                out.bridges.push_back(std::move(b));
            }
            // What no bridge within a printable span reaches is left to hang on its own: a
            // longer span sags worse than the small minimum it would hold (counted). But a
            // minimum no deeper than a line width inside the cavity below (a sliver along a
            // wall, from a tear a little faster than r) is held by that wall: each line over
            // it overhangs the line below by less than its width, a 63-degree slope at the
            // defaults.
            if (!whole) {
                const Paths below_near = clip_to_box(
                    paths_meeting(below->cavities[j], path_bounds(below->cavities[j]), w), w);
                const Paths deep = intersect(need, erode(below_near, options.line_width));
                if (std::abs(area(deep)) <
                    options.min_area_r2 * double(options.dilation) * double(options.dilation))
                    ++out.minima_held_by_wall;
                else {
                    ++out.minima_unsupported;
                    out.unheld.push_back({need, false});
                }
            }
        }
    }
    add_cover_bridges(out, layer, *below, options);
    if (bridged.empty()) return out;
    // The minima join their cavity in this slice: nothing is printed over the void but the
    // bridge, and the slice above rests on the bridge. Each cavity and the remainder change
    // once, for all the minima (big slices hold hundreds), and only near them.
    for (size_t j = 0; j < out.cavities.size(); ++j)
        out.cavities[j] = exchange(out.cavities[j], bridged, j, j + 1);
    out.remainder = exchange(out.remainder, bridged, 0, 0);
    // So does what each iteration had left, V^{j-1} = C^j ∪ .. ∪ C^k ∪ V^k: it gains the minima
    // of C^j .. C^k and loses the others. The toolpaths read V^{j-1} and V^j from it.
    for (size_t j = 1; j < out.uncarved.size(); ++j)
        out.uncarved[j] = exchange(out.uncarved[j], bridged, j, out.cavities.size());
    return out;
}

BridgeStage::BridgeStage(LayerSource& input, const Settings& settings)
    : input_(input), options_(bridge_options(settings)) {}

std::optional<LayerRecord> BridgeStage::next() {
    auto carved = [](std::optional<LayerPartition> layer) -> std::shared_ptr<const LayerPartition> {
        if (!layer) return nullptr;
        return std::make_shared<const LayerPartition>(std::move(*layer));
    };
    if (!started_) {
        started_ = true;
        pending_ = carved(input_.next());
    }
    if (!pending_) return std::nullopt;
    std::shared_ptr<const LayerPartition> below = carved(input_.next());
    StageTimer timer(Stage::kBridges);
    LayerRecord out;
    out.bridged = bridge_layer(*pending_, below.get(), options_);
    out.carved = std::exchange(pending_, std::move(below));
    return out;
}

}  // namespace carve

// The ribs' work on one slice alone or on two slices' own regions (see ribs.hpp): the options,
// each slice's empty, deep and printed regions, its overlap with the slice above, and the
// clipping of the pieces RibPlanner::add() placed. None of it waits for the serial planner.
#include <algorithm>
#include <cmath>

#include "base/stage_timer.hpp"
#include "geometry/lines.hpp"
#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"
#include "supports/ribs.hpp"

namespace carve {

RibOptions rib_options(const Settings& settings) {
    RibOptions o;
    o.enabled = settings.rib_reach > 0;
    o.line_width = settings.line_width();
    o.lean = settings.dilation_per_layer();
    o.reach = to_units(settings.rib_reach);
    o.spacing = to_units(settings.rib_spacing);
    o.piece = std::max<Coord>(2 * o.line_width, to_units(settings.rib_piece));
    // Three lattice spacings: on the shared models rib material fell by half to two thirds
    // against none (fandisk 516 -> 216 mm3, skull 415 -> 132), and little more at five.
    o.attract = 3 * o.spacing;
    o.vaults.enabled = o.enabled && settings.vault_width > 0;
    o.vaults.line_width = o.line_width;
    o.vaults.lean = o.lean;
    // Lines twice the lattice's reach apart hold every point as near as the lattice does.
    o.vaults.hold = static_cast<Coord>(std::llround(double(o.spacing) / std::sqrt(2.0)));
    o.vaults.wide = std::max<Coord>(1, to_units(settings.vault_width) / 2);
    o.vaults.rib_spacing = o.spacing;
    o.vaults.rib_piece = o.piece;
    return o;
}

std::vector<BridgeAbove> bridges_above(const BridgedPartition& bridged) {
    std::vector<BridgeAbove> out;
    for (const Bridge& b : bridged.bridges) {
        // The way its longest segment runs (its lines may be one zig-zag).
        double best = 0, dx = 0, dy = 0;
        for (const Path& l : b.lines)
            for (size_t i = 0; i + 1 < l.size(); ++i) {
                const double d = distance(l[i], l[i + 1]);
                if (d > best)
                    best = d, dx = double(l[i + 1].X - l[i].X) / d,
                    dy = double(l[i + 1].Y - l[i].Y) / d;
            }
        if (best > 0) out.push_back({b.region, dx, dy});
    }
    return out;
}

RibSlice rib_slice(const LayerRecord& layer, const RibOptions& options) {
    RibSlice out;
    if (!options.enabled) return out;
    StageTimer timer(Stage::kRibs);
    const Coord w = options.line_width;
    // Each cavity less half a line width (its wall's half inside it; cavities touch along the
    // walls between them, so each is eroded alone) and less its bridge lines.
    Paths empty;
    for (const Paths& c : layer.bridged.cavities) {
        if (c.empty()) continue;
        Paths e = erode(c, w / 2);
        empty.insert(empty.end(), std::make_move_iterator(e.begin()),
                     std::make_move_iterator(e.end()));
    }
    Paths bridge_lines;
    for (const Bridge& b : layer.bridged.bridges)
        bridge_lines.insert(bridge_lines.end(), b.lines.begin(), b.lines.end());
    if (!empty.empty()) empty = unite(empty);
    if (!bridge_lines.empty() && !empty.empty()) {
        out.unbridged = empty;
        empty = subtract(empty, dilate_lines(bridge_lines, w / 2));
    }
    if (!empty.empty()) out.deep = erode(empty, options.reach);
    const Paths& outline = layer.partition().outline;
    out.printed = empty.empty() ? outline : subtract(outline, empty);
    if (!empty.empty()) out.wall_line = erode(outline, w / 2);
    out.empty = std::move(empty);
    return out;
}

void rib_overlap(RibSlice& slice, const RibAbove& above) {
    StageTimer timer(Stage::kRibs);
    // What the slice above prints deep in this one's empty region (deep lies inside empty: one
    // boolean, not two).
    if (above.above && !slice.empty.empty() && above.printed && !above.printed->empty() &&
        !slice.deep.empty())
        slice.hang = intersect(*above.printed, slice.deep);
    slice.bridges_above.clear();
    if (!slice.hang.empty()) {
        const BBox2 box = bounds(slice.hang);
        for (const BridgeAbove& b : above.bridges)
            if (overlap(box, bounds(b.region))) slice.bridges_above.push_back(b);
    }
    slice.unheld_deep.clear();
    for (const UnheldMinimum& u : above.unheld)
        slice.unheld_deep.push_back(
            {slice.empty.empty() ? Paths{} : intersect(u.region, slice.deep), u.ceiling});
}

LayerRibs clip_ribs(LayerRibs ribs, const RibSlice& slice, const RibOptions& options) {
    if (ribs.lines.empty() && ribs.ties.empty() && ribs.vaults.empty()) return ribs;
    StageTimer timer(Stage::kRibs);
    Paths kept;
    for (Path& l : clip_lines(ribs.lines, slice.empty))
        if (length(Paths{l}, false) >= double(options.line_width)) kept.push_back(std::move(l));
    ribs.lines = std::move(kept);
    // Each tie keeps its part from the rib to the first thing printed it meets, and goes on
    // into that line by half a width so that the two fuse: the rib is joined to the wall.
    const Coord w = options.line_width;
    Paths ties;
    for (const Path& t : ribs.ties) {
        // A fading tie's free end (its front) may lie on what this slice prints (a cover's
        // top under it): the tie is then the part from its rib, at the back, to that. Dropped
        // whole, it left the slice above's tie over nothing.
        const bool from_back = !point_in_region(t.front(), slice.tie_region()) &&
                               point_in_region(t.back(), slice.tie_region());
        const Point from = from_back ? t.back() : t.front();
        const Paths parts = clip_lines(Paths{t}, slice.tie_region());
        const Path* best = nullptr;
        double best_d = double(w);
        Point far;
        for (const Path& p : parts) {
            if (p.size() < 2) continue;
            for (const bool front : {true, false}) {
                const double d = distance(front ? p.front() : p.back(), from);
                if (d < best_d) best_d = d, best = &p, far = front ? p.back() : p.front();
            }
        }
        if (!best) continue;
        if (distance(from, far) < double(w) / 2) continue;
        // Past the empty region a band may lie that prints nothing (a cover band too narrow to
        // fill, along a slope): the tie goes on to the outer wall's line.
        const Point end = past_the_edge(from, far, slice.wall_line, w);
        ties.push_back(Path{from, end});
    }
    // Ties run along each other and over the pieces where ribs pair up or tie in a row: each
    // spot printed once (flat_box, layer 30: 2,007 mm of rib lines covered what 1,404 mm
    // print). The pieces stay whole: each rib stands on its own piece of the slice below. The
    // ties are trimmed against them and each other, longest first, so that a row of ties is
    // one line and the short ones end on it. Trimmed within half a width only: what is taken
    // off a tie lies under the line that took it, and a cut end, even one facing another cut
    // end, fuses with it. No stub is dropped, however short: the part of a tie past a cut may
    // be all that joins what cut it to the tie's own target, and through it the wall.
    std::sort(ties.begin(), ties.end(), [](const Path& a, const Path& b) {
        return distance(a.front(), a.back()) > distance(b.front(), b.back());
    });
    LineSet printed(w / 2, 0);
    for (const Path& l : ribs.lines) printed.keep(l);
    for (const Path& l : ribs.vaults) printed.keep(l);
    ribs.ties.clear();
    for (const Path& t : ties)
        for (Path& p : printed.add(t)) ribs.ties.push_back(std::move(p));
    return ribs;
}

}  // namespace carve

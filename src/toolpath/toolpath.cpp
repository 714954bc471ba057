// plan_layer: from a layer's partition to its print paths, in print order (report section 4).
// Its stages are the functions numbered 1. to 6. below, called in that order at the end of the
// file; the order of the islands and of the paths within each is in islands.cpp.
//
// Geometry conventions (see partition.hpp): the boundary of wall_region is the outer wall's
// centreline, the boundary of shell_paths_region the innermost shell's, and in single-filament
// mode every cavity boundary is a centreline too. So walls are plain boundary loops, and only
// the solid cover lines need an inset (to sit beside the innermost wall, not on it).
#include "toolpath/toolpath.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <numbers>
#include <optional>

#include "base/stage_timer.hpp"
#include "carving/carving.hpp"
#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"
#include "toolpath/comb.hpp"
#include "toolpath/fill.hpp"
#include "toolpath/islands.hpp"
#include "toolpath/seam.hpp"
#include "toolpath/thin_walls.hpp"
#include "toolpath/walls.hpp"

namespace carve {

namespace {

// Cover lines overlap the innermost wall by this fraction of a line width, for adhesion.
constexpr double kCoverOverlap = 0.15;
// Half the narrowest strip of a cover band that gets a line of its own, in line widths.
constexpr double kThinGap = 0.2;

void add_loops(const Paths& region, Feature feature, int cavity, double min_length,
               std::vector<Extrusion>& out) {
    for (const Path& loop : clean(region, kSimplify)) {
        if (length(Paths{loop}, true) < min_length) continue;
        Extrusion e;
        e.feature = feature;
        e.points = loop;
        e.closed = true;
        e.cavity = cavity;
        out.push_back(std::move(e));
    }
}

// Polylines as they come from a stage (ribs, support walls): a line that ends where it starts is
// a closed loop.
void add_lines(const Paths& lines, Feature feature, std::vector<Extrusion>& out) {
    for (const Path& l : lines) {
        if (l.size() < 2) continue;
        Extrusion e;
        e.feature = feature;
        e.points = l;
        e.closed = l.size() > 2 && l.front() == l.back();
        if (e.closed) e.points.pop_back();
        out.push_back(std::move(e));
    }
}

// The single wall of a cavity (report 4.1): the boundary of the cavity opened by s', where it
// lies at least t inside V^{j-1} (`uncarved`).
void add_cavity_walls(const Paths& cavity, const Paths& uncarved, const Settings& settings,
                      int index, double min_length, std::vector<Extrusion>& out) {
    const Paths smoothed = clean(open(simplify(cavity, kSimplify), settings.opening()), kSimplify);
    for (WallPiece& piece :
         loops_inside_erosion(smoothed, uncarved, settings.restriction(),
                              to_units(settings.wall_extension_mm()), min_length)) {
        Extrusion e;
        e.feature = Feature::CavityWall;
        e.points = std::move(piece.points);
        e.closed = piece.closed;
        e.cavity = index;
        out.push_back(std::move(e));
    }
}

// The clusters of `region` (see clusters()) whose boxes meet one of `boxes`, as one region;
// their boxes go to `met` if given.
Paths clusters_meeting(const Paths& region, const std::vector<BBox2>& boxes,
                       std::vector<BBox2>* met = nullptr) {
    Paths out;
    for (Paths& cluster : clusters(region)) {
        const BBox2 b = bounds(cluster);
        if (std::none_of(boxes.begin(), boxes.end(), [&](const BBox2& o) { return overlap(o, b); }))
            continue;
        if (met) met->push_back(b);
        std::move(cluster.begin(), cluster.end(), std::back_inserter(out));
    }
    return out;
}

// Supports (supports/support_volume.hpp): the interface as dense lines across the body's walls,
// the body as its outline and walls along x every kSupportSpacing, at the same places on every
// layer so that they stack. The interface's lowest layer bridges between those walls.
constexpr double kSupportSpacingMm = 2.5;

std::vector<Extrusion> support_paths(const LayerSupport& support, const Settings& settings) {
    std::vector<Extrusion> out;
    add_lines(support.walls, Feature::Support, out);
    if (support.region.empty()) return out;
    const Coord s = settings.nozzle_radius(), w = settings.line_width();
    const Paths body =
        support.interface.empty() ? support.region : subtract(support.region, support.interface);
    const Paths inner = erode(body, s);
    add_loops(inner, Feature::Support, 0, 2.0 * double(w), out);
    if (!inner.empty()) {
        const BBox2 b = bounds(inner);
        const Coord pitch = to_units(kSupportSpacingMm);
        Paths lines;
        const Coord first = (b.min_y / pitch) * pitch;
        for (Coord y = first; y <= b.max_y; y += pitch)
            if (y > b.min_y) lines.push_back(Path{Point(b.min_x - w, y), Point(b.max_x + w, y)});
        for (Path& l : clip_lines(lines, inner)) {
            if (l.size() < 2 || length(Paths{l}, false) < double(w)) continue;
            Extrusion e;
            e.feature = Feature::Support;
            e.points = std::move(l);
            out.push_back(std::move(e));
        }
    }
    if (!support.interface.empty()) {
        std::vector<Extrusion> dense =
            fill_solid(erode(support.interface, s), 90.0, 2 * w, Feature::SupportInterface);
        for (Extrusion& e : dense) out.push_back(std::move(e));
    }
    return out;
}

// 1. Outer wall (C^0) and shells.
struct WallPaths {
    std::vector<Extrusion> outer, shells;
    // Seams: the outer wall is what the user sees, so its loops start where the seam mode puts
    // them; everything else starts where the nozzle is.
    bool placed_seams = false;
    double unprinted_mm2 = 0;  // of the slice, narrower than the narrowest part printed
    Paths corridors;           // along the thin walls' beads (ThinWalls::corridors)
};

// The region inside the innermost wall's centreline.
const Paths& innermost_wall(const LayerPartition& layer, const Settings& settings) {
    return (layer.shell_paths_region.empty() && settings.shells == 0) ? layer.wall_region
                                                                      : layer.shell_paths_region;
}

WallPaths wall_paths(const LayerPartition& layer, const Paths& inner, const Settings& settings) {
    const Coord w = settings.line_width();
    WallPaths out;
    std::vector<Extrusion>& outer = out.outer;
    ThinWalls thin = thin_walls(layer.outline, layer.wall_region, settings);
    out.unprinted_mm2 = thin.unprinted_mm2;
    out.corridors = std::move(thin.corridors);
    add_loops(thin.wall_region, Feature::OuterWall, 0, double(w), outer);
    out.placed_seams = settings.seam != SeamMode::Nearest;
    if (out.placed_seams)
        for (size_t k = 0; k < outer.size(); ++k) {
            Path& p = outer[k].points;
            const size_t v = seam_vertex(p, settings.seam, layer.index, k, Point(0, 0));
            std::rotate(p.begin(), p.begin() + static_cast<std::ptrdiff_t>(v), p.end());
        }
    for (Extrusion& e : thin.beads) outer.push_back(std::move(e));
    for (int k = 1; k <= settings.shells; ++k) {
        const Paths region = k == settings.shells ? inner : erode(layer.wall_region, k * w);
        add_loops(region, Feature::Shell, 0, double(w), out.shells);
    }
    return out;
}

// 2. Covers. The cavity walls of C^1 keep t away from the boundary of the carvable part, as
// if a wall ran on it (single filament: on it; double walls: half a width outside it, where
// the cavities' own walls begin). Solid lines keep w - overlap from the innermost wall and
// from that edge. The edge itself is printed only along bands wide enough to hold lines:
// there it is the cover's outline, which ties the line ends together. Along a thin band (a
// steep slope: the shift over `covers` layers is under 2 (w - overlap)) it would only be a
// second perimeter doing what the walls of the layers above and below already do, and on
// the shared models it was two thirds of all cover material (cat: 1,410 of 452 + 958
// mm3). CuraEngine drops its skin and skin outline there too (skin removal width). What such a
// band leaves between the wall's bead and the layers' common part gets one line (see below).
struct CoverPaths {
    std::vector<Extrusion> edges, lines;
};

CoverPaths cover_paths(const LayerPartition& layer, const BridgedPartition& bridged,
                       const Paths& inner, const Settings& settings) {
    const Coord s = settings.nozzle_radius();
    const Coord w = settings.line_width();
    const double min_length = 2.0 * double(w);
    CoverPaths out;
    if (layer.covers.empty()) return out;
    std::vector<Extrusion>& cover_edges = out.edges;
    std::vector<Extrusion>& cover_lines = out.lines;
    const Coord overlap = static_cast<Coord>(std::llround(kCoverOverlap * double(w)));
    const Coord keep_off = w - overlap;
    Paths fill;
    if (!layer.carvable.empty()) {
        const bool single = settings.walls == WallMode::Single;
        const Paths edge = single ? layer.carvable : dilate(layer.carvable, s);
        // Lines at least keep_off from the innermost wall and from the edge. With single
        // walls the edge is the carvable part's boundary and covers = inner \ carvable, so
        // that is erode(inner) ∩ covers \ dilate(carvable) = erode(covers): erosion
        // distributes over intersection and the element is symmetric. One erosion of the
        // cover band instead of three operations on the whole slice; on organic models
        // most layers have only a thin band along sloping walls, which erodes away.
        fill = single ? erode(layer.covers, keep_off)
                      : subtract(intersect(layer.covers, erode(inner, keep_off)),
                                 dilate(edge, keep_off));
        if (!fill.empty()) {
            // The edge runs keep_off from the lines it outlines; t further, so that the
            // erosion by t inside loops_inside_erosion leaves that reach.
            const Coord t = settings.restriction();
            const Paths outlined = intersect(inner, dilate(fill, keep_off + s + t));
            for (WallPiece& piece :
                 loops_inside_erosion(clean(edge, kSimplify), outlined, t, 0, min_length)) {
                Extrusion e;
                e.feature = Feature::Cover;
                e.points = std::move(piece.points);
                e.closed = piece.closed;
                cover_edges.push_back(std::move(e));
            }
        }
    } else {
        fill = intersect(layer.covers, erode(inner, keep_off));
    }
    // Where the cover bridges a cavity below, its bridge lines take the place of these.
    Paths cover_bridges;
    for (const Bridge& b : bridged.bridges)
        if (b.cover) cover_bridges.insert(cover_bridges.end(), b.lines.begin(), b.lines.end());
    if (!cover_bridges.empty() && !fill.empty())
        fill = subtract(fill, dilate_lines(cover_bridges, w));
    const double angle = (layer.index % 2 == 0) ? 45.0 : -45.0;
    cover_lines = fill_solid(fill, angle, w, Feature::Cover);
    // What of the band lies beyond the innermost wall's reach and no line of the cover covers:
    // strips too thin for two lines (on slopes), the ends of bands too short for a line. One
    // line along each, as wide as the strip; strips narrower than 2 kThinGap are left (a bead
    // that thin does not print). Within s of the carvable part the band is no surface: the
    // slices `covers` above and below all hold it (each holds the carvable part eroded by s).
    // So what needs covering is the band eroded by s on both sides: erode(covers, s).
    Paths gap = erode(layer.covers, s);
    if (gap.empty()) return out;
    Paths printed = std::move(cover_bridges);
    for (const std::vector<Extrusion>* group : {&cover_edges, &cover_lines})
        for (const Extrusion& e : *group) {
            printed.push_back(e.points);
            if (e.closed && !e.points.empty()) printed.back().push_back(e.points.front());
        }
    if (!printed.empty()) gap = subtract(gap, dilate_lines(printed, s));
    const Coord narrowest = static_cast<Coord>(std::llround(2 * kThinGap * double(w)));
    for (Extrusion& e : fill_thin(open(gap, narrowest / 2), w, overlap, narrowest, Feature::Cover))
        cover_lines.push_back(std::move(e));
    return out;
}

// 3. Cavity walls, C^1 .. C^k in the order they were modelled (4.2). Each is restricted to
// V^{j-1}, what was left before its iteration, and opened only near V^j, what it left.
std::vector<std::vector<Extrusion>> cavity_wall_paths(const BridgedPartition& bridged,
                                                      const Settings& settings) {
    const Coord s = settings.nozzle_radius();
    const Coord w = settings.line_width();
    const double min_length = 2.0 * double(w);
    std::vector<std::vector<Extrusion>> cavity_walls(bridged.cavities.size());
    auto level = [&](size_t j) -> const Paths& {  // V^j
        return j < bridged.uncarved.size() ? bridged.uncarved[j] : bridged.remainder;
    };
    for (size_t j = 0; j < bridged.cavities.size(); ++j) {
        const Paths& cavity = bridged.cavities[j];
        if (cavity.empty()) continue;
        const int index = static_cast<int>(j) + 1;
        if (settings.walls == WallMode::Double) {
            add_loops(open(erode(cavity, s), settings.opening()), Feature::CavityWall, index,
                      min_length, cavity_walls[j]);
            continue;
        }
        const Paths& uncarved = level(j);  // V^{j-1}
        const Coord opening = settings.opening();
        if (opening >= settings.restriction()) {
            add_cavity_walls(cavity, uncarved, settings, index, min_length, cavity_walls[j]);
            continue;
        }
        // Every wall point lies within s' of V^j, what the cavity leaves of V^{j-1}: a point
        // of the opened cavity's boundary is within s' of the cavity's boundary (a point
        // further in is inside a disk of radius s' in the cavity), and where that boundary is
        // V^{j-1}'s, within s' < t of it, which the restriction drops. So only the cavity's
        // clusters near V^j are opened, and only V^{j-1}'s clusters holding them are eroded; a
        // cavity that took all of V^{j-1} has no wall. On fandisk that spares most of the
        // openings.
        std::vector<BBox2> reach;
        for (const Path& p : level(j + 1)) {
            if (area(p) <= 0) continue;  // a hole's box lies in its outer's
            BBox2 b = bounds(p);
            const Coord m = opening + 2;  // and Clipper's rounding
            reach.push_back({b.min_x - m, b.min_y - m, b.max_x + m, b.max_y + m, false});
        }
        std::vector<BBox2> near_boxes;
        const Paths near = clusters_meeting(cavity, reach, &near_boxes);
        if (!near.empty())
            add_cavity_walls(near, clusters_meeting(uncarved, near_boxes), settings, index,
                             min_length, cavity_walls[j]);
    }
    return cavity_walls;
}

// 4. What the k iterations left uncarved (V^k) is solid model: its boundary is the last
// cavities' walls, so it is filled like a cover inside them. Left empty it would be a void
// whose top nothing holds. With the defaults it is a few specks; it grows when cavities
// open slowly (the tear limit) or when --cavities is small.
std::vector<Extrusion> remainder_lines(int layer_index, const BridgedPartition& bridged,
                                       const Settings& settings) {
    const Coord w = settings.line_width();
    std::vector<Extrusion> solid_lines;
    if (!bridged.remainder.empty() && !bridged.cavities.empty()) {
        const Coord overlap = static_cast<Coord>(std::llround(kCoverOverlap * double(w)));
        const double angle = (layer_index % 2 == 0) ? 45.0 : -45.0;
        solid_lines = fill_solid(erode(bridged.remainder, w - overlap), angle, w, Feature::Cover);
        for (Extrusion& e : solid_lines) e.cavity = -1;  // the stats tell it from the covers
    }
    return solid_lines;
}

// 4b. Ties (--ties, issue 49): a square grid of lines at +-45 degrees on fixed coordinates, so
// that each layer's lie on the layer below's and they stack into vertical webs, clipped to the
// carvable part (reaching s past it, onto the wall its boundary is the centreline of). Where a
// line leaves the layer below's carvable part it lies on that layer's cover: nothing of it
// hangs. A lattice's stiffness grows with the material in it, the cavities' walls' barely (they
// lean by the overhang angle and bend), so the ties are what carries load across the hollow.
std::vector<Extrusion> tie_lines(const LayerPartition& layer, const Paths& inner,
                                 const Settings& settings) {
    std::vector<Extrusion> out;
    if (!(settings.tie_spacing > 0) || layer.carvable.empty()) return out;
    const Coord w = settings.line_width();
    // Closer than two widths the lines would merge into a solid.
    const Coord spacing = std::max(to_units(settings.tie_spacing), 2 * w);
    const Paths region = intersect(dilate(layer.carvable, settings.nozzle_radius()), inner);
    if (region.empty()) return out;
    const BBox2 b = bounds(region);
    // The lines x - y = c and x + y = c, c a multiple of spacing * sqrt(2) (their normal
    // distance is the spacing).
    const double step = double(spacing) * std::numbers::sqrt2;
    Paths grid;
    for (const int sign : {-1, 1}) {
        const double lo = sign < 0 ? double(b.min_x - b.max_y) : double(b.min_x + b.min_y);
        const double hi = sign < 0 ? double(b.max_x - b.min_y) : double(b.max_x + b.max_y);
        for (double k = std::ceil(lo / step); k * step <= hi; ++k) {
            const Coord c = static_cast<Coord>(std::llround(k * step));
            // x = c + y (sign -1) or x = c - y (sign +1), from y = min_y - 1 to max_y + 1.
            const Coord y0 = b.min_y - 1, y1 = b.max_y + 1;
            grid.push_back({Point(c - sign * y0, y0), Point(c - sign * y1, y1)});
        }
    }
    const double min_length = 2.0 * double(w);
    for (Path& piece : clip_lines(grid, region)) {
        double length = 0;
        for (size_t n = 1; n < piece.size(); ++n)
            length += std::hypot(double(piece[n].X - piece[n - 1].X),
                                 double(piece[n].Y - piece[n - 1].Y));
        if (length < min_length) continue;
        Extrusion e;
        e.feature = Feature::Tie;
        e.points = std::move(piece);
        out.push_back(std::move(e));
    }
    return out;
}

// 6. Travel between the paths (issue #18): inside the island without retraction where it
// can, retracted and through the islands where it must leave. Planned here, on the worker
// threads; only the travel into the layer is left to the G-code stage.
void plan_travels(LayerToolpaths& result, const LayerPartition& layer, const Paths& corridors,
                  const Settings& settings) {
    const Coord s = settings.nozzle_radius();
    const Coord w = settings.line_width();
    result.comb_region = comb_region(layer.wall_region, layer.covers, settings);
    const Comber comber(result.comb_region);
    // Where the comb region fails (thin parts), the region inside the outer wall's
    // centreline, built only if needed; not with Combing::Inside, which keeps off covers.
    std::optional<Comber> thin;
    const bool use_thin = settings.combing == Combing::All;
    if (use_thin)
        result.thin_region =
            corridors.empty() ? layer.wall_region : unite(layer.wall_region, corridors);
    const TravelOptions options = travel_options(settings);
    auto exit_of = [](const Extrusion& e) { return e.closed ? e.points.front() : e.points.back(); };
    // Between two support paths the nozzle travels through the air beside the model, round
    // it, without retracting: a string on a support is cut off with it (CuraEngine does
    // the same), and a support layer is many short paths.
    std::optional<Comber> air;
    auto is_support = [](const Extrusion& e) {
        return e.feature == Feature::Support || e.feature == Feature::SupportInterface;
    };
    result.travels.resize(result.extrusions.size());
    Point at = exit_of(result.extrusions.front());
    for (size_t i = 1; i < result.extrusions.size(); ++i) {
        const Extrusion& e = result.extrusions[i];
        if (e.points.size() < 2) continue;  // the G-code stage skips it too
        if (is_support(e) && is_support(result.extrusions[i - 1])) {
            if (!air) {
                Paths all;
                for (size_t k = i - 1; k < result.extrusions.size(); ++k)
                    all.push_back(result.extrusions[k].points);
                const BBox2 b = bounds(all);
                const Coord m = 2 * w;
                const Paths box{
                    Path{Point(b.min_x - m, b.min_y - m), Point(b.max_x + m, b.min_y - m),
                         Point(b.max_x + m, b.max_y + m), Point(b.min_x - m, b.max_y + m)}};
                air.emplace(subtract(box, dilate(layer.outline, s)));
            }
            const Point to = e.points.front();
            std::optional<Path> via;
            if (air->island_of(at) >= 0 && air->island_of(at) == air->island_of(to))
                via = air->visible(at, to) ? std::optional<Path>(Path{}) : air->route(at, to);
            if (via) {
                if (!via->empty()) via->pop_back();  // the route ends at the path's start
                result.travels[i].via = std::move(*via);
                result.travels[i].kind = TravelKind::Inside;
                at = exit_of(e);
                continue;
            }
        }
        TravelPlan t = plan_travel(comber, at, e.points.front(), options);
        if (t.leaves && use_thin) {
            if (!thin) thin.emplace(result.thin_region);
            t = plan_travel(comber, at, e.points.front(), options, &*thin);
        }
        result.travels[i].via = std::move(t.via);
        result.travels[i].kind = t.leaves ? TravelKind::Leaves : TravelKind::Inside;
        at = exit_of(e);
    }
}

}  // namespace

std::string_view feature_name(Feature f) {
    // PrusaSlicer's words: its G-code viewer colours by them, and they read well in Cura's too.
    switch (f) {
        case Feature::OuterWall:
            return "External perimeter";
        case Feature::Shell:
            return "Perimeter";
        case Feature::Cover:
            return "Solid infill";
        case Feature::CavityWall:
            return "Internal infill";
        case Feature::Bridge:
            return "Bridge infill";
        case Feature::Rib:
        case Feature::Tie:
            // Not "Support material": checkers (carve check too) let support stand across a z
            // gap, and ribs stand on the walls inside, so they are measured as the interior is.
            // PrusaSlicer's viewer knows no other word for what is inside; ties are infill too.
            return "Internal infill";
        case Feature::Support:
            return "Support material";
        case Feature::SupportInterface:
            return "Support material interface";
        case Feature::Skirt:
        case Feature::Brim:
            return "Skirt/Brim";  // PrusaSlicer's one word for both
    }
    return "Custom";
}

LayerToolpaths with_islands_reversed(const LayerToolpaths& layer) {
    LayerToolpaths out;
    out.index = layer.index;
    out.z = layer.z;
    out.comb_region = layer.comb_region;
    out.thin_region = layer.thin_region;
    const std::vector<size_t>& starts = layer.island_starts;
    const bool planned = !layer.travels.empty();
    auto take = [&](size_t from, size_t to) {
        for (size_t i = from; i < to && i < layer.extrusions.size(); ++i) {
            out.extrusions.push_back(layer.extrusions[i]);
            // The travel into an island came from the island printed before it, no longer so.
            if (planned) out.travels.push_back(i == from ? Travel{} : layer.travels[i]);
        }
    };
    for (size_t g = starts.size(); g-- > 1;) take(starts[g - 1], starts[g]);
    take(starts.empty() ? 0 : starts.back(), layer.extrusions.size());
    return out;
}

LayerToolpaths plan_layer(const LayerRecord& record, const Settings& settings) {
    StageTimer timer(Stage::kToolpaths);
    const LayerPartition& layer = record.partition();
    const BridgedPartition& bridged = record.bridged;
    LayerToolpaths result;
    result.index = layer.index;
    result.z = settings.layer_top_mm(layer.index);

    const Paths& inner = innermost_wall(layer, settings);
    WallPaths walls = wall_paths(layer, inner, settings);  // 1.
    result.unprinted_mm2 = walls.unprinted_mm2;
    CoverPaths covers = cover_paths(layer, bridged, inner, settings);                         // 2.
    std::vector<std::vector<Extrusion>> cavity_walls = cavity_wall_paths(bridged, settings);  // 3.
    std::vector<Extrusion> solid_lines = remainder_lines(layer.index, bridged, settings);     // 4.
    std::vector<Extrusion> ties = tie_lines(layer, inner, settings);                          // 4b.

    // 5. Order, island by island (an island: a connected piece of the model's slice O_i). The
    // report's order C^0, C^1 .. C^k matters only between touching contours (4.2: a small
    // contour may rest on nothing but a contour of an earlier cavity it touches), so it is kept
    // within each island, while islands, which touch nothing of each other, are printed one
    // after the other: the nozzle leaves each island once instead of once per group. Within a
    // group, nearest neighbour; the next island is the one whose first path is nearest.
    const Paths& shape = layer.outline.empty() ? layer.wall_region : layer.outline;
    LayerIslands islands(shape, settings.line_width(), cavity_walls.size());
    islands.distribute(walls.outer, &Island::outer);
    islands.distribute(walls.shells, &Island::shells);
    // The cover's edge and lines support nothing of each other: one group, less travel.
    for (Extrusion& e : covers.lines) covers.edges.push_back(std::move(e));
    islands.distribute(covers.edges, &Island::covers);
    islands.distribute_cavity_walls(cavity_walls);
    islands.distribute(solid_lines, &Island::solid);
    std::vector<Extrusion> ribs;
    add_lines(record.ribs.lines, Feature::Rib, ribs);
    add_lines(record.ribs.ties, Feature::Rib, ribs);
    add_lines(record.ribs.vaults, Feature::Rib, ribs);
    for (Extrusion& e : ties) ribs.push_back(std::move(e));
    islands.distribute(ribs, &Island::ribs);
    islands.distribute_bridges(bridged.bridges);

    // Odd layers start from the opposite corner: a layer then tends to begin in the island
    // where the one below ended, and the travel between layers stays inside.
    BBox2 box = bounds(shape);
    PathSequence sequence(
        layer.index % 2 == 0 ? Point(box.min_x, box.min_y) : Point(box.max_x, box.max_y),
        result.extrusions);
    print_islands(islands, sequence, result.island_starts, walls.placed_seams,
                  settings.bridge_flow);

    // Supports last: nothing of the model rests on them within the layer.
    std::vector<Extrusion> supports = support_paths(record.support, settings);
    if (!supports.empty()) sequence.append(supports);

    // 6. Travel between the paths.
    if (settings.combing != Combing::Off && !result.extrusions.empty())
        plan_travels(result, layer, walls.corridors, settings);
    return result;
}

}  // namespace carve

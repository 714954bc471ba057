// plan_layer: from a layer's partition to its print paths, in print order (report section 4).
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
#include <optional>

#include "base/stage_timer.hpp"
#include "carving/carving.hpp"
#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"
#include "toolpath/comb.hpp"
#include "toolpath/fill.hpp"
#include "toolpath/order.hpp"
#include "toolpath/seam.hpp"
#include "toolpath/walls.hpp"

namespace carve {

namespace {

// Cover lines overlap the innermost wall by this fraction of a line width, for adhesion.
constexpr double kCoverOverlap = 0.15;

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
    for (WallPiece& piece : loops_inside_erosion(smoothed, uncarved, settings.restriction(),
                                                 to_units(settings.wall_extension), min_length)) {
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

// Bridges keep their line order (the supports stage chose it); only which bridge comes next
// and the direction of each line are chosen for short travel.
std::vector<Extrusion> order_bridges(const std::vector<Bridge>& bridges, double flow, Point& pos) {
    std::vector<Extrusion> out;
    std::vector<char> done(bridges.size(), 0);
    auto d2 = [](const Point& a, const Point& b) {
        const double dx = double(a.X - b.X), dy = double(a.Y - b.Y);
        return dx * dx + dy * dy;
    };
    for (size_t round = 0; round < bridges.size(); ++round) {
        size_t best = bridges.size();
        double best_d = std::numeric_limits<double>::max();
        for (size_t b = 0; b < bridges.size(); ++b) {
            if (done[b]) continue;
            for (const Path& line : bridges[b].lines) {
                if (line.empty()) continue;
                const double d = std::min(d2(pos, line.front()), d2(pos, line.back()));
                if (d < best_d) best_d = d, best = b;
                break;  // entered through its first line
            }
        }
        if (best == bridges.size()) break;
        done[best] = 1;
        for (const Path& line : bridges[best].lines) {
            if (line.size() < 2) continue;
            Extrusion e;
            e.feature = Feature::Bridge;
            e.points = line;
            e.flow = flow;
            e.cavity = bridges[best].cavity;
            if (d2(pos, line.back()) < d2(pos, line.front()))
                std::reverse(e.points.begin(), e.points.end());
            pos = e.points.back();
            out.push_back(std::move(e));
        }
    }
    return out;
}

// Above this many islands in a layer (a plate of many parts) they are ordered by one greedy
// pass from the first: the searches below grow as the cube.
constexpr size_t kTourIslands = 64;

// An open path through islands 0..k-1 (gaps[a][b]: the gap between a and b) crossing little
// outside the model: a travel from one island to the next crosses at least their gap, and the
// nozzle need not come back to the first. The best greedy nearest-gap path over every start,
// then 2-opt.
std::vector<size_t> island_tour(const std::vector<std::vector<double>>& gaps) {
    const size_t k = gaps.size();
    std::vector<size_t> best;
    double best_cost = std::numeric_limits<double>::max();
    const size_t starts = k <= kTourIslands ? k : 1;
    for (size_t first = 0; first < starts; ++first) {
        std::vector<size_t> tour{first};
        std::vector<char> used(k, 0);
        used[first] = 1;
        double cost = 0;
        while (tour.size() < k) {
            size_t next = k;
            for (size_t j = 0; j < k; ++j)
                if (!used[j] && (next == k || gaps[tour.back()][j] < gaps[tour.back()][next]))
                    next = j;
            cost += gaps[tour.back()][next];
            used[next] = 1;
            tour.push_back(next);
        }
        if (cost < best_cost) best_cost = cost, best = std::move(tour);
    }
    // Reversing best[i..j] changes only the gaps at its ends (an end of the path has none).
    auto gap = [&](size_t a, size_t b) { return a < k && b < k ? gaps[best[a]][best[b]] : 0.0; };
    for (bool improved = k <= kTourIslands; improved;) {
        improved = false;
        for (size_t i = 0; i + 1 < k; ++i)
            for (size_t j = i + 1; j < k; ++j) {
                const size_t before = i > 0 ? i - 1 : k, after = j + 1;
                if (gap(before, j) + gap(i, after) + 1 < gap(before, i) + gap(j, after)) {
                    std::reverse(best.begin() + std::ptrdiff_t(i),
                                 best.begin() + std::ptrdiff_t(j + 1));
                    improved = true;
                }
            }
    }
    return best;
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
            // Not "Support material": checkers (carve check too) let support stand across a z
            // gap, and ribs stand on the walls inside, so they are measured as the interior is.
            return "Internal infill";
        case Feature::Support:
            return "Support material";
        case Feature::SupportInterface:
            return "Support material interface";
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
    result.z = (layer.index + 1) * settings.layer_height;

    const Coord s = settings.nozzle_radius();
    const Coord w = settings.line_width();
    const double min_length = 2.0 * double(w);

    // 1. Outer wall (C^0) and shells.
    std::vector<Extrusion> outer, shells;
    add_loops(layer.wall_region, Feature::OuterWall, 0, double(w), outer);
    // Seams: the outer wall is what the user sees, so its loops start where the seam mode puts
    // them; everything else starts where the nozzle is.
    const bool placed_seams = settings.seam != SeamMode::Nearest;
    if (placed_seams)
        for (size_t k = 0; k < outer.size(); ++k) {
            Path& p = outer[k].points;
            const size_t v = seam_vertex(p, settings.seam, layer.index, k, Point(0, 0));
            std::rotate(p.begin(), p.begin() + static_cast<std::ptrdiff_t>(v), p.end());
        }
    const Paths& inner = (layer.shell_paths_region.empty() && settings.shells == 0)
                             ? layer.wall_region
                             : layer.shell_paths_region;
    for (int k = 1; k <= settings.shells; ++k) {
        const Paths region = k == settings.shells ? inner : erode(layer.wall_region, k * w);
        add_loops(region, Feature::Shell, 0, double(w), shells);
    }

    // 2. Covers. The cavity walls of C^1 keep t away from the boundary of the carvable part, as
    // if a wall ran on it (single filament: on it; double walls: half a width outside it, where
    // the cavities' own walls begin). Solid lines keep w - overlap from the innermost wall and
    // from that edge. The edge itself is printed only along bands wide enough to hold lines:
    // there it is the cover's outline, which ties the line ends together. Along a thin band (a
    // steep slope: the shift over `covers` layers is under 2 (w - overlap)) it would only be a
    // second perimeter doing what the walls of the layers above and below already do, and on
    // the shared models it was two thirds of all cover material (cat: 1,410 of 452 + 958
    // mm3). CuraEngine drops its skin and skin outline there too (skin removal width).
    std::vector<Extrusion> cover_edges, cover_lines;
    if (!layer.covers.empty()) {
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
    }

    // 3. Cavity walls, C^1 .. C^k in the order they were modelled (4.2). Each is restricted to
    // V^{j-1}, what was left before its iteration, and opened only near V^j, what it left.
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

    // What the k iterations left uncarved (V^k) is solid model: its boundary is the last
    // cavities' walls, so it is filled like a cover inside them. Left empty it would be a void
    // whose top nothing holds. With the defaults it is a few specks; it grows when cavities
    // open slowly (the tear limit) or when --cavities is small.
    std::vector<Extrusion> solid_lines;
    if (!bridged.remainder.empty() && !bridged.cavities.empty()) {
        const Coord overlap = static_cast<Coord>(std::llround(kCoverOverlap * double(w)));
        const double angle = (layer.index % 2 == 0) ? 45.0 : -45.0;
        solid_lines = fill_solid(erode(bridged.remainder, w - overlap), angle, w, Feature::Cover);
        for (Extrusion& e : solid_lines) e.cavity = -1;  // the stats tell it from the covers
    }

    // 5. Order, island by island (an island: a connected piece of the model's slice O_i). The
    // report's order C^0, C^1 .. C^k matters only between touching contours (4.2: a small
    // contour may rest on nothing but a contour of an earlier cavity it touches), so it is kept
    // within each island, while islands, which touch nothing of each other, are printed one
    // after the other: the nozzle leaves each island once instead of once per group. Within a
    // group, nearest neighbour; the next island is the one whose first path is nearest.
    const Paths& shape = layer.outline.empty() ? layer.wall_region : layer.outline;
    // Most layers are one island: then no index is built and nothing is looked up.
    const size_t outers = static_cast<size_t>(
        std::count_if(shape.begin(), shape.end(), [](const Path& p) { return area(p) > 0; }));
    std::optional<Comber> index;
    if (outers > 1) index.emplace(shape);
    const size_t island_count = index ? size_t(index->islands()) : outers;
    struct Island {
        std::vector<Extrusion> outer, shells, covers, solid, ribs;
        std::vector<std::vector<Extrusion>> cavities;
        std::vector<Bridge> bridges;
    };
    std::vector<Island> islands(island_count + 1);  // the last: unplaced
    auto island_at = [&](const Point& p) {
        if (!index) return size_t(0);
        const auto l = index->locate(p, w);
        return l ? size_t(l->island) : islands.size() - 1;
    };
    auto distribute = [&](std::vector<Extrusion>& group, auto member) {
        for (Extrusion& e : group) {
            if (e.points.empty()) continue;
            (islands[island_at(e.points.front())].*member).push_back(std::move(e));
        }
    };
    distribute(outer, &Island::outer);
    distribute(shells, &Island::shells);
    // The cover's edge and lines support nothing of each other: one group, less travel.
    for (Extrusion& e : cover_lines) cover_edges.push_back(std::move(e));
    distribute(cover_edges, &Island::covers);
    for (Island& isl : islands) isl.cavities.resize(cavity_walls.size());
    for (size_t j = 0; j < cavity_walls.size(); ++j)
        for (Extrusion& e : cavity_walls[j])
            if (!e.points.empty())
                islands[island_at(e.points.front())].cavities[j].push_back(std::move(e));
    distribute(solid_lines, &Island::solid);
    std::vector<Extrusion> ribs;
    add_lines(record.ribs.lines, Feature::Rib, ribs);
    distribute(ribs, &Island::ribs);
    for (const Bridge& b : bridged.bridges) {
        const auto first =
            std::find_if(b.lines.begin(), b.lines.end(), [](const Path& l) { return !l.empty(); });
        if (first != b.lines.end()) islands[island_at(first->front())].bridges.push_back(b);
    }

    // Odd layers start from the opposite corner: a layer then tends to begin in the island
    // where the one below ended, and the travel between layers stays inside.
    BBox2 box = bounds(shape);
    Point pos = layer.index % 2 == 0 ? Point(box.min_x, box.min_y) : Point(box.max_x, box.max_y);
    auto append = [&](std::vector<Extrusion>& group, bool keep_loop_starts = false) {
        const Point start = pos;
        order_nearest(group, pos, keep_loop_starts);
        improve_order(group, start, pos, keep_loop_starts);
        // A path of fewer than two points prints nothing (the G-code stage skipped it); gone,
        // an island's first path is one that prints.
        for (Extrusion& e : group)
            if (e.points.size() >= 2) result.extrusions.push_back(std::move(e));
    };
    auto d2 = [](const Point& a, const Point& b) {
        const double dx = double(a.X - b.X), dy = double(a.Y - b.Y);
        return dx * dx + dy * dy;
    };
    // Distance from the nozzle to where an island would start: its outer wall's seams if it has
    // an outer wall, else its first path.
    auto entry_distance = [&](const Island& isl) {
        double best = std::numeric_limits<double>::max();
        for (const Extrusion& e : isl.outer) best = std::min(best, d2(pos, e.points.front()));
        if (!isl.outer.empty()) return best;
        for (const auto* group : {&isl.shells, &isl.covers, &isl.solid, &isl.ribs})
            for (const Extrusion& e : *group) best = std::min(best, d2(pos, e.points.front()));
        for (const auto& group : isl.cavities)
            for (const Extrusion& e : group) best = std::min(best, d2(pos, e.points.front()));
        for (const Bridge& b : isl.bridges)
            for (const Path& l : b.lines)
                if (!l.empty()) best = std::min(best, d2(pos, l.front()));
        return best;
    };
    auto print_island = [&](Island& isl) {
        append(isl.outer, placed_seams);
        append(isl.shells);
        append(isl.covers);
        for (auto& group : isl.cavities) append(group);
        append(isl.solid);
        // Ribs stand on the layer below like the walls; the bridges of this layer do not need
        // them (they hold the layer above).
        append(isl.ribs);
        // Bridges last: they hang over the cavity below, anchored on the walls just printed.
        for (Extrusion& e : order_bridges(isl.bridges, settings.bridge_flow, pos))
            if (e.points.size() >= 2) result.extrusions.push_back(std::move(e));
    };
    // The islands in the order that crosses the least outside the model (issue #18: the gaps
    // between islands were most of the travel outside: cat's legs, man's arms), from the end
    // nearer the corner; the G-code stage may reverse it (LayerToolpaths::island_starts).
    std::vector<size_t> order;
    for (size_t k = 0; k + 1 < islands.size(); ++k)
        if (entry_distance(islands[k]) < std::numeric_limits<double>::max()) order.push_back(k);
    if (order.size() > 1) {
        std::vector<std::vector<double>> gaps(order.size(), std::vector<double>(order.size(), 0));
        for (size_t a = 0; a < order.size(); ++a)
            for (size_t b = a + 1; b < order.size(); ++b)
                gaps[a][b] = gaps[b][a] = index->gap(int(order[a]), int(order[b]));
        // What a travel from one to another crosses: it may step through the islands between
        // (plan_travel), so the least sum of gaps over any way, not the direct gap.
        for (size_t m = 0; m < (order.size() <= kTourIslands ? order.size() : 0); ++m)
            for (size_t a = 0; a < order.size(); ++a)
                for (size_t b = 0; b < order.size(); ++b)
                    gaps[a][b] = std::min(gaps[a][b], gaps[a][m] + gaps[m][b]);
        std::vector<size_t> tour = island_tour(gaps);
        for (size_t& t : tour) t = order[t];
        if (entry_distance(islands[tour.back()]) < entry_distance(islands[tour.front()]))
            std::reverse(tour.begin(), tour.end());
        order = std::move(tour);
    }
    for (size_t k : order) {
        result.island_starts.push_back(result.extrusions.size());
        print_island(islands[k]);
    }
    result.island_starts.push_back(result.extrusions.size());
    // An island whose paths all printed nothing is no island to start in.
    result.island_starts.erase(
        std::unique(result.island_starts.begin(), result.island_starts.end()),
        result.island_starts.end());
    if (result.island_starts.size() < 3) result.island_starts.clear();
    print_island(islands.back());  // paths of no island

    // Supports last: nothing of the model rests on them within the layer.
    std::vector<Extrusion> supports = support_paths(record.support, settings);
    if (!supports.empty()) append(supports);

    // 6. Travel between the paths (issue #18): inside the island without retraction where it
    // can, retracted and through the islands where it must leave. Planned here, on the worker
    // threads; only the travel into the layer is left to the G-code stage.
    if (settings.combing != Combing::Off && !result.extrusions.empty()) {
        result.comb_region = comb_region(layer.wall_region, layer.covers, settings);
        const Comber comber(result.comb_region);
        // Where the comb region fails (thin parts), the region inside the outer wall's
        // centreline, built only if needed; not with Combing::Inside, which keeps off covers.
        std::optional<Comber> thin;
        const bool use_thin = settings.combing == Combing::All;
        if (use_thin) result.thin_region = layer.wall_region;
        const TravelOptions options = travel_options(settings);
        auto exit_of = [](const Extrusion& e) {
            return e.closed ? e.points.front() : e.points.back();
        };
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
                if (!thin) thin.emplace(layer.wall_region);
                t = plan_travel(comber, at, e.points.front(), options, &*thin);
            }
            result.travels[i].via = std::move(t.via);
            result.travels[i].kind = t.leaves ? TravelKind::Leaves : TravelKind::Inside;
            at = exit_of(e);
        }
    }
    return result;
}

}  // namespace carve

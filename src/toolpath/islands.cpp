// The islands of a layer: the paths sorted into them, the order they are printed in, and the
// order within each (see islands.hpp).
#include "toolpath/islands.hpp"

#include <algorithm>
#include <iterator>
#include <limits>

#include "geometry/polygon.hpp"
#include "toolpath/order.hpp"

namespace carve {

namespace {

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

double d2(const Point& a, const Point& b) {
    const double dx = double(a.X - b.X), dy = double(a.Y - b.Y);
    return dx * dx + dy * dy;
}

}  // namespace

double entry_distance(const Island& isl, const Point& pos) {
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
}

LayerIslands::LayerIslands(const Paths& shape, Coord w, size_t cavity_count) : w_(w) {
    const size_t outers = static_cast<size_t>(
        std::count_if(shape.begin(), shape.end(), [](const Path& p) { return area(p) > 0; }));
    if (outers > 1) index_.emplace(shape);
    const size_t island_count = index_ ? size_t(index_->islands()) : outers;
    islands_.resize(island_count + 1);
    for (Island& isl : islands_) isl.cavities.resize(cavity_count);
}

size_t LayerIslands::island_at(const Point& p) const {
    if (!index_) return size_t(0);
    const auto l = index_->locate(p, w_);
    return l ? size_t(l->island) : islands_.size() - 1;
}

void LayerIslands::distribute(std::vector<Extrusion>& group,
                              std::vector<Extrusion> Island::*member) {
    for (Extrusion& e : group) {
        if (e.points.empty()) continue;
        (islands_[island_at(e.points.front())].*member).push_back(std::move(e));
    }
}

void LayerIslands::distribute_cavity_walls(std::vector<std::vector<Extrusion>>& cavity_walls) {
    for (size_t j = 0; j < cavity_walls.size(); ++j)
        for (Extrusion& e : cavity_walls[j])
            if (!e.points.empty())
                islands_[island_at(e.points.front())].cavities[j].push_back(std::move(e));
}

void LayerIslands::distribute_bridges(const std::vector<Bridge>& bridges) {
    for (const Bridge& b : bridges) {
        const auto first =
            std::find_if(b.lines.begin(), b.lines.end(), [](const Path& l) { return !l.empty(); });
        if (first != b.lines.end()) islands_[island_at(first->front())].bridges.push_back(b);
    }
}

// The islands in the order that crosses the least outside the model (issue #18: the gaps
// between islands were most of the travel outside: cat's legs, man's arms), from the end
// nearer the corner; the G-code stage may reverse it (LayerToolpaths::island_starts).
// Beyond kTourIslands island_tour() goes nearest first from the first island and improves
// nothing, so the gaps are read once each from the island last added: computed then, they need
// no k x k table (10,000 build items of a 3MF: 800 MB a layer, 1.7 GB on two threads, issue
// #38). The same gaps in the same order of comparison: the same tour.
std::vector<size_t> LayerIslands::nearest_island_tour(const std::vector<size_t>& order) const {
    const size_t k = order.size();
    auto gap = [&](size_t a, size_t b) {
        return a < b ? index_->gap(int(order[a]), int(order[b]))
                     : index_->gap(int(order[b]), int(order[a]));
    };
    std::vector<size_t> tour{0};
    tour.reserve(k);
    std::vector<char> used(k, 0);
    used[0] = 1;
    while (tour.size() < k) {
        size_t next = k;
        double next_gap = 0;
        for (size_t j = 0; j < k; ++j) {
            if (used[j]) continue;
            const double g = gap(tour.back(), j);
            if (next == k || g < next_gap) next = j, next_gap = g;
        }
        used[next] = 1;
        tour.push_back(next);
    }
    for (size_t& t : tour) t = order[t];
    return tour;
}

std::vector<size_t> LayerIslands::print_order(const Point& pos) const {
    std::vector<size_t> order;
    for (size_t k = 0; k + 1 < islands_.size(); ++k)
        if (entry_distance(islands_[k], pos) < std::numeric_limits<double>::max())
            order.push_back(k);
    if (order.size() > kTourIslands) {
        order = nearest_island_tour(order);
        if (entry_distance(islands_[order.back()], pos) <
            entry_distance(islands_[order.front()], pos))
            std::reverse(order.begin(), order.end());
    } else if (order.size() > 1) {
        std::vector<std::vector<double>> gaps(order.size(), std::vector<double>(order.size(), 0));
        for (size_t a = 0; a < order.size(); ++a)
            for (size_t b = a + 1; b < order.size(); ++b)
                gaps[a][b] = gaps[b][a] = index_->gap(int(order[a]), int(order[b]));
        // What a travel from one to another crosses: it may step through the islands between
        // (plan_travel), so the least sum of gaps over any way, not the direct gap.
        for (size_t m = 0; m < (order.size() <= kTourIslands ? order.size() : 0); ++m)
            for (size_t a = 0; a < order.size(); ++a)
                for (size_t b = 0; b < order.size(); ++b)
                    gaps[a][b] = std::min(gaps[a][b], gaps[a][m] + gaps[m][b]);
        std::vector<size_t> tour = island_tour(gaps);
        for (size_t& t : tour) t = order[t];
        if (entry_distance(islands_[tour.back()], pos) <
            entry_distance(islands_[tour.front()], pos))
            std::reverse(tour.begin(), tour.end());
        order = std::move(tour);
    }
    return order;
}

void PathSequence::append(std::vector<Extrusion>& group, bool keep_loop_starts) {
    const Point start = pos_;
    order_nearest(group, pos_, keep_loop_starts);
    improve_order(group, start, pos_, keep_loop_starts);
    for (Extrusion& e : group)
        if (e.points.size() >= 2) out_.push_back(std::move(e));
}

void PathSequence::print_island(Island& isl, bool placed_seams, double bridge_flow) {
    append(isl.outer, placed_seams);
    append(isl.shells);
    append(isl.covers);
    for (auto& group : isl.cavities) append(group);
    append(isl.solid);
    // Ribs stand on the layer below like the walls; the bridges of this layer do not need
    // them (they hold the layer above).
    append(isl.ribs);
    // Bridges last: they hang over the cavity below, anchored on the walls just printed.
    for (Extrusion& e : order_bridges(isl.bridges, bridge_flow, pos_))
        if (e.points.size() >= 2) out_.push_back(std::move(e));
}

void print_islands(LayerIslands& islands, PathSequence& sequence,
                   std::vector<size_t>& island_starts, bool placed_seams, double bridge_flow) {
    for (size_t k : islands.print_order(sequence.pos())) {
        island_starts.push_back(sequence.size());
        sequence.print_island(islands[k], placed_seams, bridge_flow);
    }
    island_starts.push_back(sequence.size());
    // An island whose paths all printed nothing is no island to start in.
    island_starts.erase(std::unique(island_starts.begin(), island_starts.end()),
                        island_starts.end());
    if (island_starts.size() < 3) island_starts.clear();
    sequence.print_island(islands.unplaced(), placed_seams, bridge_flow);  // paths of no island
}

}  // namespace carve

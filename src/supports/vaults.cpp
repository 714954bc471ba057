// Vault lines under wide ceilings (see vaults.hpp): seeded as a lattice of parallel chords of
// the cavity, carried down slice by slice, merging in pairs.
#include "supports/vaults.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <map>
#include <numbers>
#include <tuple>

#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"

namespace carve {

namespace {

constexpr double kWallReach = 1500.0;  // how far past the empty region an end looks for the wall

bool overlaps(const Chord& c, const std::vector<Chord>& extent, double tolerance) {
    for (const Chord& e : extent)
        if (c.to >= e.from - tolerance && c.from <= e.to + tolerance) return true;
    return false;
}

// Offsets of lattice lines spaced `spacing` across `part` in the frame (dx, dy), centred on it:
// n lines hold a band n spacings wide, which covers the part's extent.
std::vector<double> lattice_offsets(const Paths& part, double dx, double dy, double spacing) {
    double lo = std::numeric_limits<double>::max(), hi = std::numeric_limits<double>::lowest();
    for (const Path& p : part)
        for (const Point& q : p) {
            const double s = -dy * double(q.X) + dx * double(q.Y);
            lo = std::min(lo, s), hi = std::max(hi, s);
        }
    if (lo > hi) return {};
    const long long n = std::max(1LL, static_cast<long long>(std::ceil((hi - lo) / spacing)));
    const double first = (lo + hi) / 2 - double(n - 1) * spacing / 2;
    std::vector<double> out;
    out.reserve(size_t(n));
    for (long long k = 0; k < n; ++k) out.push_back(first + double(k) * spacing);
    return out;
}

// The chords of `room` on each lattice line that cross `part`.
struct Lattice {
    std::vector<double> offsets;
    std::vector<std::vector<Chord>> kept;
    double length = 0;
};

Lattice lattice(const Paths& part, const Paths& room, double dx, double dy, double spacing) {
    Lattice l;
    l.offsets = lattice_offsets(part, dx, dy, spacing);
    const auto across = chords(room, dx, dy, l.offsets);
    const auto inside = chords(part, dx, dy, l.offsets);
    l.kept.resize(l.offsets.size());
    for (size_t k = 0; k < l.offsets.size(); ++k)
        for (const Chord& c : across[k])
            if (overlaps(c, inside[k], 0)) l.kept[k].push_back(c), l.length += c.to - c.from;
    return l;
}

// The unit direction of the longest straight run of `room`'s boundary at least `min_length`
// long whose box meets `box` grown by `margin`; (0, 0) if there is none. A run is consecutive
// edges within 2 degrees of its first: booleans and erosions leave straight walls in pieces.
std::pair<double, double> longest_wall(const Paths& room, const BBox2& box, double margin,
                                       double min_length) {
    const Coord m = static_cast<Coord>(margin);
    const BBox2 near{box.min_x - m, box.min_y - m, box.max_x + m, box.max_y + m, false};
    const double straight = std::cos(2.0 * std::numbers::pi / 180);
    double best = min_length, dx = 0, dy = 0;
    auto consider = [&](const Point& a, const Point& b) {
        const double len = distance(a, b);
        if (len < best) return;
        const BBox2 e{std::min(a.X, b.X), std::min(a.Y, b.Y), std::max(a.X, b.X),
                      std::max(a.Y, b.Y), false};
        if (!overlap(e, near)) return;
        best = len, dx = double(b.X - a.X) / len, dy = double(b.Y - a.Y) / len;
    };
    for (const Path& p : room) {
        const size_t n = p.size();
        if (n < 2) continue;
        size_t start = 0;
        double ux = 0, uy = 0;
        // Two passes round the contour, so a run through its first vertex is seen whole.
        for (size_t k = 0; k < 2 * n; ++k) {
            const Point& a = p[k % n];
            const Point& b = p[(k + 1) % n];
            const double len = distance(a, b);
            if (len <= 0) continue;
            const double ex = double(b.X - a.X) / len, ey = double(b.Y - a.Y) / len;
            if (k == 0 || ex * ux + ey * uy < straight) {
                if (k > 0) consider(p[start % n], a);
                start = k, ux = ex, uy = ey;
            }
            if (k - start >= n) break;
        }
        consider(p[start % n], p[(start + std::min(n, 2 * n - start)) % n]);
    }
    return {dx, dy};
}

}  // namespace

Point past_the_edge(const Point& inside, const Point& edge, const Paths& wall_line, Coord w) {
    const double len = distance(inside, edge);
    if (len <= 0) return edge;
    const double ux = double(edge.X - inside.X) / len, uy = double(edge.Y - inside.Y) / len;
    auto beyond = [&](double by) {
        return Point(edge.X + static_cast<Coord>(std::llround(ux * by)),
                     edge.Y + static_cast<Coord>(std::llround(uy * by)));
    };
    Point end = beyond(double(w) / 2);
    if (!wall_line.empty()) {
        for (const Path& p : clip_lines(Paths{Path{edge, beyond(kWallReach)}}, wall_line))
            if (p.size() >= 2 &&
                (distance(p.front(), edge) <= 2 || distance(p.back(), edge) <= 2)) {
                const Point e = distance(p.front(), edge) <= 2 ? p.back() : p.front();
                if (distance(e, edge) > double(w) / 2) end = e;
            }
    }
    return end;
}

double VaultPlanner::settled(Family& f, long long lo, long long hi) const {
    if (hi - lo == 1) return f.base + double(lo) * double(options_.spacing());
    const auto key = std::make_pair(lo, hi);
    if (const auto it = f.settled.find(key); it != f.settled.end()) return it->second;
    const long long mid = lo + (hi - lo) / 2;
    auto seeded_in = [&](long long a, long long b) {
        const auto it = std::lower_bound(f.seeded.begin(), f.seeded.end(), a);
        return it != f.seeded.end() && *it < b;
    };
    const bool left = seeded_in(lo, mid), right = seeded_in(mid, hi);
    double at;
    if (left && right)
        at = (settled(f, lo, mid) + settled(f, mid, hi)) / 2;
    else if (left)
        at = settled(f, lo, mid);
    else if (right)
        at = settled(f, mid, hi);
    else
        at = f.base + double(lo + hi - 1) / 2 * double(options_.spacing());
    f.settled[key] = at;
    return at;
}

Paths VaultPlanner::print(const VaultRegion& slice, std::vector<Line>& lines) const {
    Paths out;
    const Coord w = options_.line_width;
    const double tolerance = 2.0 * double(options_.lean) + double(w);
    std::vector<std::vector<size_t>> by_family(families_.size());
    for (size_t i = 0; i < lines.size(); ++i) by_family[lines[i].family].push_back(i);
    std::vector<bool> alive(lines.size(), false);
    for (size_t fi = 0; fi < families_.size(); ++fi) {
        std::vector<size_t>& members = by_family[fi];
        if (members.empty()) continue;
        const Family& f = families_[fi];
        std::sort(members.begin(), members.end(),
                  [&](size_t a, size_t b) { return lines[a].at < lines[b].at; });
        std::vector<double> offsets;
        for (const size_t i : members) offsets.push_back(lines[i].at);
        const auto across = chords(slice.room, f.dx, f.dy, offsets);
        for (size_t k = 0; k < members.size(); ++k) {
            Line& l = lines[members[k]];
            std::vector<Chord> kept;
            for (const Chord& c : across[k])
                if (c.to - c.from > double(w) / 2 && overlaps(c, l.extent, tolerance))
                    kept.push_back(c);
            if (kept.empty()) continue;  // the cavity ended under it: it stands on the floor
            alive[members[k]] = true;
            for (const Chord& c : kept) {
                const Point a = chord_point(f.dx, f.dy, l.at, c.from);
                const Point b = chord_point(f.dx, f.dy, l.at, c.to);
                out.push_back(Path{past_the_edge(b, a, slice.wall_line, w),
                                   past_the_edge(a, b, slice.wall_line, w)});
            }
            l.extent = std::move(kept);
        }
    }
    std::vector<Line> left;
    left.reserve(lines.size());
    for (size_t i = 0; i < lines.size(); ++i)
        if (alive[i]) left.push_back(std::move(lines[i]));
    lines = std::move(left);
    return out;
}

std::vector<VaultPlanner::WallDistance> VaultPlanner::wall_distances(
    const VaultRegion& slice) const {
    // Probes at r, 2r, 4r, ... on either side: where the line's extent meets no chord of the
    // room any more, the wall lies between that probe and the one before.
    constexpr int kProbes = 16;
    const double r = double(options_.lean);
    std::vector<WallDistance> out(lines_.size());
    std::vector<std::vector<size_t>> by_family(families_.size());
    for (size_t i = 0; i < lines_.size(); ++i) by_family[lines_[i].family].push_back(i);
    for (size_t fi = 0; fi < families_.size(); ++fi) {
        const std::vector<size_t>& members = by_family[fi];
        if (members.empty()) continue;
        std::vector<std::pair<double, size_t>> probes;  // offset, line * 2 kProbes + probe
        for (size_t m = 0; m < members.size(); ++m)
            for (int side = 0; side < 2; ++side)
                for (int j = 0; j < kProbes; ++j) {
                    const double d = r * double(1LL << j);
                    probes.push_back({lines_[members[m]].at + (side ? d : -d),
                                      (m * 2 + size_t(side)) * kProbes + size_t(j)});
                }
        std::sort(probes.begin(), probes.end());
        std::vector<double> offsets;
        offsets.reserve(probes.size());
        for (const auto& p : probes) offsets.push_back(p.first);
        const auto across = chords(slice.room, families_[fi].dx, families_[fi].dy, offsets);
        for (size_t k = 0; k < probes.size(); ++k) {
            const size_t code = probes[k].second, j = code % kProbes, side = (code / kProbes) % 2;
            const size_t i = members[code / kProbes / 2];
            bool room = false;
            for (const Chord& c : across[k]) room = room || overlaps(c, lines_[i].extent, 0);
            if (room) continue;
            double& d = side ? out[i].plus : out[i].minus;
            d = std::min(d, r * double(1LL << j));
        }
    }
    return out;
}

Paths VaultPlanner::carry(const VaultRegion& slice) {
    if (lines_.empty()) return {};
    const double r = double(options_.lean);
    // Each line's target: the offset where it merges with the line of the other half of its
    // block's parent. A line whose other half has no line left stands for the parent as it is.
    // The blocks of each family's lines, disjoint, in order: whether a block holds a line.
    std::vector<std::vector<std::pair<long long, long long>>> blocks(families_.size());
    for (const Line& l : lines_) blocks[l.family].push_back({l.lo, l.hi});
    for (auto& b : blocks) std::sort(b.begin(), b.end());
    auto any_in = [&](size_t family, long long a, long long b) {
        const auto& v = blocks[family];
        auto it = std::lower_bound(v.begin(), v.end(), std::make_pair(a, a));
        if (it != v.end() && it->first < b) return true;
        return it != v.begin() && std::prev(it)->second > a;
    };
    std::vector<size_t> family_lines(families_.size(), 0);
    for (const Line& l : lines_) ++family_lines[l.family];
    std::vector<double> target(lines_.size());
    std::vector<bool> moving(lines_.size(), false);
    for (size_t i = 0; i < lines_.size(); ++i) {
        Line& l = lines_[i];
        if (family_lines[l.family] > 1) {
            for (int guard = 0; guard < 62; ++guard) {
                const long long size = l.hi - l.lo;
                const long long plo = l.lo - (l.lo % (2 * size)), phi = plo + 2 * size;
                const long long slo = l.lo == plo ? l.hi : plo, shi = l.lo == plo ? phi : l.lo;
                if (any_in(l.family, slo, shi)) {
                    target[i] = settled(families_[l.family], plo, phi);
                    moving[i] = true;
                    break;
                }
                l.lo = plo, l.hi = phi;
            }
        }
    }
    // A line nearer a wall along its family's normal than to where it would merge leans into
    // the wall instead and ends there, as does the last line of a family: under a tall
    // ceiling that line went on alone to the floor.
    const std::vector<WallDistance> walls = wall_distances(slice);
    for (size_t i = 0; i < lines_.size(); ++i) {
        Line& l = lines_[i];
        const WallDistance& wd = walls[i];
        const double wall = std::min(wd.minus, wd.plus);
        if (wall < std::numeric_limits<double>::max() &&
            (!moving[i] || wall < std::abs(target[i] - l.at))) {
            l.at += wd.minus <= wd.plus ? -r : r;
            moving[i] = false;  // draining: it merges with nothing
            continue;
        }
        if (!moving[i]) continue;
        l.at += std::clamp(target[i] - l.at, -r, r);
    }
    // Two halves of a block that both reached its offset go on as one line.
    std::map<std::tuple<size_t, long long, long long>, size_t> arrived;
    for (size_t i = 0; i < lines_.size(); ++i)
        if (moving[i] && std::abs(lines_[i].at - target[i]) < 0.5)
            arrived[{lines_[i].family, lines_[i].lo, lines_[i].hi}] = i;
    std::vector<bool> gone(lines_.size(), false);
    for (const auto& [key, i] : arrived) {
        Line& l = lines_[i];
        const long long size = l.hi - l.lo;
        if (l.lo % (2 * size) != 0 || gone[i]) continue;  // the left half does the merge
        const auto other = arrived.find({l.family, l.hi, l.hi + size});
        if (other == arrived.end()) continue;
        Line& o = lines_[other->second];
        l.extent.insert(l.extent.end(), o.extent.begin(), o.extent.end());
        std::sort(l.extent.begin(), l.extent.end(),
                  [](const Chord& a, const Chord& b) { return a.from < b.from; });
        l.hi = o.hi;
        l.at = target[i];
        gone[other->second] = true;
    }
    std::vector<Line> kept;
    kept.reserve(lines_.size());
    for (size_t i = 0; i < lines_.size(); ++i)
        if (!gone[i]) kept.push_back(std::move(lines_[i]));
    lines_ = std::move(kept);
    Paths out = print(slice, lines_);
    // Families with no line left are dropped, the others renumbered.
    std::vector<size_t> renumber(families_.size(), families_.size());
    std::vector<bool> used(families_.size(), false);
    for (const Line& l : lines_) used[l.family] = true;
    std::vector<Family> families;
    for (size_t fi = 0; fi < families_.size(); ++fi)
        if (used[fi]) renumber[fi] = families.size(), families.push_back(std::move(families_[fi]));
    families_ = std::move(families);
    for (Line& l : lines_) l.family = renumber[l.family];
    return out;
}

Paths VaultPlanner::seed(const VaultRegion& slice, const Paths& hang,
                         const std::vector<BridgeAbove>& above) {
    if (!options_.enabled || hang.empty() || slice.room.empty()) return {};
    const Paths wide = open(hang, options_.wide);
    if (wide.empty()) return {};
    const double spacing = double(options_.spacing());
    // Each part's way: along the longest straight wall of the cavity near it, so that the
    // lines lean into walls parallel to them and end there, and the family thins out across
    // the cavity's narrow side. Unless that runs within 30 degrees of the bridge lines above it
    // (a line beside a parallel vault line sags between its ends): then at right angles to the
    // wall. Near no straight wall, across the bridge lines; under none, the way with the least
    // line to print. Parts that go the same way share one lattice: its lines run wall to
    // wall, and a lattice of each part would print the same chords once for every part they
    // cross (the bladed plate's ceiling, cut into strips by its blades: seven lattices over
    // one cavity). Parts of separate cavities keep lattices of their own, each centred on its
    // cavity's parts, so that copies of an object print alike wherever they stand.
    const double min_wall = 2.0 * spacing;
    const std::vector<Paths> rooms = components(slice.room);
    std::vector<BBox2> room_boxes;
    for (const Paths& r : rooms) room_boxes.push_back(bounds(r));
    // (room, rounded direction) -> its parts
    std::map<std::tuple<size_t, long long, long long>, Paths> ways;
    for (const Paths& part : components(wide)) {
        const BBox2 box = bounds(part);
        size_t room = 0;
        double most = 0;
        for (size_t i = 0; i < rooms.size() && rooms.size() > 1; ++i) {
            if (!overlap(box, room_boxes[i])) continue;
            const double a = std::abs(area(intersect(part, rooms[i])));
            if (a > most) most = a, room = i;
        }
        double bx = 0, by = 0, best = 0;  // the bridge above it
        for (const BridgeAbove& b : above) {
            if (!overlap(box, bounds(b.region))) continue;
            const double a = std::abs(area(intersect(part, b.region)));
            if (a > best) best = a, bx = b.dx, by = b.dy;
        }
        double dx = 1, dy = 0;
        const auto [wx, wy] = longest_wall(slice.room, box, 4 * spacing, min_wall);
        if (wx != 0 || wy != 0) {
            dx = wx, dy = wy;
            if (best > 0 && std::abs(dx * bx + dy * by) > std::cos(std::numbers::pi / 6))
                dx = -wy, dy = wx;
        } else if (best > 0) {
            dx = -by, dy = bx;
        } else {
            double least = 0;
            for (int step = 0; step < 12; ++step) {
                const double t = double(step) * std::numbers::pi / 12;
                const double length =
                    lattice(part, slice.room, std::cos(t), std::sin(t), spacing).length;
                if (step == 0 || length < least) least = length, dx = std::cos(t), dy = std::sin(t);
            }
        }
        // Wall to wall, a vault under a small part in a wide cavity prints more than the ribs
        // would (fandisk: a 14 mm2 part, 146 mm of chords a slice): left to them.
        const double cell = double(options_.rib_spacing);
        const double ribs =
            std::abs(area(part)) / (cell * cell) * (double(options_.rib_piece) + cell);
        if (lattice(part, slice.room, dx, dy, spacing).length > ribs) continue;
        if (dy < 0 || (dy == 0 && dx < 0)) dx = -dx, dy = -dy;  // a line runs both ways
        Paths& group = ways[{room, std::llround(dx * 1e6), std::llround(dy * 1e6)}];
        group.insert(group.end(), part.begin(), part.end());
    }
    std::vector<Line> fresh;
    for (const auto& [way, parts] : ways) {
        const double dx = double(std::get<1>(way)) / 1e6, dy = double(std::get<2>(way)) / 1e6;
        const double norm = std::hypot(dx, dy);
        Family f;
        f.dx = dx / norm, f.dy = dy / norm;
        const Lattice chosen = lattice(parts, slice.room, f.dx, f.dy, spacing);
        f.base = chosen.offsets.empty() ? 0 : chosen.offsets.front();
        const size_t fi = families_.size();
        for (size_t k = 0; k < chosen.offsets.size(); ++k) {
            if (chosen.kept[k].empty()) continue;
            f.seeded.push_back(static_cast<long long>(k));
            Line l;
            l.family = fi;
            l.lo = static_cast<long long>(k), l.hi = l.lo + 1;
            l.at = chosen.offsets[k];
            l.extent = chosen.kept[k];
            fresh.push_back(std::move(l));
        }
        if (!f.seeded.empty()) families_.push_back(std::move(f));
    }
    Paths out = print(slice, fresh);
    for (Line& l : fresh) lines_.push_back(std::move(l));
    return out;
}

}  // namespace carve

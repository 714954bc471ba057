// Ribs under what would hang (see ribs.hpp): seeded on a fixed lattice under the parts of the
// slice above that lie deep inside this slice's cavities, then carried down slice by slice,
// each leaning towards the nearest printed thing until it stands on it. The work on one slice
// alone (its regions, the overlap with the slice above, the clipping) is in rib_slice.cpp.
#include "supports/ribs.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "base/stage_timer.hpp"
#include "geometry/lines.hpp"
#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"

namespace carve {

constexpr double kDirScale = 1024.0;
constexpr double kFarWall = 4.0;  // tie() cells from the wall beyond which it looks further

// Nearest point of a region's boundary to a point, and whether the point lies inside it. The
// paths' boxes let far contours be skipped: a rib is tested against every cavity of a slice.
class WallBoundary {
  public:
    explicit WallBoundary(const Paths& region) : region_(region) {
        boxes_.reserve(region.size());
        for (const Path& p : region) boxes_.push_back(bounds(p));
    }

    struct Hit {
        bool inside = false;
        double distance = 0;
        Point at;
    };

    Hit nearest(const Point& p) const {
        Hit hit;
        hit.inside = point_in_region(p, region_);
        double best2 = std::numeric_limits<double>::max();
        // Nearest contours first by box distance, so that most are skipped.
        std::vector<std::pair<double, size_t>> order;
        order.reserve(region_.size());
        for (size_t i = 0; i < region_.size(); ++i)
            order.push_back({box_distance2(boxes_[i], p), i});
        std::sort(order.begin(), order.end());
        for (const auto& [d2, i] : order) {
            if (d2 > best2) break;
            const Path& path = region_[i];
            for (size_t k = 0; k < path.size(); ++k) {
                const Point& a = path[k];
                const Point& b = path[(k + 1) % path.size()];
                const Point q = closest_on_segment(a, b, p);
                const double dx = double(q.X - p.X), dy = double(q.Y - p.Y);
                const double e2 = dx * dx + dy * dy;
                if (e2 < best2) best2 = e2, hit.at = q;
            }
        }
        hit.distance = region_.empty() ? 0 : std::sqrt(best2);
        return hit;
    }

  private:
    static double box_distance2(const BBox2& b, const Point& p) {
        const double dx =
            p.X < b.min_x ? double(b.min_x - p.X) : (p.X > b.max_x ? double(p.X - b.max_x) : 0);
        const double dy =
            p.Y < b.min_y ? double(b.min_y - p.Y) : (p.Y > b.max_y ? double(p.Y - b.max_y) : 0);
        return dx * dx + dy * dy;
    }

  public:
    static Point closest_on_segment(const Point& a, const Point& b, const Point& p) {
        const double vx = double(b.X - a.X), vy = double(b.Y - a.Y);
        const double len2 = vx * vx + vy * vy;
        if (len2 <= 0) return a;
        double t = (double(p.X - a.X) * vx + double(p.Y - a.Y) * vy) / len2;
        t = std::clamp(t, 0.0, 1.0);
        return Point(a.X + static_cast<Coord>(std::llround(t * vx)),
                     a.Y + static_cast<Coord>(std::llround(t * vy)));
    }

    const Paths& region_;
    std::vector<BBox2> boxes_;
};

namespace {

// Points hashed into square cells, so that a rib looks only at the ribs near it: pairing and
// merging by scanning every other rib made a wide ceiling's lattice quadratic (a 1000 mm cube's
// ceiling seeds some 150,000 ribs).
class PointGrid {
  public:
    explicit PointGrid(double cell) : cell_(cell) {}
    void insert(const Point& p, size_t index) {
        cells_[key(cell_of(p.X), cell_of(p.Y))].push_back(index);
    }
    // `index` in every cell the box from (x0, y0) to (x1, y1) crosses: a line, not a point.
    void insert_box(Coord x0, Coord y0, Coord x1, Coord y1, size_t index) {
        for (long long gx = cell_of(x0); gx <= cell_of(x1); ++gx)
            for (long long gy = cell_of(y0); gy <= cell_of(y1); ++gy)
                cells_[key(gx, gy)].push_back(index);
    }
    // Calls visit(index) for every point inserted within `radius` of p's cell neighbourhood (a
    // superset of those within `radius`).
    template <class Visit>
    void near(const Point& p, double radius, Visit visit) const {
        square(p, static_cast<long long>(std::ceil(radius / cell_)), -1, visit);
    }
    // Calls visit(index) for what lies in the cells exactly `ring` cells from p's (Chebyshev).
    template <class Visit>
    void ring(const Point& p, long long ring, Visit visit) const {
        square(p, ring, ring, visit);
    }

  private:
    // The cells within `reach` of p's, x then y; only those `ring` away unless it is -1.
    template <class Visit>
    void square(const Point& p, long long reach, long long ring, Visit visit) const {
        const long long cx = cell_of(p.X), cy = cell_of(p.Y);
        for (long long gx = cx - reach; gx <= cx + reach; ++gx)
            for (long long gy = cy - reach; gy <= cy + reach; ++gy) {
                if (ring >= 0 && std::max(std::abs(gx - cx), std::abs(gy - cy)) != ring) continue;
                const auto it = cells_.find(key(gx, gy));
                if (it == cells_.end()) continue;
                for (const size_t i : it->second) visit(i);
            }
    }
    long long cell_of(Coord v) const {
        return static_cast<long long>(std::floor(double(v) / cell_));
    }
    static unsigned long long key(long long cx, long long cy) {
        return (static_cast<unsigned long long>(cx) << 32) ^
               static_cast<unsigned long long>(cy & 0xffffffffLL);
    }
    double cell_;
    std::unordered_map<unsigned long long, std::vector<size_t>> cells_;
};

// Disks of `radius` around the points, as one region.
Paths disks(const std::vector<Point>& centres, Coord radius) {
    if (centres.empty() || radius <= 0) return {};
    const Path d = disk(radius);
    Paths all;
    all.reserve(centres.size());
    for (const Point& c : centres) {
        Path p = d;
        for (Point& v : p) v.X += c.X, v.Y += c.Y;
        all.push_back(std::move(p));
    }
    return unite(all);
}

}  // namespace

Path RibPlanner::piece_of(const Node& n) const {
    const double half = double(options_.piece) / 2 / kDirScale;
    const Coord ox = static_cast<Coord>(std::llround(double(n.dir.X) * half));
    const Coord oy = static_cast<Coord>(std::llround(double(n.dir.Y) * half));
    return Path{Point(n.at.X - ox, n.at.Y - oy), Point(n.at.X + ox, n.at.Y + oy)};
}

bool RibPlanner::follows(const Point& before, const Point& after) const {
    return distance(before, after) <= 2.0 * double(options_.lean) + double(options_.line_width);
}

void RibPlanner::follow_wall(Node& n, const WallBoundary& walls) const {
    const Point at = walls.nearest(n.anchor).at;
    if (follows(n.anchor, at)) n.anchor = at;
}

bool RibPlanner::fade_step(Node& n) const {
    // The free end ends r nearer the anchor than it was, wherever the anchor slid along its
    // wall: a wall that recedes as fast as the fade closes must not keep it going.
    const double r = double(options_.lean), w = double(options_.line_width);
    const double d = distance(n.anchor, n.at);
    const double length = std::min(n.fade_length, d) - r;
    if (length <= w / 2 || d <= 0) return false;
    n.at = Point(
        n.anchor.X + static_cast<Coord>(std::llround(double(n.at.X - n.anchor.X) / d * length)),
        n.anchor.Y + static_cast<Coord>(std::llround(double(n.at.Y - n.anchor.Y) / d * length)));
    n.fade_length = length;
    return true;
}

void RibPlanner::start_fade(const Point& free_end, const Point& fixed, long long follow,
                            std::vector<Node>& fading) const {
    Node f;
    f.at = free_end;
    f.anchor = fixed;
    f.target = follow;
    f.fading = true;
    f.fade_length = distance(free_end, fixed);
    if (fade_step(f)) fading.push_back(f);
}

// Each rib is tied to the nearest thing printed on its slice: the wall, or the tie or piece of
// a rib nearer the wall, so the ties make a forest rooted on the walls (lightning infill's
// branches) and each tie is short. A rib keeps what it was tied to above while that is nearly as
// near (a tie that moves stands on the one below); a tie given up fades.
void RibPlanner::tie(std::vector<Node>& nodes, const WallBoundary& boundary,
                     std::vector<Node>& fading) const {
    const double w = double(options_.line_width);
    const double cell = 2.0 * double(options_.spacing);  // further ribs are not looked at
    const double keep = 2.0 * w;
    std::vector<WallBoundary::Hit> wall(nodes.size());
    std::vector<size_t> order(nodes.size());
    for (size_t i = 0; i < nodes.size(); ++i) wall[i] = boundary.nearest(nodes[i].at), order[i] = i;
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
        return wall[a].distance != wall[b].distance ? wall[a].distance < wall[b].distance
                                                    : nodes[a].id < nodes[b].id;
    });
    PointGrid grid(cell);
    std::unordered_map<long long, size_t> placed;
    auto nearest_on = [&](size_t j, const Point& p, Point& q) {
        const Node& o = nodes[j];
        const Path piece = piece_of(o);
        double best = std::numeric_limits<double>::max();
        auto try_segment = [&](const Point& a, const Point& b) {
            const Point c = WallBoundary::closest_on_segment(a, b, p);
            const double d = distance(c, p);
            if (d < best) best = d, q = c;
        };
        try_segment(piece[0], piece[1]);
        if (distance(o.at, o.anchor) > w / 2) try_segment(o.at, o.anchor);
        return best;
    };
    for (const size_t i : order) {
        Node& n = nodes[i];
        long long target = kWall;
        Point at = wall[i].at;
        double best = wall[i].distance;
        grid.near(n.at, cell, [&](size_t j) {
            Point q;
            const double d = nearest_on(j, n.at, q);
            // Within one cell, which the 3 x 3 cells round it always hold: the same ribs
            // wherever the part stands.
            if (d < best && d <= cell) best = d, target = nodes[j].id, at = q;
        });
        // Nothing within a cell and the wall far: a wide cavity's lattice, thinned by the
        // pairing until its ribs stand further apart than a cell. Tied to the wall, every rib
        // printed a tie across the cavity on every slice, each crossing the ribs between
        // (a 1000 mm cube: tie length grew as the cube of its size, the run past 300 s, issue
        // #38). The nearest rib nearer the wall then, however far, ring by ring until no
        // further cell can hold one nearer: the forest stays rooted on the walls, its ties
        // short. Within kFarWall cells of a wall nothing changes.
        if (target == kWall && best > kFarWall * cell) {
            for (long long ring = 0;; ++ring) {
                grid.ring(n.at, ring, [&](size_t j) {
                    Point q;
                    const double d = nearest_on(j, n.at, q);
                    if (d < best) best = d, target = nodes[j].id, at = q;
                });
                // Cells beyond this ring lie further than ring cells away.
                if (double(ring) * cell >= best) break;
            }
        }
        if (n.target != kUntied && n.target != target) {
            double before = std::numeric_limits<double>::max();
            Point q;
            if (n.target == kWall) {
                before = wall[i].distance, q = wall[i].at;
            } else if (const auto it = placed.find(n.target); it != placed.end()) {
                before = nearest_on(it->second, n.at, q);
            }
            if (before <= best + keep) {
                target = n.target, at = q;
            } else {
                // Its far end closes on the rib, which goes on below (what it was tied to may
                // not: a wall can fall away under a cover as a rib can stop).
                start_fade(n.anchor, n.at, n.id, fading);
            }
        }
        // Tied to the same thing still, but to another part of it (the wall it was tied to
        // fell away, a bridge line ended, the rib it is tied to was tied elsewhere and its
        // nearest point jumped along the new tie): the old tie fades. Pivoted round the rib,
        // the tie's far end hung over nothing.
        if (n.target != kUntied && target == n.target && !follows(n.anchor, at))
            start_fade(n.anchor, n.at, n.id, fading);
        n.target = target;
        n.anchor = at;
        n.tied_from = n.at;
        placed[n.id] = i;
        // Registered in every cell its tie and piece cross, for the ribs further out.
        const Path piece = piece_of(n);
        const Coord x0 = std::min({n.at.X, at.X, piece[0].X, piece[1].X});
        const Coord x1 = std::max({n.at.X, at.X, piece[0].X, piece[1].X});
        const Coord y0 = std::min({n.at.Y, at.Y, piece[0].Y, piece[1].Y});
        const Coord y1 = std::max({n.at.Y, at.Y, piece[0].Y, piece[1].Y});
        grid.insert_box(x0, y0, x1, y1, i);
    }
}

RibPlanner::RibPlanner(const RibOptions& options) : options_(options), vaults_(options.vaults) {}

LayerRibs RibPlanner::add(const LayerRecord& layer) {
    if (!options_.enabled) return {};
    RibSlice slice = rib_slice(layer, options_);
    rib_overlap(slice, above_);
    LayerRibs out = clip_ribs(add(layer, slice), slice, options_);
    above_.above = layer.partition().index > 0;
    above_.printed = std::make_shared<const Paths>(std::move(slice.printed));
    above_.unheld = layer.bridged.unheld;
    above_.bridges = bridges_above(layer.bridged);
    return out;
}

// One slice's add(): what its phases share, in the order they run (add() below).
struct RibPlanner::Descent {
    RibPlanner& p;
    const RibSlice& slice;
    LayerRibs& out;
    const Coord w, r;
    // The lattice's reach: a rib holds what lies within rho of it.
    const Coord rho;
    const double attract;
    const WallBoundary boundary;
    // Ties go to the walls, not to this slice's bridge lines: the slice below has no bridge
    // there to hold a tie that ends on one.
    const WallBoundary walls;
    std::vector<WallBoundary::Hit> hits;  // each rib's nearest wall, after seeding
    PointGrid grid;                       // the ribs, after seeding
    PointGrid moved_grid;                 // `moved`, as it grows
    std::vector<size_t> partner;          // each rib's pair, or nodes_.size()
    std::vector<Node> moved;              // the ribs one slice lower
    std::vector<Node> fading;             // the fading ties one slice lower
    std::vector<Node> faded;  // fades carried from the slice above, moved once `moved` is known

    Descent(RibPlanner& planner, const RibSlice& s, LayerRibs& o)
        : p(planner),
          slice(s),
          out(o),
          w(planner.options_.line_width),
          r(planner.options_.lean),
          rho(static_cast<Coord>(std::llround(double(planner.options_.spacing) / std::sqrt(2.0)))),
          attract(double(planner.options_.attract)),
          boundary(s.empty),
          walls(s.tie_region()),
          grid(attract),
          moved_grid(std::max(attract, 4.0 * double(r))) {}

    void seed();
    void seed_lattice(const Paths& hang);
    void pair_up();
    void lower();
    void lower(size_t i);
    void carry_fades();
    void print();
    void hold_minima();
};

// The vaults of the slice above carried down; new ones under the wide parts of what the slice
// above prints deep inside this slice's empty region and nothing holds yet; new ribs under the
// rest.
void RibPlanner::Descent::seed() {
    const VaultRegion vault_region{slice.tie_region(), slice.wall_line};
    out.vaults = p.vaults_.carry(vault_region);
    Paths hang = slice.hang;
    if (hang.empty()) return;
    std::vector<Point> old;
    for (const Node& n : p.nodes_)
        if (!n.fading) old.push_back(n.at);
    if (!hang.empty() && !old.empty()) hang = subtract(hang, disks(old, rho - r));
    // A little past the lines' reach: the disks' polygons leave slivers between lines exactly
    // twice the reach apart.
    const Coord hold = p.options_.vaults.hold + w / 4;
    if (!hang.empty() && !out.vaults.empty()) hang = subtract(hang, dilate_lines(out.vaults, hold));
    if (!hang.empty()) {
        Paths fresh = p.vaults_.seed(vault_region, hang, slice.bridges_above);
        if (!fresh.empty()) {
            hang = subtract(hang, dilate_lines(fresh, hold));
            out.vaults.insert(out.vaults.end(), std::make_move_iterator(fresh.begin()),
                              std::make_move_iterator(fresh.end()));
        }
    }
    const double min_area = 0.5 * double(w) * double(w);
    Paths kept;
    for (const Path& h : hang)
        if (area(h) < 0 || area(h) >= min_area) kept.push_back(h);
    hang = std::move(kept);
    if (!hang.empty() && std::abs(area(hang)) >= min_area) seed_lattice(hang);
}

// New ribs on the lattice's points near `hang` that lie deep enough inside the empty region.
void RibPlanner::Descent::seed_lattice(const Paths& hang) {
    const Paths near = dilate(hang, rho);
    const Coord a = p.options_.spacing;
    // Each piece's lattice starts at its own corner: copies of one part (--copies, a plate of
    // equal parts) get the same ribs wherever they stand.
    for (const Path& outer : near) {
        if (area(outer) <= 0) continue;
        const Paths piece{outer};
        const BBox2 b = bounds(outer);
        for (Coord y = b.min_y; y <= b.max_y; y += a)
            for (Coord x = b.min_x; x <= b.max_x; x += a) {
                const Point at(x, y);
                if (!point_in_region(at, piece) || !point_in_region(at, near)) continue;
                const WallBoundary::Hit h = boundary.nearest(at);
                if (!h.inside || h.distance <= double(r)) continue;
                // The piece runs across the way to the nearest wall: over a bridge, whose lines
                // run wall to wall, it crosses several of them.
                const double dx = double(h.at.X - at.X), dy = double(h.at.Y - at.Y);
                const double len = std::hypot(dx, dy);
                Node n;
                n.id = p.next_id_++;
                n.at = at;
                n.dir = len > 0 ? Point(static_cast<Coord>(std::llround(-dy / len * kDirScale)),
                                        static_cast<Coord>(std::llround(dx / len * kDirScale)))
                                : Point(static_cast<Coord>(kDirScale), 0);
                p.nodes_.push_back(n);
            }
    }
}

// Ribs are paired, nearest pairs first, and each pair leans together: leaning each towards its
// nearest other, a lattice's ties make ribs chase one another in a row at one speed and never
// meet (the flat box kept some 480 ribs down to its floor, 22,000 pieces).
void RibPlanner::Descent::pair_up() {
    const std::vector<Node>& nodes = p.nodes_;
    moved.reserve(nodes.size());
    hits.reserve(nodes.size());
    for (const Node& n : nodes) hits.push_back(boundary.nearest(n.at));
    for (size_t i = 0; i < nodes.size(); ++i) grid.insert(nodes[i].at, i);
    partner.assign(nodes.size(), nodes.size());
    struct Pair {
        double d;
        size_t i, k;
    };
    std::vector<Pair> pairs;
    for (size_t i = 0; i < nodes.size(); ++i) {
        if (nodes[i].fading || !hits[i].inside || hits[i].distance <= double(r)) continue;
        // The ribs near i, in index order as the full scan took them.
        std::vector<size_t> near;
        grid.near(nodes[i].at, attract, [&](size_t k) {
            if (k > i) near.push_back(k);
        });
        std::sort(near.begin(), near.end());
        for (const size_t k : near) {
            if (nodes[k].fading || !hits[k].inside || hits[k].distance <= double(r)) continue;
            const double d = distance(nodes[k].at, nodes[i].at);
            if (d > 0 && d < attract && d < hits[i].distance && d < hits[k].distance)
                pairs.push_back({d, i, k});
        }
    }
    std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) {
        return a.d != b.d ? a.d < b.d : (a.i != b.i ? a.i < b.i : a.k < b.k);
    });
    for (const Pair& pair : pairs)
        if (partner[pair.i] == nodes.size() && partner[pair.k] == nodes.size())
            partner[pair.i] = pair.k, partner[pair.k] = pair.i;
}

// Every rib goes down one slice: it stands on what this slice prints if that lies within r of
// it; else it moves up to r towards it and prints a piece here. A rib nearer another than any
// wall leans towards it instead: the two meet and go on as one (a tree, as lightning infill
// grows), which saves a column.
//
// A tie that cannot go on one slice lower (its rib stood on a wall, merged into another or tied
// elsewhere) would leave the tie above it in the air: it fades instead, its free end moving r a
// slice towards where it was tied, a web whose edge leans like a cavity's wall. Ties go to the
// nearest thing printed, so they are short and so are their fades.
void RibPlanner::Descent::lower() {
    if (slice.empty.empty()) return;
    for (size_t i = 0; i < p.nodes_.size(); ++i) lower(i);
}

void RibPlanner::Descent::lower(size_t i) {
    const std::vector<Node>& nodes = p.nodes_;
    const Node& n = nodes[i];
    const WallBoundary::Hit& h = hits[i];
    if (n.fading) {
        faded.push_back(n);
        return;
    }
    if (!h.inside || h.distance <= double(r)) {  // it stands on this slice
        // Its tie closes on where it stands (a tie to the wall is that short already). On a
        // bridge line of this slice, the fade closes on the wall it runs from.
        if (n.target >= 0) p.start_fade(n.anchor, walls.nearest(n.at).at, kWall, fading);
        return;
    }
    Node m = n;
    bool leaned = false;
    double best = std::min(attract, h.distance);
    size_t other = partner[i];
    if (other < nodes.size()) {
        best = distance(nodes[other].at, n.at);
    } else {
        std::vector<size_t> near;
        grid.near(n.at, best, [&](size_t k) { near.push_back(k); });
        std::sort(near.begin(), near.end());
        for (const size_t k : near) {
            if (nodes[k].fading) continue;
            const double d = distance(nodes[k].at, n.at);
            if (k != i && d > 0 && d < best) best = d, other = k;
        }
    }
    if (other < nodes.size()) {
        const Point& to = nodes[other].at;
        const double step = std::min(double(r), best / 2);
        m.at.X += static_cast<Coord>(std::llround(double(to.X - n.at.X) / best * step));
        m.at.Y += static_cast<Coord>(std::llround(double(to.Y - n.at.Y) / best * step));
        // Not through a wall: the new place must still be clear of what is printed.
        const WallBoundary::Hit g = boundary.nearest(m.at);
        leaned = g.inside && g.distance > double(r);
        if (!leaned) m.at = n.at;
    }
    const double dx = double(h.at.X - n.at.X), dy = double(h.at.Y - n.at.Y);
    if (!leaned) {
        // All the way to the wall if that is nearer than r: a rib that only closed to r of it
        // kept pace with a receding wall, a strand beside it for many layers.
        const double step = std::min(double(r), h.distance);
        m.at.X += static_cast<Coord>(std::llround(dx / h.distance * step));
        m.at.Y += static_cast<Coord>(std::llround(dy / h.distance * step));
    }
    // The piece runs along the nearest wall: where the rib comes to stand on it, the whole
    // piece lies within r of it (one across would stick out over the cavity).
    m.dir = Point(static_cast<Coord>(std::llround(-dy / h.distance * kDirScale)),
                  static_cast<Coord>(std::llround(dx / h.distance * kDirScale)));
    // Ribs that meet go on as one: the one kept is within r of where the other was.
    size_t into = moved.size();
    moved_grid.near(n.at, double(r), [&](size_t k) {
        const Node& o = moved[k];
        if (k < into && distance(o.at, n.at) <= double(r) && distance(o.at, m.at) <= double(r))
            into = k;
    });
    if (into < moved.size()) {
        if (n.target != kUntied) p.start_fade(n.anchor, moved[into].at, moved[into].id, fading);
        return;
    }
    moved_grid.insert(m.at, moved.size());
    moved.push_back(m);
}

// A fade's fixed end follows its wall, or the rib it closes on while that rib goes on.
void RibPlanner::Descent::carry_fades() {
    std::unordered_map<long long, size_t> moved_index;
    for (size_t k = 0; k < moved.size(); ++k) moved_index[moved[k].id] = k;
    for (Node f : faded) {
        if (f.target == kWall) {
            p.follow_wall(f, walls);
        } else {
            size_t o = moved.size();
            if (const auto it = moved_index.find(f.target); it != moved_index.end()) o = it->second;
            if (o == moved.size()) {
                // The rib it closed on merged into another or stood: the nearest rib within
                // reach takes its place, or the wall it stood on.
                double best = 2.0 * double(r) + double(w);
                moved_grid.near(f.anchor, best, [&](size_t k) {
                    const double d = distance(moved[k].at, f.anchor);
                    if (d < best || (d == best && (o == moved.size() || k > o))) best = d, o = k;
                });
                if (o == moved.size()) {
                    const WallBoundary::Hit at = walls.nearest(f.anchor);
                    // A rib that stood deep inside what this slice prints (a wall's tip
                    // pointing down met it): where it stood is printed, so the fade closes on
                    // that. Dropped, every fade closing on it left its tie above in the air (a
                    // 17 mm line on the repro of the rib-fade bug).
                    if (p.follows(f.anchor, at.at)) {
                        f.anchor = at.at;
                    } else if (at.inside) {
                        continue;
                    }
                    f.target = kWall;
                }
            }
            if (o < moved.size()) f.target = moved[o].id, f.anchor = moved[o].at;
        }
        if (p.fade_step(f)) fading.push_back(f);
    }
}

// Each rib's tie and piece, and each fading tie.
void RibPlanner::Descent::print() {
    Paths pieces;
    pieces.reserve(p.nodes_.size());
    for (const Node& n : p.nodes_) {
        if (distance(n.at, n.anchor) > double(w) / 2) out.ties.push_back(Path{n.at, n.anchor});
        if (n.fading) continue;
        pieces.push_back(p.piece_of(n));
    }
    out.lines = std::move(pieces);  // clip_ribs() stops them at the walls
}

// The minima of the slice above that no bridge held: held now if nothing of them deeper than
// `reach` inside this slice's empty region is further than the lattice's reach from a rib
// printed here.
void RibPlanner::Descent::hold_minima() {
    if (slice.unheld_deep.empty()) return;
    std::vector<Point> at;
    for (const Node& n : p.nodes_)
        if (!n.fading) at.push_back(n.at);
    Paths covered = disks(at, rho + r);
    if (!out.vaults.empty())
        covered = unite(covered, dilate_lines(out.vaults, p.options_.vaults.hold + r));
    for (const UnheldMinimum& u : slice.unheld_deep) {
        Paths left = u.region;
        if (!left.empty() && !covered.empty()) left = subtract(left, covered);
        if (std::abs(area(left)) < 0.5 * double(w) * double(w)) {
            ++out.minima_held;
            if (u.ceiling) ++out.ceilings_held;
        }
    }
}

LayerRibs RibPlanner::add(const LayerRecord& layer, const RibSlice& slice) {
    LayerRibs out;
    if (!options_.enabled) return out;
    StageTimer timer(Stage::kRibs);
    if (!has_above_) nodes_.clear(), vaults_.clear();
    Descent d(*this, slice, out);
    if (has_above_ && !slice.empty.empty()) d.seed();
    d.pair_up();
    d.lower();
    d.carry_fades();
    tie(d.moved, d.walls, d.fading);
    for (Node& f : d.fading) d.moved.push_back(f);
    nodes_ = std::move(d.moved);
    d.print();
    d.hold_minima();
    has_above_ = layer.partition().index > 0;
    return out;
}

}  // namespace carve

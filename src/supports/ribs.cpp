// Ribs under what would hang (see ribs.hpp): seeded on a fixed lattice under the parts of the
// slice above that lie deep inside this slice's cavities, then carried down slice by slice,
// each leaning towards the nearest printed thing until it stands on it.
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
    // Calls visit(index) for every point inserted within `radius` of p's cell neighbourhood (a
    // superset of those within `radius`).
    template <class Visit>
    void near(const Point& p, double radius, Visit visit) const {
        const long long reach = static_cast<long long>(std::ceil(radius / cell_));
        const long long cx = cell_of(p.X), cy = cell_of(p.Y);
        for (long long gx = cx - reach; gx <= cx + reach; ++gx)
            for (long long gy = cy - reach; gy <= cy + reach; ++gy) {
                const auto it = cells_.find(key(gx, gy));
                if (it == cells_.end()) continue;
                for (const size_t i : it->second) visit(i);
            }
    }

  private:
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
    auto cell_of = [&](Coord v) { return static_cast<long long>(std::floor(double(v) / cell)); };
    auto key = [](long long cx, long long cy) {
        return (static_cast<unsigned long long>(cx) << 32) ^
               static_cast<unsigned long long>(cy & 0xffffffffLL);
    };
    std::unordered_map<unsigned long long, std::vector<size_t>> grid;
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
        const long long cx = cell_of(n.at.X), cy = cell_of(n.at.Y);
        for (long long gx = cx - 1; gx <= cx + 1; ++gx)
            for (long long gy = cy - 1; gy <= cy + 1; ++gy) {
                const auto it = grid.find(key(gx, gy));
                if (it == grid.end()) continue;
                for (const size_t j : it->second) {
                    Point q;
                    const double d = nearest_on(j, n.at, q);
                    // Within one cell, which the 3 x 3 cells round it always hold: the same
                    // ribs wherever the part stands.
                    if (d < best && d <= cell) best = d, target = nodes[j].id, at = q;
                }
            }
        // Nothing within a cell and the wall far: a wide cavity's lattice, thinned by the
        // pairing until its ribs stand further apart than a cell. Tied to the wall, every rib
        // printed a tie across the cavity on every slice, each crossing the ribs between
        // (a 1000 mm cube: tie length grew as the cube of its size, the run past 300 s, issue
        // #38). The nearest rib nearer the wall then, however far, ring by ring until no
        // further cell can hold one nearer: the forest stays rooted on the walls, its ties
        // short. Within kFarWall cells of a wall nothing changes.
        if (target == kWall && best > kFarWall * cell) {
            for (long long ring = 0;; ++ring) {
                for (long long gx = cx - ring; gx <= cx + ring; ++gx)
                    for (long long gy = cy - ring; gy <= cy + ring; ++gy) {
                        if (std::max(std::abs(gx - cx), std::abs(gy - cy)) != ring) continue;
                        const auto it = grid.find(key(gx, gy));
                        if (it == grid.end()) continue;
                        for (const size_t j : it->second) {
                            Point q;
                            const double d = nearest_on(j, n.at, q);
                            if (d < best) best = d, target = nodes[j].id, at = q;
                        }
                    }
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
        // Tied to the wall still, but to another part of it (the wall it was tied to fell
        // away, or a bridge line ended): the old tie fades.
        if (n.target == kWall && target == kWall && !follows(n.anchor, at))
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
        for (long long gx = cell_of(x0); gx <= cell_of(x1); ++gx)
            for (long long gy = cell_of(y0); gy <= cell_of(y1); ++gy)
                grid[key(gx, gy)].push_back(i);
    }
}

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

RibPlanner::RibPlanner(const RibOptions& options) : options_(options), vaults_(options.vaults) {}

RibSlice rib_slice(const LayerRecord& layer, const RibOptions& options) {
    RibSlice out;
    if (!options.enabled) return out;
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
    StageTimer timer(Stage::kBridges);
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
    StageTimer timer(Stage::kBridges);
    Paths kept;
    for (Path& l : clip_lines(ribs.lines, slice.empty))
        if (length(Paths{l}, false) >= double(options.line_width)) kept.push_back(std::move(l));
    ribs.lines = std::move(kept);
    // Each tie keeps its part from the rib to the first thing printed it meets, and goes on
    // into that line by half a width so that the two fuse: the rib is joined to the wall.
    const Coord w = options.line_width;
    Paths ties;
    for (const Path& t : ribs.ties) {
        const Point from = t.front();
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

LayerRibs RibPlanner::add(const LayerRecord& layer, const RibSlice& slice) {
    LayerRibs out;
    if (!options_.enabled) return out;
    StageTimer timer(Stage::kBridges);
    const Coord w = options_.line_width, r = options_.lean;
    const Paths& empty = slice.empty;

    if (!has_above_) nodes_.clear(), vaults_.clear();
    const Coord rho = static_cast<Coord>(std::llround(double(options_.spacing) / std::sqrt(2.0)));
    const WallBoundary boundary(empty);
    // Ties go to the walls, not to this slice's bridge lines: the slice below has no bridge
    // there to hold a tie that ends on one.
    const WallBoundary walls(slice.tie_region());

    // The vaults of the slice above carried down; new ones under the wide parts of what the
    // slice above prints deep inside this slice's empty region and nothing holds yet; new
    // ribs under the rest.
    const VaultRegion vault_region{slice.tie_region(), slice.wall_line};
    if (has_above_ && !empty.empty()) out.vaults = vaults_.carry(vault_region);
    if (has_above_ && !empty.empty()) {
        Paths hang = slice.hang;
        if (!hang.empty()) {
            std::vector<Point> old;
            for (const Node& n : nodes_)
                if (!n.fading) old.push_back(n.at);
            if (!hang.empty() && !old.empty()) hang = subtract(hang, disks(old, rho - r));
            // A little past the lines' reach: the disks' polygons leave slivers between lines
            // exactly twice the reach apart.
            const Coord hold = options_.vaults.hold + w / 4;
            if (!hang.empty() && !out.vaults.empty())
                hang = subtract(hang, dilate_lines(out.vaults, hold));
            if (!hang.empty()) {
                Paths fresh = vaults_.seed(vault_region, hang, slice.bridges_above);
                if (!fresh.empty()) {
                    hang = subtract(hang, dilate_lines(fresh, hold));
                    out.vaults.insert(out.vaults.end(), std::make_move_iterator(fresh.begin()),
                                      std::make_move_iterator(fresh.end()));
                }
            }
            const double min_area = 0.5 * double(w) * double(w);
            Paths kept;
            for (const Path& p : hang)
                if (area(p) < 0 || area(p) >= min_area) kept.push_back(p);
            hang = std::move(kept);
            if (!hang.empty() && std::abs(area(hang)) >= min_area) {
                const Paths near = dilate(hang, rho);
                const Coord a = options_.spacing;
                // Each piece's lattice starts at its own corner: copies of one part (--copies,
                // a plate of equal parts) get the same ribs wherever they stand.
                for (const Path& outer : near) {
                    if (area(outer) <= 0) continue;
                    const Paths piece{outer};
                    const BBox2 b = bounds(outer);
                    for (Coord y = b.min_y; y <= b.max_y; y += a)
                        for (Coord x = b.min_x; x <= b.max_x; x += a) {
                            const Point p(x, y);
                            if (!point_in_region(p, piece) || !point_in_region(p, near)) continue;
                            const WallBoundary::Hit h = boundary.nearest(p);
                            if (!h.inside || h.distance <= double(r)) continue;
                            // The piece runs across the way to the nearest wall: over a bridge,
                            // whose lines run wall to wall, it crosses several of them.
                            const double dx = double(h.at.X - p.X), dy = double(h.at.Y - p.Y);
                            const double len = std::hypot(dx, dy);
                            Node n;
                            n.id = next_id_++;
                            n.at = p;
                            n.dir =
                                len > 0
                                    ? Point(static_cast<Coord>(std::llround(-dy / len * kDirScale)),
                                            static_cast<Coord>(std::llround(dx / len * kDirScale)))
                                    : Point(static_cast<Coord>(kDirScale), 0);
                            nodes_.push_back(n);
                        }
                }
            }
        }
    }

    // Every rib goes down one slice: it stands on what this slice prints if that lies within
    // r of it; else it moves up to r towards it and prints a piece here.
    // A rib nearer another than any wall leans towards it instead: the two meet and go on as
    // one (a tree, as lightning infill grows), which saves a column.
    std::vector<Node> moved;
    moved.reserve(nodes_.size());
    const double attract = double(options_.attract);
    std::vector<WallBoundary::Hit> hits;
    hits.reserve(nodes_.size());
    for (const Node& n : nodes_) hits.push_back(boundary.nearest(n.at));
    // Ribs are paired, nearest pairs first, and each pair leans together: leaning each towards
    // its nearest other, a lattice's ties make ribs chase one another in a row at one speed and
    // never meet (the flat box kept some 480 ribs down to its floor, 22,000 pieces).
    PointGrid grid(attract);
    for (size_t i = 0; i < nodes_.size(); ++i) grid.insert(nodes_[i].at, i);
    PointGrid moved_grid(std::max(attract, 4.0 * double(r)));
    std::vector<size_t> partner(nodes_.size(), nodes_.size());
    {
        struct Pair {
            double d;
            size_t i, k;
        };
        std::vector<Pair> pairs;
        for (size_t i = 0; i < nodes_.size(); ++i) {
            if (nodes_[i].fading || !hits[i].inside || hits[i].distance <= double(r)) continue;
            // The ribs near i, in index order as the full scan took them.
            std::vector<size_t> near;
            grid.near(nodes_[i].at, attract, [&](size_t k) {
                if (k > i) near.push_back(k);
            });
            std::sort(near.begin(), near.end());
            for (const size_t k : near) {
                if (nodes_[k].fading || !hits[k].inside || hits[k].distance <= double(r)) continue;
                const double d = distance(nodes_[k].at, nodes_[i].at);
                if (d > 0 && d < attract && d < hits[i].distance && d < hits[k].distance)
                    pairs.push_back({d, i, k});
            }
        }
        std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) {
            return a.d != b.d ? a.d < b.d : (a.i != b.i ? a.i < b.i : a.k < b.k);
        });
        for (const Pair& p : pairs)
            if (partner[p.i] == nodes_.size() && partner[p.k] == nodes_.size())
                partner[p.i] = p.k, partner[p.k] = p.i;
    }
    // A tie that cannot go on one slice lower (its rib stood on a wall, merged into another or
    // tied elsewhere) would leave the tie above it in the air: it fades instead, its free end
    // moving r a slice towards where it was tied, a web whose edge leans like a cavity's wall.
    // Ties go to the nearest thing printed, so they are short and so are their fades.
    std::vector<Node> fading;
    std::vector<Node> faded;  // fades carried from the slice above, moved once `moved` is known
    for (size_t i = 0; i < nodes_.size(); ++i) {
        const Node& n = nodes_[i];
        if (empty.empty()) continue;
        const WallBoundary::Hit& h = hits[i];
        if (n.fading) {
            faded.push_back(n);
            continue;
        }
        if (!h.inside || h.distance <= double(r)) {  // it stands on this slice
            // Its tie closes on where it stands (a tie to the wall is that short already).
            // On a bridge line of this slice, the fade closes on the wall it runs from.
            if (n.target >= 0) start_fade(n.anchor, walls.nearest(n.at).at, kWall, fading);
            continue;
        }
        Node m = n;
        bool leaned = false;
        double best = std::min(attract, h.distance);
        size_t other = partner[i];
        if (other < nodes_.size()) {
            best = distance(nodes_[other].at, n.at);
        } else {
            std::vector<size_t> near;
            grid.near(n.at, best, [&](size_t k) { near.push_back(k); });
            std::sort(near.begin(), near.end());
            for (const size_t k : near) {
                if (nodes_[k].fading) continue;
                const double d = distance(nodes_[k].at, n.at);
                if (k != i && d > 0 && d < best) best = d, other = k;
            }
        }
        if (other < nodes_.size()) {
            const Point& to = nodes_[other].at;
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
            // All the way to the wall if that is nearer than r: a rib that only closed to r of
            // it kept pace with a receding wall, a strand beside it for many layers.
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
            if (n.target != kUntied) start_fade(n.anchor, moved[into].at, moved[into].id, fading);
            continue;
        }
        moved_grid.insert(m.at, moved.size());
        moved.push_back(m);
    }
    // A fade's fixed end follows its wall, or the rib it closes on while that rib goes on.
    std::unordered_map<long long, size_t> moved_index;
    for (size_t k = 0; k < moved.size(); ++k) moved_index[moved[k].id] = k;
    for (Node f : faded) {
        if (f.target == kWall) {
            follow_wall(f, walls);
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
                    const Point at = walls.nearest(f.anchor).at;
                    if (!follows(f.anchor, at)) continue;
                    f.target = kWall;
                    f.anchor = at;
                }
            }
            if (o < moved.size()) f.target = moved[o].id, f.anchor = moved[o].at;
        }
        if (fade_step(f)) fading.push_back(f);
    }
    tie(moved, walls, fading);
    for (Node& f : fading) moved.push_back(f);
    nodes_ = std::move(moved);

    Paths pieces;
    pieces.reserve(nodes_.size());
    for (const Node& n : nodes_) {
        if (distance(n.at, n.anchor) > double(w) / 2) out.ties.push_back(Path{n.at, n.anchor});
        if (n.fading) continue;
        pieces.push_back(piece_of(n));
    }
    out.lines = std::move(pieces);  // clip_ribs() stops them at the walls

    // The minima of the slice above that no bridge held: held now if nothing of them deeper
    // than `reach` inside this slice's empty region is further than the lattice's reach from a
    // rib printed here.
    if (!slice.unheld_deep.empty()) {
        std::vector<Point> at;
        for (const Node& n : nodes_)
            if (!n.fading) at.push_back(n.at);
        Paths covered = disks(at, rho + r);
        if (!out.vaults.empty())
            covered = unite(covered, dilate_lines(out.vaults, options_.vaults.hold + r));
        for (const UnheldMinimum& u : slice.unheld_deep) {
            Paths left = u.region;
            if (!left.empty() && !covered.empty()) left = subtract(left, covered);
            if (std::abs(area(left)) < 0.5 * double(w) * double(w)) {
                ++out.minima_held;
                if (u.ceiling) ++out.ceilings_held;
            }
        }
    }

    has_above_ = layer.partition().index > 0;
    return out;
}

}  // namespace carve

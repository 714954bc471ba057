// Ribs under what would hang (see ribs.hpp): seeded on a fixed lattice under the parts of the
// slice above that lie deep inside this slice's cavities, then carried down slice by slice,
// each leaning towards the nearest printed thing until it stands on it.
#include "supports/ribs.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "base/stage_timer.hpp"
#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"

namespace carve {

namespace {

constexpr double kDirScale = 1024.0;

// Nearest point of a region's boundary to a point, and whether the point lies inside it. The
// paths' boxes let far contours be skipped: a rib is tested against every cavity of a slice.
class Boundary {
  public:
    explicit Boundary(const Paths& region) : region_(region) {
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

Coord floor_to(Coord v, Coord step) {
    Coord q = v / step;
    if (q * step > v) --q;
    return q * step;
}

}  // namespace

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
    return o;
}

RibPlanner::RibPlanner(const RibOptions& options) : options_(options) {}

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
    if (!bridge_lines.empty() && !empty.empty())
        empty = subtract(unite(empty), dilate_lines(bridge_lines, w / 2));
    else if (!empty.empty())
        empty = unite(empty);
    if (!empty.empty()) out.deep = erode(empty, options.reach);
    const Paths& outline = layer.partition().outline;
    out.printed = empty.empty() ? outline : subtract(outline, empty);
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
    slice.unheld_deep.clear();
    for (const UnheldMinimum& u : above.unheld)
        slice.unheld_deep.push_back(
            {slice.empty.empty() ? Paths{} : intersect(u.region, slice.deep), u.ceiling});
}

LayerRibs clip_ribs(LayerRibs ribs, const RibSlice& slice, const RibOptions& options) {
    if (ribs.lines.empty()) return ribs;
    StageTimer timer(Stage::kBridges);
    Paths kept;
    for (Path& l : clip_lines(ribs.lines, slice.empty))
        if (length(Paths{l}, false) >= double(options.line_width)) kept.push_back(std::move(l));
    ribs.lines = std::move(kept);
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
    return out;
}

LayerRibs RibPlanner::add(const LayerRecord& layer, const RibSlice& slice) {
    LayerRibs out;
    if (!options_.enabled) return out;
    StageTimer timer(Stage::kBridges);
    const Coord w = options_.line_width, r = options_.lean;
    const Paths& empty = slice.empty;

    if (!has_above_) nodes_.clear();
    const Coord rho = static_cast<Coord>(std::llround(double(options_.spacing) / std::sqrt(2.0)));
    const Boundary boundary(empty);

    // New ribs under what the slice above prints deep inside this slice's empty region.
    if (has_above_ && !empty.empty()) {
        Paths hang = slice.hang;
        if (!hang.empty()) {
            std::vector<Point> old;
            for (const Node& n : nodes_) old.push_back(n.at);
            if (!hang.empty() && !old.empty()) hang = subtract(hang, disks(old, rho - r));
            const double min_area = 0.5 * double(w) * double(w);
            Paths kept;
            for (const Path& p : hang)
                if (area(p) < 0 || area(p) >= min_area) kept.push_back(p);
            hang = std::move(kept);
            if (!hang.empty() && std::abs(area(hang)) >= min_area) {
                const Paths near = dilate(hang, rho);
                const BBox2 b = bounds(near);
                const Coord a = options_.spacing;
                for (Coord y = floor_to(b.min_y, a); y <= b.max_y; y += a)
                    for (Coord x = floor_to(b.min_x, a); x <= b.max_x; x += a) {
                        const Point p(x, y);
                        if (!point_in_region(p, near)) continue;
                        const Boundary::Hit h = boundary.nearest(p);
                        if (!h.inside || h.distance <= double(r)) continue;
                        // The piece runs across the way to the nearest wall: over a bridge,
                        // whose lines run wall to wall, it crosses several of them.
                        const double dx = double(h.at.X - p.X), dy = double(h.at.Y - p.Y);
                        const double len = std::hypot(dx, dy);
                        Node n;
                        n.at = p;
                        n.dir = len > 0
                                    ? Point(static_cast<Coord>(std::llround(-dy / len * kDirScale)),
                                            static_cast<Coord>(std::llround(dx / len * kDirScale)))
                                    : Point(static_cast<Coord>(kDirScale), 0);
                        nodes_.push_back(n);
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
    std::vector<Boundary::Hit> hits;
    hits.reserve(nodes_.size());
    for (const Node& n : nodes_) hits.push_back(boundary.nearest(n.at));
    // Ribs are paired, nearest pairs first, and each pair leans together: leaning each towards
    // its nearest other, a lattice's ties make ribs chase one another in a row at one speed and
    // never meet (the flat box kept some 480 ribs down to its floor, 22,000 pieces).
    std::vector<size_t> partner(nodes_.size(), nodes_.size());
    {
        struct Pair {
            double d;
            size_t i, k;
        };
        std::vector<Pair> pairs;
        for (size_t i = 0; i < nodes_.size(); ++i) {
            if (!hits[i].inside || hits[i].distance <= double(r)) continue;
            for (size_t k = i + 1; k < nodes_.size(); ++k) {
                if (!hits[k].inside || hits[k].distance <= double(r)) continue;
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
    for (size_t i = 0; i < nodes_.size(); ++i) {
        const Node& n = nodes_[i];
        if (empty.empty()) continue;
        const Boundary::Hit& h = hits[i];
        if (!h.inside || h.distance <= double(r)) continue;  // it stands on this slice
        Node m = n;
        bool leaned = false;
        double best = std::min(attract, h.distance);
        size_t other = partner[i];
        if (other < nodes_.size()) {
            best = distance(nodes_[other].at, n.at);
        } else {
            for (size_t k = 0; k < nodes_.size(); ++k) {
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
            const Boundary::Hit g = boundary.nearest(m.at);
            leaned = g.inside && g.distance > double(r);
            if (!leaned) m.at = n.at;
        }
        const double dx = double(h.at.X - n.at.X), dy = double(h.at.Y - n.at.Y);
        if (!leaned) {
            const double step = std::min(double(r), h.distance - double(r));
            m.at.X += static_cast<Coord>(std::llround(dx / h.distance * step));
            m.at.Y += static_cast<Coord>(std::llround(dy / h.distance * step));
        }
        // The piece runs along the nearest wall: where the rib comes to stand on it, the whole
        // piece lies within r of it (one across would stick out over the cavity).
        m.dir = Point(static_cast<Coord>(std::llround(-dy / h.distance * kDirScale)),
                      static_cast<Coord>(std::llround(dx / h.distance * kDirScale)));
        // Ribs that meet go on as one: the one kept is within r of where the other was.
        const bool merged = std::any_of(moved.begin(), moved.end(), [&](const Node& o) {
            return distance(o.at, n.at) <= double(r) && distance(o.at, m.at) <= double(r);
        });
        if (merged) continue;
        moved.push_back(m);
    }
    nodes_ = std::move(moved);

    Paths pieces;
    pieces.reserve(nodes_.size());
    for (const Node& n : nodes_) {
        const double half = double(options_.piece) / 2 / kDirScale;
        const Coord ox = static_cast<Coord>(std::llround(double(n.dir.X) * half));
        const Coord oy = static_cast<Coord>(std::llround(double(n.dir.Y) * half));
        pieces.push_back(Path{Point(n.at.X - ox, n.at.Y - oy), Point(n.at.X + ox, n.at.Y + oy)});
    }
    out.lines = std::move(pieces);  // clip_ribs() stops them at the walls

    // The minima of the slice above that no bridge held: held now if nothing of them deeper
    // than `reach` inside this slice's empty region is further than the lattice's reach from a
    // rib printed here.
    if (!slice.unheld_deep.empty()) {
        std::vector<Point> at;
        for (const Node& n : nodes_) at.push_back(n.at);
        const Paths covered = disks(at, rho + r);
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

// Clipper-backed booleans. Kept in one place so that fill rules and orientation are chosen once.
#include "geometry/polygon.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>

#include "geometry/probe.hpp"

namespace carve {

using namespace ClipperLib;

namespace {

// The transitive closure of "boxes overlap" over n non-empty contours (empty ones are left
// out): lists of indices, in first-seen order.
template <typename PathAt>
std::vector<std::vector<size_t>> box_groups(size_t n, PathAt path_at) {
    struct Group {
        BBox2 box;
        std::vector<size_t> members;
        bool merged = false;
    };
    std::vector<Group> groups;
    std::vector<size_t> hits;
    for (size_t i = 0; i < n; ++i) {
        const Path& p = path_at(i);
        if (p.empty()) continue;
        const BBox2 b = bounds(p);
        hits.clear();
        for (size_t g = 0; g < groups.size(); ++g)
            if (!groups[g].merged && overlap(groups[g].box, b)) hits.push_back(g);
        if (hits.empty()) {
            groups.push_back({b, {i}});
            continue;
        }
        Group& into = groups[hits.front()];
        expand(into.box, b);
        into.members.push_back(i);
        for (size_t h = 1; h < hits.size(); ++h) {
            Group& from = groups[hits[h]];
            expand(into.box, from.box);
            into.members.insert(into.members.end(), from.members.begin(), from.members.end());
            from.merged = true;
            from.members.clear();
        }
    }
    std::vector<std::vector<size_t>> out;
    for (Group& g : groups)
        if (!g.merged) out.push_back(std::move(g.members));
    return out;
}

// Fill rules of the two operands.
struct Fills {
    PolyFillType subject = pftNonZero, clip = pftNonZero;
};

// Executes `c`, appending its result to `out`.
void execute_into(Clipper& c, ClipType op, Fills fill, Paths& out) {
    Paths part;
    c.Execute(op, part, fill.subject, fill.clip);
    std::move(part.begin(), part.end(), std::back_inserter(out));
}

Paths run_clipper(ClipType op, const Paths& subject, const Paths* clip, Fills fill) {
    Clipper c;
    c.AddPaths(subject, ptSubject, true);
    if (clip) c.AddPaths(*clip, ptClip, true);
    Paths out;
    c.Execute(op, out, fill.subject, fill.clip);
    return out;
}

// `p` with every run of consecutive vertices beyond one side of `box` (strictly) replaced by
// the run's first and last vertex. The new edge lies beyond that side with the run, so the
// winding number of every point inside the box is unchanged; and every edge that reaches the
// box is kept as it was. Clipper's sweep also clamps each crossing it rounds into its scanbeam,
// whose bounds are the y of every vertex of the pass, wherever it lies: so the vertices level
// with the box (its band of y, one unit wider for the rounding) stay too, even beyond its left
// or right side. Then a boolean rounds its crossings with anything inside the box exactly as it
// would on `p`. A cavity above that spans the slice then brings to each small piece of V only
// its edges near it and its vertices level with it, plus a few.
void fold_beyond(const Path& p, const BBox2& box, Path& out) {
    out = p;
    Path next;
    auto in_band = [&](const Point& q) { return q.Y >= box.min_y - 1 && q.Y <= box.max_y + 1; };
    for (int side = 0; side < 4; ++side) {
        auto beyond = [&](const Point& q) {
            switch (side) {
                case 0:
                    return q.X < box.min_x && !in_band(q);
                case 1:
                    return q.X > box.max_x && !in_band(q);
                case 2:
                    return q.Y < box.min_y - 1;
                default:
                    return q.Y > box.max_y + 1;
            }
        };
        const size_t n = out.size();
        size_t start = n;  // a vertex not beyond this side, where the walk starts
        for (size_t i = 0; i < n && start == n; ++i)
            if (!beyond(out[i])) start = i;
        if (start == n || n < 4) continue;  // wholly beyond: the caller's box test drops it
        next.clear();
        for (size_t k = 0; k < n; ++k) {
            const size_t i = (start + k) % n;
            // Interior vertices of a run beyond the side: both neighbours beyond too.
            if (beyond(out[i]) && beyond(out[(i + n - 1) % n]) && beyond(out[(i + 1) % n]))
                continue;
            next.push_back(out[i]);
        }
        std::swap(out, next);
    }
}

// Where the result lies within one operand, the anchor (the subject of a difference, the
// smaller operand of an intersection), only the other operand's contours over the anchor's
// pieces matter. So each cluster of the anchor (box_groups) is clipped alone, with the other
// operand's contours whose boxes meet the cluster's, folded to its box (fold_beyond): late in
// the sweep V is dozens of small pieces, and grouping both operands together would join them
// all through the cavity above that spans them. Folding keeps every edge that reaches the box,
// so Clipper rounds each crossing the same way in every pass (the other operand's contours
// beside the box come folded too when they have vertices level with it: fold_beyond says why),
// and the pieces of a partition made by several passes still meet exactly (a
// Sutherland-Hodgman cut would move the cut edges by the rounding of their new ends).
Paths run_within(ClipType op, const Paths& subject, const Paths& clip, Fills fill,
                 bool anchor_is_subject) {
    const Paths& anchor = anchor_is_subject ? subject : clip;
    const Paths& other = anchor_is_subject ? clip : subject;
    const PolyType anchor_type = anchor_is_subject ? ptSubject : ptClip;
    const PolyType other_type = anchor_is_subject ? ptClip : ptSubject;
    std::vector<BBox2> other_boxes;
    other_boxes.reserve(other.size());
    for (const Path& p : other) other_boxes.push_back(bounds(p));
    Paths out;
    Path folded;
    for (const std::vector<size_t>& members :
         box_groups(anchor.size(), [&](size_t i) -> const Path& { return anchor[i]; })) {
        BBox2 box;
        for (size_t i : members) expand(box, bounds(anchor[i]));
        Clipper c;
        for (size_t i : members) c.AddPath(anchor[i], anchor_type, true);
        bool met = false;
        for (size_t j = 0; j < other.size(); ++j) {
            const BBox2& ob = other_boxes[j];
            if (!overlap(ob, box)) {
                // Beside the box, it cannot change a winding number inside; but its vertices
                // level with the box bound scanbeams there (see fold_beyond), so those stay.
                if (ob.max_y >= box.min_y - 1 && ob.min_y <= box.max_y + 1 &&
                    std::any_of(other[j].begin(), other[j].end(), [&](const Point& q) {
                        return q.Y >= box.min_y - 1 && q.Y <= box.max_y + 1;
                    })) {
                    fold_beyond(other[j], box, folded);
                    c.AddPath(folded, other_type, true);
                }
                continue;
            }
            met = true;
            if (contains(box, ob)) {
                c.AddPath(other[j], other_type, true);
                continue;
            }
            fold_beyond(other[j], box, folded);
            c.AddPath(folded, other_type, true);
        }
        if (!met && op == ctIntersection) continue;
        execute_into(c, op, fill, out);
    }
    return out;
}

size_t vertex_count(const Paths& region) {
    size_t n = 0;
    for (const Path& p : region) n += p.size();
    return n;
}

// Clipper's sweep costs about (scanbeams) x (edges active on a scanline), so pieces side by
// side make each other's scanbeams dearer. The winding number at a point only depends on the
// contours whose boxes hold it, so groups of contours whose boxes do not overlap any other
// group's (box_groups) are independent: each is clipped alone and the results are
// concatenated, exactly. Late in the sweep a slice's cavities and remainder are dozens of
// pieces across the slice. That is how unions and symmetric differences run; differences and
// intersections go further (run_within).
Paths run(ClipType op, const Paths& subject, const Paths* clip, Fills fill = {}) {
    GeometryTimer timer(GeometryOp::kBoolean);
    if (clip && op == ctDifference) return run_within(op, subject, *clip, fill, true);
    if (clip && op == ctIntersection)
        return run_within(op, subject, *clip, fill, vertex_count(subject) <= vertex_count(*clip));
    const size_t ns = subject.size(), n = ns + (clip ? clip->size() : 0);
    if (n < 3) return run_clipper(op, subject, clip, fill);
    auto path_at = [&](size_t i) -> const Path& { return i < ns ? subject[i] : (*clip)[i - ns]; };
    const std::vector<std::vector<size_t>> groups = box_groups(n, path_at);
    if (groups.size() <= 1) return run_clipper(op, subject, clip, fill);
    Paths out;
    for (const std::vector<size_t>& members : groups) {
        Clipper c;
        for (size_t i : members) c.AddPath(path_at(i), i < ns ? ptSubject : ptClip, true);
        execute_into(c, op, fill, out);
    }
    return out;
}

void collect_components(const PolyNode& node, std::vector<Paths>& out) {
    for (const PolyNode* child : node.Childs) {
        if (!child->IsHole()) {
            Paths comp{child->Contour};
            for (const PolyNode* hole : child->Childs) {
                comp.push_back(hole->Contour);
                collect_components(*hole, out);
            }
            out.push_back(std::move(comp));
        }
    }
}

}  // namespace

double area(const Path& path) {
    return Area(path);
}

double area(const Paths& region) {
    double a = 0;
    for (const Path& p : region) a += Area(p);
    return a;
}

Paths unite(const Paths& a) {
    return run(ctUnion, a, nullptr);
}
Paths unite(const Paths& a, const Paths& b) {
    return run(ctUnion, a, &b);
}
// Most calls in the sweep and the bridge search meet pieces far apart; a bounding-box test is
// a few hundred comparisons where Clipper would build and sweep both inputs.
Paths intersect(const Paths& a, const Paths& b) {
    if (a.empty() || b.empty() || !overlap(bounds(a), bounds(b))) return {};
    return run(ctIntersection, a, &b);
}
Paths subtract(const Paths& a, const Paths& b) {
    if (a.empty()) return {};
    if (b.empty() || !overlap(bounds(a), bounds(b))) return a;
    return run(ctDifference, a, &b);
}
Paths subtract_from_union(const Paths& a, const Paths& b) {
    if (a.empty()) return {};
    if (b.empty() || !overlap(bounds(a), bounds(b))) return unite(a);
    return run(ctDifference, a, &b);
}
Paths symmetric_difference(const Paths& a, const Paths& b) {
    return run(ctXor, a, &b);
}
Paths unite_positive(const Paths& a) {
    return run(ctUnion, a, nullptr, {pftPositive, pftPositive});
}

Paths resolve(const PositiveRegion& a) {
    return unite_positive(a.contours);
}
Paths subtract(const PositiveRegion& a, const Paths& b) {
    if (a.contours.empty()) return {};
    if (b.empty() || !overlap(bounds(a.contours), bounds(b))) return resolve(a);
    return run(ctDifference, a.contours, &b, {pftPositive, pftNonZero});
}

Paths subtract_positive(const Paths& a, const PositiveRegion& b) {
    if (a.empty()) return {};
    if (b.contours.empty() || !overlap(bounds(a), bounds(b.contours))) return a;
    return run(ctDifference, a, &b.contours, {pftNonZero, pftPositive});
}
Paths intersect_positive(const Paths& a, const PositiveRegion& b) {
    if (a.empty() || b.contours.empty() || !overlap(bounds(a), bounds(b.contours))) return {};
    return run(ctIntersection, a, &b.contours, {pftNonZero, pftPositive});
}

Paths clip_lines(const Paths& lines, const Paths& region) {
    if (lines.empty() || region.empty()) return {};
    Clipper c;
    c.AddPaths(lines, ptSubject, false);
    c.AddPaths(region, ptClip, true);
    PolyTree tree;
    c.Execute(ctIntersection, tree, pftNonZero, pftNonZero);
    Paths out;
    OpenPathsFromPolyTree(tree, out);
    return out;
}

Paths clean(const Paths& region, double tolerance) {
    Paths out;
    CleanPolygons(region, out, tolerance);
    out.erase(std::remove_if(out.begin(), out.end(), [](const Path& p) { return p.size() < 3; }),
              out.end());
    return out;
}

void drop_straight_points(Path& p, double tolerance) {
    const size_t n = p.size();
    if (n < 4) return;
    const double t2 = tolerance * tolerance;
    Path out;
    out.reserve(n);
    bool dropped = true;  // keeps the first point
    for (size_t i = 0; i < n; ++i) {
        const Point& b = p[i];
        if (!dropped && i + 1 < n) {
            const Point& a = out.back();
            const Point& c = p[i + 1];
            const double ux = double(c.X - a.X), uy = double(c.Y - a.Y);
            const double vx = double(b.X - a.X), vy = double(b.Y - a.Y);
            const double cross = ux * vy - uy * vx, len2 = ux * ux + uy * uy;
            const double along = ux * vx + uy * vy;
            if (cross * cross <= t2 * len2 && along > 0 && along < len2) {
                dropped = true;
                continue;
            }
        }
        dropped = false;
        out.push_back(b);
    }
    if (out.size() >= 3) p = std::move(out);
}

Paths simplify(const Paths& region, double tolerance) {
    Paths out = region;
    for (Path& p : out) drop_straight_points(p, tolerance);
    return out;
}

void expand(BBox2& box, const BBox2& other) {
    if (other.empty) return;
    if (box.empty) {
        box = other;
        return;
    }
    box.min_x = std::min(box.min_x, other.min_x);
    box.min_y = std::min(box.min_y, other.min_y);
    box.max_x = std::max(box.max_x, other.max_x);
    box.max_y = std::max(box.max_y, other.max_y);
}

BBox2 bounds(const Path& path) {
    BBox2 b;
    for (const Point& q : path) expand(b, {q.X, q.Y, q.X, q.Y, false});
    return b;
}

BBox2 bounds(const Paths& region) {
    BBox2 b;
    for (const Path& p : region) expand(b, bounds(p));
    return b;
}

bool contains(const BBox2& outer, const BBox2& inner) {
    return inner.min_x >= outer.min_x && inner.max_x <= outer.max_x && inner.min_y >= outer.min_y &&
           inner.max_y <= outer.max_y;
}

bool overlap(const BBox2& a, const BBox2& b) {
    return !a.empty && !b.empty && a.min_x <= b.max_x && b.min_x <= a.max_x && a.min_y <= b.max_y &&
           b.min_y <= a.max_y;
}

double length(const Paths& paths, bool closed) {
    double len = 0;
    for (const Path& p : paths) {
        if (p.size() < 2) continue;
        for (size_t i = 1; i < p.size(); ++i)
            len += std::hypot(double(p[i].X - p[i - 1].X), double(p[i].Y - p[i - 1].Y));
        if (closed)
            len += std::hypot(double(p.front().X - p.back().X), double(p.front().Y - p.back().Y));
    }
    return len;
}

std::vector<Paths> clusters(const Paths& region) {
    std::vector<Paths> out;
    for (const std::vector<size_t>& members :
         box_groups(region.size(), [&](size_t i) -> const Path& { return region[i]; })) {
        Paths& cluster = out.emplace_back();
        cluster.reserve(members.size());
        for (size_t i : members) cluster.push_back(region[i]);
    }
    return out;
}

namespace {

// A side of a box: the line where X (or Y) is `at`, keeping the points on the `above` side.
struct BoxSide {
    Coord at;
    bool on_x, above;
    bool keeps(const Point& q) const {
        const Coord c = on_x ? q.X : q.Y;
        return above ? c >= at : c <= at;
    }
    // Where segment ab, which it separates, crosses it; the other coordinate rounded.
    Point cut(const Point& a, const Point& b) const {
        const double t =
            on_x ? double(at - a.X) / double(b.X - a.X) : double(at - a.Y) / double(b.Y - a.Y);
        return on_x ? Point(at, a.Y + static_cast<Coord>(std::llround(t * double(b.Y - a.Y))))
                    : Point(a.X + static_cast<Coord>(std::llround(t * double(b.X - a.X))), at);
    }
};

// One Sutherland-Hodgman step: the part of `in` on the kept side, crossings on the side.
void clip_to_side(const Path& in, Path& out, const BoxSide& side) {
    out.clear();
    const size_t n = in.size();
    for (size_t i = 0; i < n; ++i) {
        const Point& a = in[(i + n - 1) % n];
        const Point& b = in[i];
        const bool keep_b = side.keeps(b);
        if (side.keeps(a) != keep_b) out.push_back(side.cut(a, b));
        if (keep_b) out.push_back(b);
    }
}

}  // namespace

Paths clip_to_box(const Paths& region, const BBox2& box) {
    const BoxSide sides[] = {{box.min_x, true, true},
                             {box.max_x, true, false},
                             {box.min_y, false, true},
                             {box.max_y, false, false}};
    Paths out;
    Path cut, next;
    for (const Path& p : region) {
        const BBox2 pb = bounds(p);
        if (!overlap(pb, box)) continue;  // winding 0 inside the box
        if (contains(box, pb)) {
            out.push_back(p);
            continue;
        }
        cut = p;
        for (const BoxSide& side : sides) {
            clip_to_side(cut, next, side);
            std::swap(cut, next);
        }
        if (cut.size() >= 3) out.push_back(cut);
    }
    return out;
}

Paths contours_near(const Paths& region, const Paths& other, Coord reach) {
    std::vector<BBox2> boxes;
    for (const Path& p : other)
        if (area(p) > 0) boxes.push_back(bounds(p));  // a hole's box lies in its outer's
    const Coord m = reach + 2;                        // and Clipper's rounding
    Paths out;
    for (const Path& p : region) {
        const BBox2 b = bounds(p);
        const BBox2 grown{b.min_x - m, b.min_y - m, b.max_x + m, b.max_y + m, false};
        if (std::any_of(boxes.begin(), boxes.end(),
                        [&](const BBox2& o) { return overlap(o, grown); }))
            out.push_back(p);
    }
    return out;
}

// In a normalised region every hole lies in its outer's box, so a group of contours whose boxes
// overlap no other group's (box_groups) and that holds a single outer is one component as it
// stands; only groups with several outers (islands in holes, pieces side by side) need
// Clipper's nesting. The sweep and the bridges split regions of dozens of small pieces.
std::vector<Paths> components(const Paths& region) {
    std::vector<Paths> comps;
    Paths nested;
    for (const std::vector<size_t>& members :
         box_groups(region.size(), [&](size_t i) -> const Path& { return region[i]; })) {
        std::vector<size_t> outers, holes;
        for (size_t i : members) {
            const double a = area(region[i]);
            if (a != 0) (a > 0 ? outers : holes).push_back(i);
        }
        if (outers.size() != 1) {
            for (size_t i : members) nested.push_back(region[i]);
            continue;
        }
        Paths& comp = comps.emplace_back();
        comp.push_back(region[outers.front()]);
        for (size_t i : holes) comp.push_back(region[i]);
    }
    if (!nested.empty()) {
        PolyTree tree;
        Clipper c;
        c.AddPaths(nested, ptSubject, true);
        c.Execute(ctUnion, tree, pftNonZero, pftNonZero);
        collect_components(tree, comps);
    }
    return comps;
}

// In a normalised region the holes are the clockwise contours and an island in a hole is a
// counter-clockwise contour inside it, which no contour crosses: box containment and one vertex
// tell, without a Clipper pass to build the nesting.
Paths without_holes(const Paths& region) {
    Paths outers;
    for (const Path& p : region)
        if (area(p) > 0) outers.push_back(p);
    return unite(outers);
}

Paths empty_holes(const Paths& region) {
    std::vector<BBox2> boxes;
    std::vector<size_t> outers;
    boxes.reserve(region.size());
    for (size_t i = 0; i < region.size(); ++i) {
        boxes.push_back(bounds(region[i]));
        if (Area(region[i]) > 0) outers.push_back(i);
    }
    auto inside = [&](size_t island, size_t hole) {
        if (!contains(boxes[hole], boxes[island])) return false;
        for (const Point& v : region[island])  // a vertex off the hole's contour decides
            if (const int in = PointInPolygon(v, region[hole]); in >= 0) return in == 1;
        return false;
    };
    Paths out;
    for (size_t h = 0; h < region.size(); ++h) {
        if (region[h].size() < 3 || Area(region[h]) >= 0) continue;
        if (std::any_of(outers.begin(), outers.end(), [&](size_t o) { return inside(o, h); }))
            continue;
        Path hole = region[h];
        ReversePath(hole);
        out.push_back(std::move(hole));
    }
    return out;
}

bool point_in_region(const Point& p, const Paths& region) {
    int winding = 0;
    for (const Path& path : region) {
        int r = PointInPolygon(p, path);
        if (r == -1) return true;
        if (r == 1) winding += Orientation(path) ? 1 : -1;
    }
    return winding != 0;
}

}  // namespace carve

// Input preparation for the segment Voronoi builder: cleaning, simplification, union, and the
// mending of what Clipper leaves touching or crossing.
#include "skeleton/contours.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "geometry/simplify.hpp"

namespace carve::skel {

namespace {

// Contours of each component of the region (outer first, then its holes), interior on the left.
void collect(const ClipperLib::PolyNode& node, std::vector<Paths>& out) {
    for (const ClipperLib::PolyNode* outer : node.Childs) {
        if (outer->Contour.size() < 3) continue;
        Paths comp{outer->Contour};
        if (!ClipperLib::Orientation(comp[0])) ClipperLib::ReversePath(comp[0]);
        for (const ClipperLib::PolyNode* hole : outer->Childs) {
            if (hole->Contour.size() >= 3) {
                comp.push_back(hole->Contour);
                if (ClipperLib::Orientation(comp.back())) ClipperLib::ReversePath(comp.back());
            }
            collect(*hole, out);
        }
        out.push_back(std::move(comp));
    }
}

}  // namespace

std::vector<Paths> prepare_components(const Paths& region, double tolerance, int* mended) {
    Paths cleaned;
    ClipperLib::CleanPolygons(region, cleaned, 1.415);
    // Not StrictlySimple: on contours touching at several vertices its output has been seen
    // with a material triangle turned into a hole (winding -1). The plain union orients
    // correctly; what it leaves touching, mend_component() takes care of.
    ClipperLib::Clipper clipper;
    // Douglas-Peucker: Boost's builder costs some 30 us per segment (most circle events of a
    // finely tessellated smooth contour fall back to its multiprecision path), so vertices that
    // move the axis by less than the allowed error are not worth their cost.
    SimplifyScratch scratch;
    Path simple;
    for (const Path& p : cleaned) {
        if (p.size() < 3) continue;
        douglas_peucker(p, true, tolerance, scratch, simple);
        if (simple.size() >= 3) clipper.AddPath(simple, ClipperLib::ptSubject, true);
    }
    ClipperLib::PolyTree tree;
    clipper.Execute(ClipperLib::ctUnion, tree, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
    std::vector<Paths> comps;
    collect(tree, comps);
    int count = 0;
    for (Paths& comp : comps) count += mend_component(comp) > 0;
    comps.erase(
        std::remove_if(comps.begin(), comps.end(), [](const Paths& c) { return c.empty(); }),
        comps.end());
    if (mended) *mended = count;
    return comps;
}

namespace {

struct SegRef {
    Coord min_x, max_x, min_y, max_y;
    int contour, index;
};

struct Split {
    int contour, index;
    double t;  // position along the segment, for ordering
    Point p;
};

int orientation(const Point& a, const Point& b, const Point& c) {
    const __int128 v = __int128(b.X - a.X) * (c.Y - a.Y) - __int128(b.Y - a.Y) * (c.X - a.X);
    return v > 0 ? 1 : (v < 0 ? -1 : 0);
}

double along(const Point& p, const Point& a, const Point& b) {
    const double dx = double(b.X - a.X), dy = double(b.Y - a.Y);
    const double l2 = dx * dx + dy * dy;
    return l2 > 0 ? (double(p.X - a.X) * dx + double(p.Y - a.Y) * dy) / l2 : 0.0;
}

// Removes pairs of edges running along the same segment in opposite directions: a spike
// (a, b, a) within a contour, or a zero-width wall where two contours meet along a segment. The
// region has no area on either side of such a pair, and Boost's builder would merge the two
// sites into one. The contours are re-linked around each removed pair. Returns the pairs removed.
int cancel_opposite_edges(Paths& comp) {
    struct E {
        Point a, b;
        int prev, next;
        bool dead;
    };
    std::vector<E> edges;
    for (const Path& path : comp) {
        const int base = int(edges.size());
        const int n = int(path.size());
        for (int i = 0; i < n; ++i) {
            edges.push_back(
                {path[i], path[(i + 1) % n], base + (i + n - 1) % n, base + (i + 1) % n, false});
        }
    }
    struct Key {
        Point lo, hi;
        int edge;
    };
    auto less = [](const Point& p, const Point& q) { return p.X != q.X ? p.X < q.X : p.Y < q.Y; };
    std::vector<Key> keys;
    keys.reserve(edges.size());
    for (int i = 0; i < int(edges.size()); ++i) {
        const E& e = edges[i];
        keys.push_back(less(e.a, e.b) ? Key{e.a, e.b, i} : Key{e.b, e.a, i});
    }
    std::sort(keys.begin(), keys.end(), [&](const Key& p, const Key& q) {
        if (p.lo != q.lo) return less(p.lo, q.lo);
        if (p.hi != q.hi) return less(p.hi, q.hi);
        return p.edge < q.edge;
    });
    int removed = 0;
    for (size_t g = 0; g < keys.size();) {
        size_t h = g;
        while (h < keys.size() && keys[h].lo == keys[g].lo && keys[h].hi == keys[g].hi) ++h;
        for (size_t x = g; x < h; ++x) {
            const int i = keys[x].edge;
            if (edges[i].dead) continue;
            for (size_t y = x + 1; y < h; ++y) {
                const int j = keys[y].edge;
                if (edges[j].dead || edges[j].a != edges[i].b) continue;
                edges[i].dead = edges[j].dead = true;
                ++removed;
                const int p1 = edges[i].prev, n1 = edges[i].next;
                const int p2 = edges[j].prev, n2 = edges[j].next;
                if (n1 == j && n2 == i) break;  // a two-edge loop vanishes
                if (n1 == j) {
                    edges[p1].next = n2, edges[n2].prev = p1;
                } else if (n2 == i) {
                    edges[p2].next = n1, edges[n1].prev = p2;
                } else {
                    edges[p1].next = n2, edges[n2].prev = p1;
                    edges[p2].next = n1, edges[n1].prev = p2;
                }
                break;
            }
        }
        g = h;
    }
    if (removed == 0) return 0;
    Paths out;
    std::vector<uint8_t> seen(edges.size(), 0);
    for (int i = 0; i < int(edges.size()); ++i) {
        if (edges[i].dead || seen[i]) continue;
        Path path;
        for (int e = i; !seen[e]; e = edges[e].next) {
            seen[e] = 1;
            path.push_back(edges[e].a);
        }
        if (path.size() >= 3) out.push_back(std::move(path));
    }
    comp = std::move(out);
    return removed;
}

// Do segments ab and cd share a point other than a common endpoint?
bool improper(const Point& a, const Point& b, const Point& c, const Point& d) {
    const int o1 = orientation(a, b, c), o2 = orientation(a, b, d);
    const int o3 = orientation(c, d, a), o4 = orientation(c, d, b);
    auto within = [](const Point& p, const Point& q, const Point& r) {  // r in box of pq
        return std::min(p.X, q.X) <= r.X && r.X <= std::max(p.X, q.X) &&
               std::min(p.Y, q.Y) <= r.Y && r.Y <= std::max(p.Y, q.Y);
    };
    if (o1 == 0 && c != a && c != b && within(a, b, c)) return true;
    if (o2 == 0 && d != a && d != b && within(a, b, d)) return true;
    if (o3 == 0 && a != c && a != d && within(c, d, a)) return true;
    if (o4 == 0 && b != c && b != d && within(c, d, b)) return true;
    return o1 * o2 < 0 && o3 * o4 < 0;
}

// Splits segments that meet elsewhere than at a common endpoint (exact integer test): at the
// other's vertex nearest to it when that vertex is within 1.5 units (Clipper rounded it a hair
// across, or left it on the segment), else both at their rounded crossing point.
int split_improper(Paths& comp) {
    std::vector<SegRef> segs;
    std::vector<Split> splits;
    segs.clear();
    for (int c = 0; c < int(comp.size()); ++c) {
        const Path& path = comp[c];
        for (int i = 0; i < int(path.size()); ++i) {
            const Point& a = path[i];
            const Point& b = path[(i + 1) % path.size()];
            segs.push_back({std::min(a.X, b.X), std::max(a.X, b.X), std::min(a.Y, b.Y),
                            std::max(a.Y, b.Y), c, i});
        }
    }
    std::sort(segs.begin(), segs.end(),
              [](const SegRef& p, const SegRef& q) { return p.min_x < q.min_x; });
    auto ends = [&](const SegRef& s) {
        const Path& path = comp[s.contour];
        return std::pair<Point, Point>(path[s.index], path[(s.index + 1) % path.size()]);
    };
    splits.clear();
    for (size_t i = 0; i < segs.size(); ++i) {
        for (size_t j = i + 1; j < segs.size() && segs[j].min_x <= segs[i].max_x; ++j) {
            const SegRef& s = segs[i];
            const SegRef& t = segs[j];
            if (t.min_y > s.max_y || t.max_y < s.min_y) continue;
            const auto [a, b] = ends(s);
            const auto [c, d] = ends(t);
            if (!improper(a, b, c, d)) continue;
            // Rounding put a vertex a hair across the other segment: make it a vertex of
            // that segment too (the nearest such vertex). Otherwise meet at the crossing.
            double best = 1.5;
            Split split{-1, 0, 0, Point()};
            auto offer = [&](const SegRef& on, const Point& p, const Point& q, const Point& v) {
                if (v == p || v == q) return;
                const double dist = segment_distance(v, p, q);
                if (dist < best) best = dist, split = {on.contour, on.index, along(v, p, q), v};
            };
            offer(s, a, b, c);
            offer(s, a, b, d);
            offer(t, c, d, a);
            offer(t, c, d, b);
            if (split.contour >= 0) {
                splits.push_back(split);
                continue;
            }
            const double den =
                double(b.X - a.X) * double(d.Y - c.Y) - double(b.Y - a.Y) * double(d.X - c.X);
            if (den == 0) continue;
            const double u =
                (double(c.X - a.X) * double(d.Y - c.Y) - double(c.Y - a.Y) * double(d.X - c.X)) /
                den;
            const Point p(std::llround(a.X + u * double(b.X - a.X)),
                          std::llround(a.Y + u * double(b.Y - a.Y)));
            if (p != a && p != b) splits.push_back({s.contour, s.index, along(p, a, b), p});
            if (p != c && p != d) splits.push_back({t.contour, t.index, along(p, c, d), p});
        }
    }
    if (splits.empty()) return 0;
    std::sort(splits.begin(), splits.end(), [](const Split& p, const Split& q) {
        if (p.contour != q.contour) return p.contour < q.contour;
        if (p.index != q.index) return p.index < q.index;
        return p.t < q.t;
    });
    size_t k = 0;
    for (int c = 0; c < int(comp.size()); ++c) {
        Path mended;
        const Path& path = comp[c];
        for (int i = 0; i < int(path.size()); ++i) {
            if (mended.empty() || mended.back() != path[i]) mended.push_back(path[i]);
            for (; k < splits.size() && splits[k].contour == c && splits[k].index == i; ++k)
                if (mended.back() != splits[k].p) mended.push_back(splits[k].p);
        }
        while (mended.size() > 1 && mended.front() == mended.back()) mended.pop_back();
        comp[c] = std::move(mended);
    }
    comp.erase(
        std::remove_if(comp.begin(), comp.end(), [](const Path& path) { return path.size() < 3; }),
        comp.end());
    return int(splits.size());
}

}  // namespace

// Makes a component meet the builder's precondition: split where segments meet improperly,
// drop the zero-width pairs this leaves, until nothing changes (4 passes at most).
int mend_component(Paths& comp) {
    int total = 0;
    for (int pass = 0; pass < 4; ++pass) {
        const int changes = split_improper(comp) + cancel_opposite_edges(comp);
        if (changes == 0) break;
        total += changes;
    }
    return total;
}

}  // namespace carve::skel

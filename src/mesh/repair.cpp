// analyse_and_repair: cleans an indexed mesh and makes every shell face the right way.
//
// Order of work: drop triangles with a repeated vertex; drop zero-area slivers, splitting the
// triangle across a sliver's long edge at its middle vertex so that the surface stays closed
// (the T-junction the sliver was hiding); drop exact duplicates; count edge incidence; orient
// each shell (connected through manifold edges) by a breadth-first walk; then choose each
// shell's side: outermost closed shells enclose positive volume, a closed shell nested inside an
// odd number of others is a void and encloses negative volume. Everything is linear in the
// triangle count except the nesting test, which shoots a few rays per closed shell only.
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <span>
#include <string>

#include "mesh/mesh.hpp"
#include "mesh/shells.hpp"

namespace carve {

using namespace shells;

namespace {

using Tri = std::array<uint32_t, 3>;
constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();

int corner(const Tri& t, uint32_t v) {
    return t[0] == v ? 0 : t[1] == v ? 1 : t[2] == v ? 2 : -1;
}

// Vertex -> the triangles that use it, in increasing triangle order.
struct Star {
    std::vector<uint32_t> first;
    std::vector<uint32_t> tris;
    std::span<const uint32_t> of(uint32_t v) const {
        return {tris.data() + first[v], tris.data() + first[v + 1]};
    }
};

// The buckets are filled from their ends, so that the counts turn into the starts in place
// without a second array of vertex size (36 MB on a soup of 3 million triangles).
Star build_star(const std::vector<Tri>& tris, size_t vertex_count) {
    Star s;
    s.first.assign(vertex_count + 1, 0);
    for (const Tri& t : tris)
        for (uint32_t v : t) ++s.first[v];
    for (size_t v = 1; v < vertex_count; ++v) s.first[v] += s.first[v - 1];
    s.first[vertex_count] = static_cast<uint32_t>(3 * tris.size());
    s.tris.resize(3 * tris.size());
    for (uint32_t t = static_cast<uint32_t>(tris.size()); t-- > 0;)
        for (uint32_t v : tris[t]) s.tris[--s.first[v]] = t;
    return s;
}

// Zero area up to rounding: the cross product is tiny against the longest edge squared.
bool zero_area(const std::vector<Vec3>& vs, const Tri& t) {
    const Vec3 e1 = sub(vs[t[1]], vs[t[0]]), e2 = sub(vs[t[2]], vs[t[0]]),
               e3 = sub(vs[t[2]], vs[t[1]]);
    const Vec3 c = cross(e1, e2);
    const double l2 = std::max({dot(e1, e1), dot(e2, e2), dot(e3, e3)});
    return dot(c, c) <= 1e-24 * l2 * l2;
}

size_t drop_repeated_vertices(std::vector<Tri>& tris) {
    const size_t before = tris.size();
    std::erase_if(tris, [](const Tri& t) { return t[0] == t[1] || t[1] == t[2] || t[0] == t[2]; });
    return before - tris.size();
}

// Drops zero-area triangles. A sliver (a, c, b) with c between a and b usually sits on a
// T-junction: the triangle on the other side of a-b ends at a and b while the triangles on the
// sliver's side end at c. That triangle is split at c so that the surface stays closed. Slivers
// touching a vertex already involved in this round wait for the next round, because the star
// is only rebuilt between rounds.
size_t drop_zero_area(Mesh& mesh, size_t& splits) {
    auto& tris = mesh.triangles;
    const auto& vs = mesh.vertices;
    size_t dropped = 0;
    for (int round = 0; round < 64; ++round) {
        std::vector<uint32_t> slivers;
        for (uint32_t t = 0; t < tris.size(); ++t)
            if (zero_area(vs, tris[t])) slivers.push_back(t);
        if (slivers.empty()) return dropped;
        const Star star = build_star(tris, vs.size());
        const size_t old_count = tris.size();
        std::vector<uint8_t> busy(vs.size(), 0), removed(old_count, 0);
        std::vector<uint32_t> across;
        for (uint32_t s : slivers) {
            const Tri t = tris[s];
            int k = 0;  // the corner opposite the longest edge is the middle vertex
            double longest = -1;
            for (int i = 0; i < 3; ++i) {
                const Vec3 e = sub(vs[t[(i + 1) % 3]], vs[t[(i + 2) % 3]]);
                if (dot(e, e) > longest) longest = dot(e, e), k = i;
            }
            const uint32_t c = t[k], a = t[(k + 1) % 3], b = t[(k + 2) % 3];
            if (busy[a] || busy[b] || busy[c]) continue;
            across.clear();
            for (uint32_t n : star.of(a))
                if (n != s && !removed[n] && corner(tris[n], b) >= 0) across.push_back(n);
            removed[s] = 1;
            ++dropped;
            busy[a] = busy[b] = busy[c] = 1;
            for (uint32_t n : across) {
                const Tri u = tris[n];
                if (corner(u, c) >= 0 || zero_area(vs, u)) continue;
                const int ia = corner(u, a), ib = corner(u, b);
                const bool a_to_b = (ia + 1) % 3 == ib;
                const uint32_t p = a_to_b ? a : b, q = a_to_b ? b : a;
                const uint32_t r = u[(corner(u, q) + 1) % 3];
                tris[n] = {p, c, r};
                tris.push_back({c, q, r});
                busy[r] = 1;
                ++splits;
            }
        }
        size_t out = 0;
        for (size_t t = 0; t < tris.size(); ++t)
            if (t >= old_count || !removed[t]) tris[out++] = tris[t];
        tris.resize(out);
    }
    const size_t before = tris.size();
    std::erase_if(tris, [&](const Tri& t) { return zero_area(vs, t); });
    return dropped + before - tris.size();
}

bool same_orientation(const Tri& t, const Tri& u) {
    const int j = corner(u, t[0]);
    return u[(j + 1) % 3] == t[1];
}

// What lies across edge i of triangle t, packed into one word at 3t + i so that the walk over
// shells reads one cache line per triangle: the neighbour across a manifold edge (or kNoNeighbour),
// whether it runs the edge the same way (one of the two is wrong), and whether the edge has odd
// incidence (the surface has a rim there).
constexpr uint32_t kNoNeighbour = 0x3FFFFFFFu;
constexpr uint32_t kSameDirection = 1u << 30;
constexpr uint32_t kOddEdge = 1u << 31;

struct EdgeInfo {
    std::vector<uint32_t> across;
    size_t open = 0, nonmanifold = 0;
    std::vector<std::pair<uint32_t, uint32_t>> duplicates;  // triangles on the same 3 vertices
};

// Half-edges are bucketed by their lower vertex and each bucket is sorted by the upper one, so
// that the triangles around an edge are found without touching the triangle array again
// (which, in file order, would be a cache miss per look-up on large meshes). Unless final, a
// mesh with duplicates gets its counts and duplicates only, to be analysed again without them.
EdgeInfo analyse_edges(const std::vector<Tri>& tris, size_t vertex_count, bool final,
                       const std::function<void(const EdgeInfo&)>& counted) {
    // 12 bytes per half-edge, the direction in the id's top bit: with the bucket starts and
    // the mesh itself, the largest memory of the whole repair.
    constexpr uint32_t kForward = 1u << 31;  // runs from lower to upper
    struct HalfEdge {
        uint32_t upper;  // the edge's higher vertex index
        uint32_t third;  // the triangle's remaining vertex
        uint32_t id;     // 3t + i, | kForward
    };
    const size_t n = tris.size();
    // Filled from the bucket ends, as build_star does; the order inside a bucket does not
    // matter, since it is sorted.
    std::vector<uint32_t> first(vertex_count + 1, 0);
    for (const Tri& t : tris)
        for (int i = 0; i < 3; ++i) ++first[std::min(t[i], t[(i + 1) % 3])];
    for (size_t v = 1; v < vertex_count; ++v) first[v] += first[v - 1];
    first[vertex_count] = static_cast<uint32_t>(3 * n);
    std::vector<HalfEdge> half(3 * n);
    for (uint32_t t = 0; t < n; ++t) {
        for (uint32_t i = 0; i < 3; ++i) {
            const uint32_t a = tris[t][i], b = tris[t][(i + 1) % 3], c = tris[t][(i + 2) % 3];
            half[--first[std::min(a, b)]] = {std::max(a, b), c,
                                             (3 * t + i) | (a < b ? kForward : 0)};
        }
    }

    // First the counts and the duplicates; a caller that drops duplicates analyses again, so
    // the neighbours are only worked out on a mesh without them (or when told it is final),
    // after counted() has seen the counts: a triangle soup is refused there, before the
    // neighbour array adds its 12 bytes per triangle.
    EdgeInfo e;
    for (size_t v = 0; v < vertex_count; ++v) {
        HalfEdge* lo = half.data() + first[v];
        HalfEdge* hi = half.data() + first[v + 1];
        std::sort(lo, hi, [](const HalfEdge& x, const HalfEdge& y) {
            return x.upper != y.upper ? x.upper < y.upper : (x.id & ~kForward) < (y.id & ~kForward);
        });
        for (HalfEdge* g = lo; g < hi;) {
            HalfEdge* end = g + 1;
            while (end < hi && end->upper == g->upper) ++end;
            const size_t count = static_cast<size_t>(end - g);
            if (count == 1) ++e.open;
            if (count > 2) ++e.nonmanifold;
            for (HalfEdge* h = g; h < end; ++h)
                for (HalfEdge* k = h + 1; k < end; ++k)
                    if (k->third == h->third)
                        e.duplicates.push_back({(h->id & ~kForward) / 3, (k->id & ~kForward) / 3});
            g = end;
        }
    }
    if (!e.duplicates.empty() && !final) return e;
    counted(e);

    e.across.assign(3 * n, kNoNeighbour);
    for (size_t v = 0; v < vertex_count; ++v) {
        const HalfEdge* lo = half.data() + first[v];
        const HalfEdge* hi = half.data() + first[v + 1];
        for (const HalfEdge* g = lo; g < hi;) {
            const HalfEdge* end = g + 1;
            while (end < hi && end->upper == g->upper) ++end;
            const size_t count = static_cast<size_t>(end - g);
            if (count == 2) {
                const uint32_t same = (g[0].id ^ g[1].id) & kForward ? 0 : kSameDirection;
                const uint32_t id0 = g[0].id & ~kForward, id1 = g[1].id & ~kForward;
                e.across[id0] = id1 / 3 | same;
                e.across[id1] = id0 / 3 | same;
            }
            if (count % 2)
                for (const HalfEdge* h = g; h < end; ++h) e.across[h->id & ~kForward] |= kOddEdge;
            g = end;
        }
    }
    return e;
}

// Triangles on the same three vertices: keep one of the majority orientation; a pair facing
// opposite ways encloses nothing and both go.
size_t drop_duplicates(std::vector<Tri>& tris,
                       const std::vector<std::pair<uint32_t, uint32_t>>& pairs) {
    if (pairs.empty()) return 0;
    const uint32_t n = static_cast<uint32_t>(tris.size());
    std::vector<uint32_t> leader(n, kNone);  // the lowest-numbered triangle of the group
    auto root = [&](uint32_t t) {
        while (leader[t] != kNone) t = leader[t];
        return t;
    };
    for (auto [a, b] : pairs) {
        const uint32_t ra = root(a), rb = root(b);
        if (ra != rb) leader[std::max(ra, rb)] = std::min(ra, rb);
    }
    // balance[g]: +1 per triangle of group g facing like its leader, -1 per one facing away.
    std::vector<int> balance(n, 0);
    std::vector<uint8_t> grouped(n, 0);
    for (uint32_t t = 0; t < n; ++t) {
        if (leader[t] == kNone) continue;
        const uint32_t g = root(t);
        if (!grouped[g]) grouped[g] = 1, balance[g] = 1;
        grouped[t] = 1;
        balance[g] += same_orientation(tris[t], tris[g]) ? 1 : -1;
    }
    std::vector<uint32_t> keeper(n, kNone);
    for (uint32_t t = 0; t < n; ++t) {
        if (!grouped[t]) continue;
        const uint32_t g = root(t);
        if (keeper[g] == kNone && balance[g] != 0 &&
            (balance[g] > 0) == same_orientation(tris[t], tris[g]))
            keeper[g] = t;
    }
    size_t out = 0;
    for (uint32_t t = 0; t < n; ++t)
        if (!grouped[t] || keeper[root(t)] == t) tris[out++] = tris[t];
    const size_t dropped = n - out;
    tris.resize(out);
    return dropped;
}

std::string plural(size_t n, const std::string& word) {
    return std::to_string(n) + " " + word + (n == 1 ? "" : "s");
}

// Shells: triangles connected through manifold edges, each oriented like its seed.
struct ShellWalk {
    std::vector<uint32_t> shell_of;  // each triangle's shell
    std::vector<uint8_t> flip;       // whether it is turned against its shell's seed
    std::vector<Shell> shells;
};

ShellWalk walk_shells(const std::vector<Tri>& tris, const EdgeInfo& edges) {
    const uint32_t n = static_cast<uint32_t>(tris.size());
    ShellWalk w;
    w.shell_of.assign(n, kNone);
    w.flip.assign(n, 0);
    std::vector<uint32_t> queue;
    for (uint32_t seed = 0; seed < n; ++seed) {
        if (w.shell_of[seed] != kNone) continue;
        const uint32_t id = static_cast<uint32_t>(w.shells.size());
        w.shells.emplace_back();
        Shell& sh = w.shells.back();
        w.shell_of[seed] = id;
        queue.assign(1, seed);
        while (!queue.empty()) {
            const uint32_t t = queue.back();
            queue.pop_back();
            ++sh.size;
            sh.flips += w.flip[t];
            for (int i = 0; i < 3; ++i) {
                const uint32_t across = edges.across[3 * t + i];
                if (across & kOddEdge) sh.closed = false;
                const uint32_t m = across & kNoNeighbour;
                if (m == kNoNeighbour) continue;
                const uint8_t want = w.flip[t] ^ ((across & kSameDirection) ? 1 : 0);
                if (w.shell_of[m] == kNone) {
                    w.shell_of[m] = id;
                    w.flip[m] = want;
                    queue.push_back(m);
                } else if (w.flip[m] != want) {
                    sh.conflict = true;
                }
            }
        }
    }
    return w;
}

// Box, extreme vertices and volume (as walked) of each shell, in triangle order, which is cache
// friendly. Volumes are taken about the mesh's box centre; an open shell's volume depends on
// that point, so it is measured again about its own box centre. Returns which vertices a
// triangle uses.
std::vector<uint8_t> measure_shells(const Mesh& mesh, ShellWalk& w) {
    const auto& tris = mesh.triangles;
    const uint32_t n = static_cast<uint32_t>(tris.size());
    const BBox3 box = bounding_box(mesh);
    const Vec3 centre{(box.min.x + box.max.x) / 2, (box.min.y + box.max.y) / 2,
                      (box.min.z + box.max.z) / 2};
    auto six_volume = [&](const Tri& t, const Vec3& o) {
        const Vec3 a = sub(mesh.vertices[t[0]], o), b = sub(mesh.vertices[t[1]], o),
                   c = sub(mesh.vertices[t[2]], o);
        return dot(a, cross(b, c));
    };
    std::vector<uint8_t> seen(w.shells.size(), 0), used(mesh.vertices.size(), 0);
    bool any_open = false;
    for (uint32_t t = 0; t < n; ++t) {
        Shell& sh = w.shells[w.shell_of[t]];
        if (!seen[w.shell_of[t]]) {
            seen[w.shell_of[t]] = 1;
            sh.lo = sh.hi = mesh.vertices[tris[t][0]];
            sh.extreme.fill(tris[t][0]);
            any_open |= !sh.closed;
        }
        for (uint32_t vi : tris[t]) {
            used[vi] = 1;
            const Vec3& p = mesh.vertices[vi];
            if (p.x < sh.lo.x) sh.lo.x = p.x, sh.extreme[0] = vi;
            if (p.x > sh.hi.x) sh.hi.x = p.x, sh.extreme[1] = vi;
            if (p.y < sh.lo.y) sh.lo.y = p.y, sh.extreme[2] = vi;
            if (p.y > sh.hi.y) sh.hi.y = p.y, sh.extreme[3] = vi;
            if (p.z < sh.lo.z) sh.lo.z = p.z, sh.extreme[4] = vi;
            if (p.z > sh.hi.z) sh.hi.z = p.z, sh.extreme[5] = vi;
        }
        const double six = six_volume(tris[t], centre);
        sh.volume += w.flip[t] ? -six : six;
    }
    for (Shell& sh : w.shells) sh.volume_about_centre = sh.volume;
    if (any_open) {
        for (Shell& sh : w.shells)
            if (!sh.closed) sh.volume = 0;
        for (uint32_t t = 0; t < n; ++t) {
            Shell& sh = w.shells[w.shell_of[t]];
            if (sh.closed) continue;
            const Vec3 o{(sh.lo.x + sh.hi.x) / 2, (sh.lo.y + sh.hi.y) / 2, (sh.lo.z + sh.hi.z) / 2};
            const double six = six_volume(tris[t], o);
            sh.volume += w.flip[t] ? -six : six;
        }
    }
    return used;
}

// What turning the shells the right way round did.
struct ShellTurns {
    std::vector<uint8_t> turn;  // each shell's
    size_t flipped = 0, inverted = 0, voids = 0, conflicts = 0;
};

// Each shell's side: closed shells by nesting parity, open ones by their (approximate) volume,
// or by majority when they enclose next to nothing (a flat sheet). The triangles are turned.
ShellTurns orient_shells(std::vector<Tri>& tris, const ShellWalk& w) {
    ShellTurns out;
    out.turn.assign(w.shells.size(), 0);
    for (size_t s = 0; s < w.shells.size(); ++s) {
        const Shell& sh = w.shells[s];
        const bool want_negative = sh.closed && sh.depth % 2 == 1;
        const Vec3 diag = sub(sh.hi, sh.lo);
        const double tiny = 1e-9 * std::pow(std::sqrt(dot(diag, diag)), 3);
        if (std::abs(sh.volume) > tiny)
            out.turn[s] = (sh.volume < 0) != want_negative;
        else
            out.turn[s] = 2 * sh.flips > sh.size;
        const size_t changed = out.turn[s] ? sh.size - sh.flips : sh.flips;
        if (changed == sh.size)
            ++out.inverted;
        else
            out.flipped += changed;
        out.voids += want_negative;
        out.conflicts += sh.conflict;
    }
    for (uint32_t t = 0; t < static_cast<uint32_t>(tris.size()); ++t)
        if (w.flip[t] ^ out.turn[w.shell_of[t]]) std::swap(tris[t][1], tris[t][2]);
    return out;
}

// Vertices no triangle uses (any more) are dropped, keeping the order of the others.
void drop_unused_vertices(Mesh& mesh, const std::vector<uint8_t>& used) {
    if (std::find(used.begin(), used.end(), 0) == used.end()) return;
    std::vector<uint32_t> remap(mesh.vertices.size(), kNone);
    size_t kept = 0;
    for (size_t v = 0; v < mesh.vertices.size(); ++v) {
        if (!used[v]) continue;
        remap[v] = static_cast<uint32_t>(kept);
        mesh.vertices[kept++] = mesh.vertices[v];
    }
    mesh.vertices.resize(kept);
    for (Tri& t : mesh.triangles)
        for (uint32_t& v : t) v = remap[v];
}

// One warning for each kind of repair, in the report's words.
void add_warnings(MeshReport& report, size_t splits, const ShellTurns& turns) {
    auto& w = report.warnings;
    if (report.degenerate_dropped > 0) {
        std::string line = "dropped " + plural(report.degenerate_dropped, "degenerate triangle") +
                           " (zero area or a repeated vertex)";
        if (splits > 0)
            line += "; split " + plural(splits, "neighbouring triangle") +
                    " at the slivers' middle vertices so that the surface stays closed";
        w.push_back(line);
    }
    if (report.duplicate_dropped > 0)
        w.push_back("dropped " + plural(report.duplicate_dropped, "duplicate triangle"));
    if (turns.flipped > 0)
        w.push_back("flipped " + plural(turns.flipped, "facet") +
                    " to agree with their neighbours");
    if (turns.inverted > 0) {
        if (report.shells == 1)
            w.push_back(
                "the mesh was inside out (every facet faced inwards); turned it outside out");
        else
            w.push_back(plural(turns.inverted, "shell") + " of " + std::to_string(report.shells) +
                        " faced the wrong way (inside out); turned them around");
    }
    if (turns.conflicts > 0)
        w.push_back(plural(turns.conflicts, "shell") +
                    " cannot be oriented consistently (one-sided, like a Moebius strip)");
    if (report.open_edges > 0)
        w.push_back("mesh is not closed: " + plural(report.open_edges, "open edge") +
                    "; slicing it anyway with non-zero fill");
    if (report.nonmanifold_edges > 0)
        w.push_back(plural(report.nonmanifold_edges, "non-manifold edge") +
                    " (shared by more than two triangles); slicing it anyway with non-zero fill");
}

}  // namespace

void analyse_and_repair(Mesh& mesh, MeshReport& report,
                        const std::function<void(const MeshReport&)>& edges_counted) {
    auto& tris = mesh.triangles;
    if (report.triangles_read == 0) report.triangles_read = tris.size();

    size_t splits = 0;
    const size_t repeated = drop_repeated_vertices(tris);
    const size_t zero = drop_zero_area(mesh, splits);
    report.degenerate_dropped = repeated + zero;
    report.zero_area_splits = splits;

    auto counted = [&](const EdgeInfo& e) {
        report.open_edges = e.open;
        report.nonmanifold_edges = e.nonmanifold;
        if (edges_counted) edges_counted(report);
    };
    EdgeInfo edges = analyse_edges(tris, mesh.vertices.size(), false, counted);
    report.duplicate_dropped = drop_duplicates(tris, edges.duplicates);
    if (!edges.duplicates.empty()) edges = analyse_edges(tris, mesh.vertices.size(), true, counted);

    ShellWalk walk = walk_shells(tris, edges);
    const std::vector<uint8_t> used = measure_shells(mesh, walk);
    nesting_depths(mesh, walk.shell_of, walk.shells);
    const ShellTurns turns = orient_shells(tris, walk);
    const std::vector<Shell>& shells = walk.shells;

    // The total is summed from the shells rather than measured again: one pass less over a large
    // mesh, and the same figure as signed_volume() as long as every vertex is used.
    double volume = 0;
    BBox3 bbox;
    for (size_t s = 0; s < shells.size(); ++s) {
        const Shell& sh = shells[s];
        volume += turns.turn[s] ? -sh.volume_about_centre : sh.volume_about_centre;
        if (s == 0) bbox.min = sh.lo, bbox.max = sh.hi;
        bbox.min = {std::min(bbox.min.x, sh.lo.x), std::min(bbox.min.y, sh.lo.y),
                    std::min(bbox.min.z, sh.lo.z)};
        bbox.max = {std::max(bbox.max.x, sh.hi.x), std::max(bbox.max.y, sh.hi.y),
                    std::max(bbox.max.z, sh.hi.z)};
    }
    drop_unused_vertices(mesh, used);

    report.triangles = tris.size();
    report.vertices = mesh.vertices.size();
    report.flipped_triangles = turns.flipped;
    report.inverted_shells = turns.inverted;
    report.inverted = turns.inverted > 0;
    report.shells = shells.size();
    report.internal_voids = turns.voids;
    report.bbox = bbox;
    report.volume_mm3 = volume / 6.0;
    add_warnings(report, splits, turns);
}

}  // namespace carve

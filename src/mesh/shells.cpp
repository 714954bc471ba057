// Nesting of closed shells by ray parity (shells.hpp).
#include "mesh/shells.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace carve::shells {

namespace {

using Tri = std::array<uint32_t, 3>;

// Projection of a point along the nesting rays: (u, v) across the ray, d along it.
struct Projected {
    double u, v, d;
};

// Edge function of q against p0 -> p1, computed from the lexicographically smaller end so
// that the two triangles sharing an edge get exactly opposite values.
double edge_function(const Projected& p0, const Projected& p1, const Projected& q) {
    const bool swap = p1.u < p0.u || (p1.u == p0.u && p1.v < p0.v);
    const Projected& a = swap ? p1 : p0;
    const Projected& b = swap ? p0 : p1;
    const double w = (b.u - a.u) * (q.v - a.v) - (b.v - a.v) * (q.u - a.u);
    return swap ? -w : w;
}

// A point exactly on an edge belongs to the triangle that runs the edge "downwards".
bool owns_edge(const Projected& p0, const Projected& p1) {
    return p1.v < p0.v || (p1.v == p0.v && p1.u < p0.u);
}

}  // namespace

void nesting_depths(const Mesh& mesh, const std::vector<uint32_t>& shell_of,
                    std::vector<Shell>& shells) {
    std::vector<uint32_t> closed;
    for (uint32_t s = 0; s < shells.size(); ++s)
        if (shells[s].closed) closed.push_back(s);
    if (closed.size() < 2) return;

    // A skew ray direction makes rays along faces or through edges of axis-aligned boxes unlikely.
    Vec3 d{1.0, 0.3141592653589793, 0.2718281828459045};
    const double dl = std::sqrt(dot(d, d));
    d = {d.x / dl, d.y / dl, d.z / dl};
    Vec3 u = cross(d, Vec3{0, 0, 1});
    const double ul = std::sqrt(dot(u, u));
    u = {u.x / ul, u.y / ul, u.z / ul};
    const Vec3 v = cross(d, u);
    auto project = [&](const Vec3& p) { return Projected{dot(p, u), dot(p, v), dot(p, d)}; };

    struct Query {
        Projected p;
        uint32_t shell;
    };
    std::vector<Query> queries;
    std::vector<uint32_t> query_count(shells.size(), 0);
    for (uint32_t s : closed) {
        std::array<uint32_t, 6> ex = shells[s].extreme;
        std::sort(ex.begin(), ex.end());
        for (size_t k = 0; k < ex.size(); ++k) {
            if (k > 0 && ex[k] == ex[k - 1]) continue;
            queries.push_back({project(mesh.vertices[ex[k]]), s});
            ++query_count[s];
        }
    }
    // Queries binned on a grid across the rays so that each triangle meets only nearby ones.
    double u0 = queries[0].p.u, u1 = u0, v0 = queries[0].p.v, v1 = v0;
    for (const Query& q : queries) {
        u0 = std::min(u0, q.p.u), u1 = std::max(u1, q.p.u);
        v0 = std::min(v0, q.p.v), v1 = std::max(v1, q.p.v);
    }
    const int g =
        std::clamp(static_cast<int>(std::ceil(std::sqrt(double(queries.size())))), 1, 256);
    const double cu = std::max(u1 - u0, 1e-9) / g, cv = std::max(v1 - v0, 1e-9) / g;
    auto cell_u = [&](double x) { return std::clamp(static_cast<int>((x - u0) / cu), 0, g - 1); };
    auto cell_v = [&](double y) { return std::clamp(static_cast<int>((y - v0) / cv), 0, g - 1); };
    std::vector<uint32_t> cell_first(g * g + 1, 0), cell_items(queries.size());
    for (const Query& q : queries) ++cell_first[cell_v(q.p.v) * g + cell_u(q.p.u) + 1];
    for (int c = 0; c < g * g; ++c) cell_first[c + 1] += cell_first[c];
    {
        std::vector<uint32_t> fill(cell_first.begin(), cell_first.end() - 1);
        for (uint32_t i = 0; i < queries.size(); ++i)
            cell_items[fill[cell_v(queries[i].p.v) * g + cell_u(queries[i].p.u)]++] = i;
    }

    std::vector<Projected> pv(mesh.vertices.size());
    for (size_t i = 0; i < pv.size(); ++i) pv[i] = project(mesh.vertices[i]);
    std::vector<uint64_t> hits;  // (query << 32) | shell crossed, once per crossing
    for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
        const uint32_t s = shell_of[t];
        if (!shells[s].closed) continue;
        const Tri& tri = mesh.triangles[t];
        Projected p0 = pv[tri[0]], p1 = pv[tri[1]], p2 = pv[tri[2]];
        const double tu0 = std::min({p0.u, p1.u, p2.u}), tu1 = std::max({p0.u, p1.u, p2.u});
        const double tv0 = std::min({p0.v, p1.v, p2.v}), tv1 = std::max({p0.v, p1.v, p2.v});
        if (tu1 < u0 || tu0 > u1 || tv1 < v0 || tv0 > v1) continue;
        double area = edge_function(p0, p1, p2);
        if (area == 0) continue;  // seen edge-on
        if (area < 0) std::swap(p1, p2), area = -area;
        for (int cy = cell_v(tv0); cy <= cell_v(tv1); ++cy) {
            for (int cx = cell_u(tu0); cx <= cell_u(tu1); ++cx) {
                const int c = cy * g + cx;
                for (uint32_t k = cell_first[c]; k < cell_first[c + 1]; ++k) {
                    const uint32_t qi = cell_items[k];
                    const Query& q = queries[qi];
                    if (q.shell == s || q.p.u < tu0 || q.p.u > tu1 || q.p.v < tv0 || q.p.v > tv1)
                        continue;
                    const double w0 = edge_function(p1, p2, q.p);
                    const double w1 = edge_function(p2, p0, q.p);
                    const double w2 = edge_function(p0, p1, q.p);
                    if (w0 < 0 || w1 < 0 || w2 < 0) continue;
                    if ((w0 == 0 && !owns_edge(p1, p2)) || (w1 == 0 && !owns_edge(p2, p0)) ||
                        (w2 == 0 && !owns_edge(p0, p1)))
                        continue;
                    const double sum = w0 + w1 + w2;
                    if (sum <= 0) continue;
                    const double depth = (w0 * p0.d + w1 * p1.d + w2 * p2.d) / sum;
                    if (depth > q.p.d) hits.push_back(uint64_t(qi) << 32 | s);
                }
            }
        }
    }
    std::sort(hits.begin(), hits.end());
    // inside[(query shell, other shell)] = queries of the first found inside the second
    std::vector<std::pair<uint64_t, uint32_t>> inside;
    for (size_t i = 0; i < hits.size();) {
        size_t j = i;
        while (j < hits.size() && hits[j] == hits[i]) ++j;
        if ((j - i) % 2 == 1) {
            const uint32_t qs = queries[hits[i] >> 32].shell;
            const uint32_t other = static_cast<uint32_t>(hits[i] & 0xFFFFFFFFu);
            inside.push_back({uint64_t(qs) << 32 | other, 1});
        }
        i = j;
    }
    std::sort(inside.begin(), inside.end());
    for (size_t i = 0; i < inside.size();) {
        size_t j = i;
        while (j < inside.size() && inside[j].first == inside[i].first) ++j;
        const uint32_t qs = static_cast<uint32_t>(inside[i].first >> 32);
        // Nested only with every extreme vertex inside: a shell that pokes out of the other
        // (a blade standing 0.1 mm deep in a plate, two overlapping spheres) is a second solid
        // the slicer unites with it, not a void. The majority this once asked for turned the
        // six blades of a plate inside out, and their slices were cut away from it.
        if (j - i == query_count[qs]) ++shells[qs].depth;
        i = j;
    }
}

}  // namespace carve::shells

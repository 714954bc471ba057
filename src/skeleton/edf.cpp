// The extended grassfire (Liu, Chambers, Letscher, Ju 2011) on the axis graph, and the pruning of
// the axis by EDF - R (the "erosion thickness": how much of the shape lies beyond a point).
//
// Why event driven rather than a plain leaves-first peel: a junction must take the d - 1
// *earliest* fires to reach it and burn into the branch whose fire comes last. A peel that
// visits leaves in arbitrary order would pick the wrong remaining branch at junctions.
#include <algorithm>
#include <cmath>

#include "skeleton/axis_graph.hpp"

namespace carve::skel {

double site_distance(const AxisSite& s, double x, double y) {
    if (s.point) return std::hypot(x - s.ax, y - s.ay);
    const double dx = s.bx - s.ax, dy = s.by - s.ay;
    const double len2 = dx * dx + dy * dy;
    double t = len2 > 0 ? ((x - s.ax) * dx + (y - s.ay) * dy) / len2 : 0.0;
    t = std::clamp(t, 0.0, 1.0);
    return std::hypot(x - (s.ax + t * dx), y - (s.ay + t * dy));
}

void AxisGraph::add_edge(int a, int b, const AxisSite& site) {
    if (a == b) return;
    const double l = std::hypot(nodes[b].x - nodes[a].x, nodes[b].y - nodes[a].y);
    edges.push_back({a, b, l, site});
}

namespace {

constexpr uint8_t kArrivedA = 1, kArrivedB = 2;

bool later(const Burn::Event& p, const Burn::Event& q) {
    return p.t > q.t;
}

}  // namespace

void burn(const AxisGraph& g, Burn& st) {
    const int n = int(g.nodes.size());
    const int m = int(g.edges.size());
    st.offset.assign(n + 1, 0);
    for (const AxisEdge& e : g.edges) {
        ++st.offset[e.a + 1];
        ++st.offset[e.b + 1];
    }
    for (int v = 0; v < n; ++v) st.offset[v + 1] += st.offset[v];
    st.adj.resize(2 * size_t(m));
    st.arrived.assign(n, 0);  // used as a fill cursor first
    for (int i = 0; i < m; ++i) {
        st.adj[st.offset[g.edges[i].a] + st.arrived[g.edges[i].a]++] = i;
        st.adj[st.offset[g.edges[i].b] + st.arrived[g.edges[i].b]++] = i;
    }
    st.arrived.assign(n, 0);
    st.edf.assign(n, kInfinity);
    st.from_a.assign(m, kInfinity);
    st.from_b.assign(m, kInfinity);
    st.flags.assign(m, 0);
    st.burnt.assign(n, 0);
    st.heap.clear();

    for (int v = 0; v < n; ++v)
        if (st.offset[v + 1] - st.offset[v] <= 1) st.heap.push_back({g.nodes[v].r, v, -1});
    std::make_heap(st.heap.begin(), st.heap.end(), later);

    while (!st.heap.empty()) {
        std::pop_heap(st.heap.begin(), st.heap.end(), later);
        const Burn::Event ev = st.heap.back();
        st.heap.pop_back();
        const int v = ev.node;
        if (ev.edge >= 0) st.flags[ev.edge] |= (g.edges[ev.edge].a == v ? kArrivedA : kArrivedB);
        if (st.burnt[v]) continue;
        if (ev.edge >= 0) ++st.arrived[v];
        const int degree = st.offset[v + 1] - st.offset[v];
        if (st.arrived[v] + 1 < degree) continue;  // more than one branch still unburnt
        st.burnt[v] = 1;
        st.edf[v] = ev.t;
        for (int k = st.offset[v]; k < st.offset[v + 1]; ++k) {
            const int e = st.adj[k];
            const AxisEdge& edge = g.edges[e];
            const bool at_a = edge.a == v;
            if (st.flags[e] & (at_a ? kArrivedA : kArrivedB)) continue;
            (at_a ? st.from_a : st.from_b)[e] = ev.t;
            const int w = at_a ? edge.b : edge.a;
            if (!st.burnt[w]) {
                st.heap.push_back({ev.t + edge.length, w, e});
                std::push_heap(st.heap.begin(), st.heap.end(), later);
            }
            break;  // d - 1 edges have arrived: at most one is left
        }
    }
}

namespace {

struct Piece {
    int edge;
    double s0, s1;
    bool whole_start, whole_end;  // s0 == 0 / s1 == length: ends at the graph node itself
};

DPoint along(const AxisGraph& g, int e, double s) {
    const AxisEdge& edge = g.edges[e];
    const AxisNode& a = g.nodes[edge.a];
    const AxisNode& b = g.nodes[edge.b];
    const double t = edge.length > 0 ? s / edge.length : 0.0;
    return {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
}

// EDF - R - threshold at distance s along e (concave in s).
double margin(const AxisGraph& g, const Burn& st, int e, double s, double threshold) {
    const DPoint p = along(g, e, s);
    return edf_along(st, g, e, s) - site_distance(g.edges[e].site, p.x, p.y) - threshold;
}

// The crossing between lo (margin >= 0) and hi (margin < 0); lo may be above or below hi.
double crossing(const AxisGraph& g, const Burn& st, int e, double lo, double hi, double thr) {
    for (int i = 0; i < 60 && std::abs(hi - lo) > 1e-4; ++i) {
        const double mid = 0.5 * (lo + hi);
        (margin(g, st, e, mid, thr) >= 0 ? lo : hi) = mid;
    }
    return lo;
}

// Finds the kept interval of an edge whose two ends are pruned; false if there is none.
bool middle_interval(const AxisGraph& g, const Burn& st, int e, double thr, double& s0,
                     double& s1) {
    const AxisEdge& edge = g.edges[e];
    const double l = edge.length;
    if (l <= 0) return false;
    // Cheap bound first: EDF is at most its peak on the edge, R drops by at most l/2 below the
    // mean of the end radii (R is 1-Lipschitz).
    double peak;
    if (std::isfinite(st.from_a[e]) && std::isfinite(st.from_b[e]))
        peak = 0.5 * (st.from_a[e] + st.from_b[e] + l);
    else
        peak = std::min(st.from_a[e], st.from_b[e]) + l;
    const double r_min = std::max(0.0, 0.5 * (g.nodes[edge.a].r + g.nodes[edge.b].r - l));
    if (peak - r_min < thr) return false;
    // Golden-section search for the maximum of the concave margin.
    const double phi = 0.5 * (std::sqrt(5.0) - 1.0);
    double lo = 0, hi = l;
    double x1 = hi - phi * (hi - lo), x2 = lo + phi * (hi - lo);
    double f1 = margin(g, st, e, x1, thr), f2 = margin(g, st, e, x2, thr);
    for (int i = 0; i < 80 && hi - lo > 1e-4; ++i) {
        if (f1 >= 0 || f2 >= 0) break;
        if (f1 < f2) {
            lo = x1;
            x1 = x2;
            f1 = f2;
            x2 = lo + phi * (hi - lo);
            f2 = margin(g, st, e, x2, thr);
        } else {
            hi = x2;
            x2 = x1;
            f2 = f1;
            x1 = hi - phi * (hi - lo);
            f1 = margin(g, st, e, x1, thr);
        }
    }
    double top;
    if (f1 >= 0)
        top = x1;
    else if (f2 >= 0)
        top = x2;
    else
        return false;
    s0 = crossing(g, st, e, top, 0.0, thr);
    s1 = crossing(g, st, e, top, l, thr);
    return s1 > s0;
}

struct UnionFind {
    std::vector<int> parent;
    void reset(int n) {
        parent.resize(n);
        for (int i = 0; i < n; ++i) parent[i] = i;
    }
    int find(int v) {
        while (parent[v] != v) v = parent[v] = parent[parent[v]];
        return v;
    }
    void unite(int a, int b) { parent[find(a)] = find(b); }
};

}  // namespace

void prune(const AxisGraph& g, const Burn& st, double thr, std::vector<Polyline>& out) {
    const int n = int(g.nodes.size());
    const int m = int(g.edges.size());
    if (n == 0) return;

    std::vector<Piece> pieces;
    pieces.reserve(m);
    for (int e = 0; e < m; ++e) {
        const AxisEdge& edge = g.edges[e];
        const double l = edge.length;
        const double fa = edf_along(st, g, e, 0) - g.nodes[edge.a].r - thr;
        const double fb = edf_along(st, g, e, l) - g.nodes[edge.b].r - thr;
        if (fa >= 0 && fb >= 0) {
            pieces.push_back({e, 0, l, true, true});
        } else if (fa >= 0) {
            const double s = crossing(g, st, e, 0.0, l, thr);
            if (s > 0) pieces.push_back({e, 0, s, true, false});
        } else if (fb >= 0) {
            const double s = crossing(g, st, e, l, 0.0, thr);
            if (s < l) pieces.push_back({e, s, l, false, true});
        } else {
            double s0, s1;
            if (middle_interval(g, st, e, thr, s0, s1)) pieces.push_back({e, s0, s1, false, false});
        }
    }

    // Connected parts of the axis that lost everything keep their last burnt point.
    UnionFind uf;
    uf.reset(n);
    for (const AxisEdge& edge : g.edges) uf.unite(edge.a, edge.b);
    std::vector<uint8_t> seeded(n, 0);
    for (const Piece& p : pieces) seeded[uf.find(g.edges[p.edge].a)] = 1;
    std::vector<double> best(n, -kInfinity);
    std::vector<DPoint> best_point(n);
    auto offer = [&](int root, double t, DPoint p) {
        if (t > best[root]) best[root] = t, best_point[root] = p;
    };
    for (int v = 0; v < n; ++v) {
        const int root = uf.find(v);
        if (seeded[root]) continue;
        const double t = std::isfinite(st.edf[v]) ? st.edf[v] : g.nodes[v].r;
        offer(root, t, {g.nodes[v].x, g.nodes[v].y});
    }
    for (int e = 0; e < m; ++e) {
        const int root = uf.find(g.edges[e].a);
        if (seeded[root]) continue;
        if (!std::isfinite(st.from_a[e]) || !std::isfinite(st.from_b[e])) continue;
        const double l = g.edges[e].length;
        const double s = std::clamp(0.5 * (st.from_b[e] + l - st.from_a[e]), 0.0, l);
        offer(root, edf_along(st, g, e, s), along(g, e, s));
    }
    for (int v = 0; v < n; ++v)
        if (uf.find(v) == v && !seeded[v] && best[v] > -kInfinity) out.push_back({best_point[v]});

    if (pieces.empty()) return;

    // The kept pieces as a small graph: graph nodes they reach, plus one node per cut.
    std::vector<int> node_id(n, -1);
    std::vector<DPoint> pts;
    struct Link {
        int u, v;
    };
    std::vector<Link> links;
    links.reserve(pieces.size());
    auto graph_node = [&](int v) {
        if (node_id[v] < 0) {
            node_id[v] = int(pts.size());
            pts.push_back({g.nodes[v].x, g.nodes[v].y});
        }
        return node_id[v];
    };
    for (const Piece& p : pieces) {
        const AxisEdge& edge = g.edges[p.edge];
        int u, v;
        if (p.whole_start) {
            u = graph_node(edge.a);
        } else {
            u = int(pts.size());
            pts.push_back(along(g, p.edge, p.s0));
        }
        if (p.whole_end) {
            v = graph_node(edge.b);
        } else {
            v = int(pts.size());
            pts.push_back(along(g, p.edge, p.s1));
        }
        links.push_back({u, v});
    }
    const int k = int(pts.size());
    std::vector<int> off(k + 1, 0), inc(2 * links.size());
    for (const Link& l : links) ++off[l.u + 1], ++off[l.v + 1];
    for (int i = 0; i < k; ++i) off[i + 1] += off[i];
    std::vector<int> fill(off.begin(), off.end() - 1);
    for (int i = 0; i < int(links.size()); ++i) {
        inc[fill[links[i].u]++] = i;
        inc[fill[links[i].v]++] = i;
    }
    std::vector<uint8_t> used(links.size(), 0);
    auto degree = [&](int v) { return off[v + 1] - off[v]; };
    auto walk = [&](int start, int first_link) {
        Polyline line{pts[start]};
        int v = start, l = first_link;
        while (true) {
            used[l] = 1;
            v = links[l].u == v ? links[l].v : links[l].u;
            line.push_back(pts[v]);
            if (degree(v) != 2 || v == start) break;
            int next = -1;
            for (int j = off[v]; j < off[v + 1]; ++j)
                if (!used[inc[j]]) next = inc[j];
            if (next < 0) break;
            l = next;
        }
        out.push_back(std::move(line));
    };
    for (int v = 0; v < k; ++v) {
        if (degree(v) == 2) continue;
        for (int j = off[v]; j < off[v + 1]; ++j)
            if (!used[inc[j]]) walk(v, inc[j]);
    }
    for (int i = 0; i < int(links.size()); ++i)  // what is left are cycles
        if (!used[i]) walk(links[i].u, i);
}

}  // namespace carve::skel

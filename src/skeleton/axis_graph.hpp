// SKEL internals: the medial axis as a graph of straight pieces, and its pruning by the extended
// distance function (EDF) of Liu et al. 2011.
//
// Private to src/skeleton (and its tests). Coordinates are doubles in whatever frame the caller
// built the graph in; every length (R, EDF, threshold) is in that frame's units.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

namespace carve::skel {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

struct DPoint {
    double x = 0, y = 0;
};

// The boundary feature an axis edge is equidistant from: R at any point of the edge is the
// distance to it. Kept so that the pruning cut is placed with the true R, not an interpolation
// (R is hyperbolic along the bisector of two reflex vertices, for instance).
struct AxisSite {
    double ax = 0, ay = 0, bx = 0, by = 0;
    bool point = true;  // a boundary vertex (a) rather than a boundary segment (a, b)
};

double site_distance(const AxisSite& site, double x, double y);

struct AxisNode {
    double x = 0, y = 0;
    double r = 0;  // distance to the boundary: radius of the maximal disk centred here
};

struct AxisEdge {
    int a = 0, b = 0;
    double length = 0;
    AxisSite site;
};

// Straight pieces: a parabolic arc is already a chain of chords with their own nodes.
struct AxisGraph {
    std::vector<AxisNode> nodes;
    std::vector<AxisEdge> edges;
    void clear() {
        nodes.clear();
        edges.clear();
    }
    int add_node(double x, double y, double r) {
        nodes.push_back({x, y, r});
        return int(nodes.size()) - 1;
    }
    void add_edge(int a, int b, const AxisSite& site);
};

// The extended grassfire on the axis graph.
//
// Fire starts at every leaf v at time R(v) (when Blum's grassfire reaches it) and runs along the
// axis at unit speed. A node of degree d catches fire once d - 1 of its edges have burnt up to
// it (it would otherwise cut the unburnt axis in two), at the latest of those arrival times; it
// then burns into its last edge. Parts of cycles never catch fire: their EDF stays infinite.
// Event driven (a heap ordered by time), O(E log E).
struct Burn {
    std::vector<double> edf;     // per node: time it burns, kInfinity if never
    std::vector<double> from_a;  // per edge: time the fire enters it at node a, else kInfinity
    std::vector<double> from_b;  // per edge: same at node b
    std::vector<int> offset;     // adjacency (CSR): edges of node v are adj[offset[v]..offset[v+1])
    std::vector<int> adj;
    // scratch
    std::vector<int> arrived;
    std::vector<uint8_t> flags;
    std::vector<uint8_t> burnt;
    struct Event {
        double t;
        int node, edge;
    };
    std::vector<Event> heap;
};

void burn(const AxisGraph& graph, Burn& state);

// EDF at distance s from node a along edge e.
inline double edf_along(const Burn& state, const AxisGraph& graph, int e, double s) {
    const double l = graph.edges[e].length;
    double t = state.from_a[e] + s;
    double u = state.from_b[e] + (l - s);
    return t < u ? t : u;
}

using Polyline = std::vector<DPoint>;

// Keeps the points where EDF - R >= threshold, cutting edges where EDF - R crosses it (EDF - R
// is concave along an edge, so each edge keeps one interval at most). A connected part of the
// axis that loses everything keeps the point that burns last (its centre: the extended medial
// axis of a tree-shaped axis in Liu et al.), so every region component still gets a seed.
// Output: open polylines between junctions and ends; a cycle is closed by repeating its first
// point; a lone point is a one-point polyline.
void prune(const AxisGraph& graph, const Burn& state, double threshold, std::vector<Polyline>& out);

}  // namespace carve::skel

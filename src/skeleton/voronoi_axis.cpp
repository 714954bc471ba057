// The inner medial axis of a polygon from Boost.Polygon's segment Voronoi diagram.
//
// Which Voronoi edges lie inside: an edge of a boundary segment's cell lies entirely on one side
// of that segment (the cell touches its segment only there), and the interior is on the left of
// every contour edge; so one signed distance decides. An edge between two vertex cells lies
// inside exactly when the vertex is reflex (a convex vertex's cell is outside). Only vertices
// shared by several contours (touching contours) need a point-in-region test. No O(n) test per
// edge.
//
// The builder is guarded: it writes through pointers into vectors it reserved beforehand, so a
// run that would create more edges than a Voronoi diagram can have is stopped before it
// reallocates them (and before it loops), and a cycle of zero-length edges (other than around
// a vertex cell collapsed to its vertex), which its clean-up pass cannot merge, is refused
// before that pass runs. The diagram is then checked (every
// segment has its cell, no ray starts inside, axis vertices are equidistant from their sites,
// every axis end is a boundary vertex); the caller retries in a rotated frame on failure.
#include "skeleton/voronoi_axis.hpp"

#include <algorithm>
#include <boost/polygon/voronoi.hpp>
#include <cmath>
#include <optional>

#include "base/stage_timer.hpp"
#include "skeleton/circle_events.hpp"

namespace carve::skel {

namespace bp = boost::polygon;

namespace {

struct BuildFailure {};

// A boundary segment; `reflex` and `shared` describe its start vertex.
struct Seg {
    double ax, ay, bx, by;
    int next;
    bool reflex;
    bool shared;  // the start point is also a vertex elsewhere (touching contours)
};

// voronoi_diagram with the builder's output hooks wrapped (the builder calls them on the static
// type it is given, so hiding the base versions is enough).
class GuardedDiagram : public bp::voronoi_diagram<double> {
    using Base = bp::voronoi_diagram<double>;

  public:
    void _reserve(std::size_t num_sites) {
        sites_ = num_sites;
        Base::_reserve(num_sites);
    }

    template <typename CT>
    std::pair<void*, void*> _insert_new_edge(const bp::detail::site_event<CT>& site1,
                                             const bp::detail::site_event<CT>& site2) {
        guard(cells().empty() ? 2 : 1, 0);
        return Base::_insert_new_edge(site1, site2);
    }

    template <typename CT1, typename CT2>
    std::pair<void*, void*> _insert_new_edge(const bp::detail::site_event<CT1>& site1,
                                             const bp::detail::site_event<CT1>& site3,
                                             const bp::detail::circle_event<CT2>& circle,
                                             void* data12, void* data23) {
        guard(0, 1);
        return Base::_insert_new_edge(site1, site3, circle, data12, data23);
    }

    void _build() {
        refuse_degenerate_cycles();
        Base::_build();
    }

  private:
    void guard(std::size_t new_cells, std::size_t new_vertices) const {
        if (edges().size() + 2 > edges().capacity() ||
            cells().size() + new_cells > cells().capacity() ||
            vertices().size() + new_vertices > vertices().capacity() ||
            edges().size() + 2 > 6 * sites_ + 16)
            throw BuildFailure{};
    }

    // The clean-up pass merges the two ends of every zero-length edge. Zero-length edges around
    // the cell of a contour vertex are normal where contours touch (the cell shrinks to the
    // vertex itself); any other cycle of them would make the pass merge a vertex with itself.
    void refuse_degenerate_cycles() {
        const auto& vs = vertices();
        const auto& es = edges();
        parent_.resize(vs.size());
        for (std::size_t i = 0; i < vs.size(); ++i) parent_[i] = i;
        auto find = [&](std::size_t v) {
            while (parent_[v] != v) v = parent_[v] = parent_[parent_[v]];
            return v;
        };
        bp::voronoi_diagram_traits<double>::vertex_equality_predicate_type same;
        for (std::size_t i = 0; i + 1 < es.size(); i += 2) {
            const vertex_type* v1 = es[i].vertex0();
            const vertex_type* v2 = es[i].vertex1();
            if (!v1 || !v2 || !same(*v1, *v2)) continue;
            const std::size_t r1 = find(std::size_t(v1 - vs.data()));
            const std::size_t r2 = find(std::size_t(v2 - vs.data()));
            if (r1 == r2 && !collapsed_vertex_cell(es[i], *v1)) throw BuildFailure{};
            parent_[r1] = r2;
        }
    }

    bool collapsed_vertex_cell(const edge_type& e, const vertex_type& v) const {
        for (const cell_type* c : {e.cell(), e.twin()->cell()}) {
            if (!c->contains_point() || !segs_) continue;
            const Seg& s = (*segs_)[c->source_index()];
            const bool start = c->source_category() == bp::SOURCE_CATEGORY_SEGMENT_START_POINT;
            if ((start ? s.ax : s.bx) == v.x() && (start ? s.ay : s.by) == v.y()) return true;
        }
        return false;
    }

    std::size_t sites_ = 0;
    std::vector<std::size_t> parent_;

  public:
    const std::vector<Seg>* segs_ = nullptr;  // the input, to locate vertex sites
};

struct VertexKey {
    Coord x, y;
    int seg;
};

}  // namespace

struct VoronoiWorkspace {
    std::optional<
        bp::voronoi_builder<int32_t, bp::detail::voronoi_ctype_traits<int32_t>, LocalPredicates>>
        builder;
    GuardedDiagram diagram;
    std::vector<Seg> segs;
    std::vector<VertexKey> keys;
    std::vector<uint8_t> seen;
    std::vector<int> vertex_node;
    std::vector<int> degree;
};

void VoronoiWorkspaceDeleter::operator()(VoronoiWorkspace* w) const {
    delete w;
}
VoronoiWorkspacePtr make_voronoi_workspace() {
    return VoronoiWorkspacePtr(new VoronoiWorkspace);
}

const char* to_string(AxisStatus status) {
    switch (status) {
        case AxisStatus::kOk:
            return "ok";
        case AxisStatus::kOutOfRange:
            return "coordinates out of range";
        case AxisStatus::kBuilderAborted:
            return "builder aborted";
        case AxisStatus::kMissingCell:
            return "segment without a cell";
        case AxisStatus::kInteriorRay:
            return "infinite edge inside the region";
        case AxisStatus::kNotEquidistant:
            return "axis vertex not equidistant from its sites";
        case AxisStatus::kDanglingAxis:
            return "axis end inside the region";
    }
    return "?";
}

namespace {

using Cell = bp::voronoi_diagram<double>::cell_type;
using Edge = bp::voronoi_diagram<double>::edge_type;
using Vertex = bp::voronoi_diagram<double>::vertex_type;

constexpr Coord kMaxCoord = Coord(1) << 30;
constexpr double kOnBoundary = 0.05;  // units of the (scaled) frame

// The segment whose start point is the vertex site of a point cell.
int vertex_segment(const std::vector<Seg>& segs, const Cell& cell) {
    const int i = int(cell.source_index());
    return cell.source_category() == bp::SOURCE_CATEGORY_SEGMENT_START_POINT ? i : segs[i].next;
}

AxisSite cell_site(const std::vector<Seg>& segs, const Cell& cell) {
    if (cell.contains_segment()) {
        const Seg& s = segs[cell.source_index()];
        return {s.ax, s.ay, s.bx, s.by, false};
    }
    const Seg& s = segs[vertex_segment(segs, cell)];
    return {s.ax, s.ay, 0, 0, true};
}

// Signed distance of (x, y) from the line of s, positive on the left (the interior side).
double side(const Seg& s, double x, double y) {
    const double dx = s.bx - s.ax, dy = s.by - s.ay;
    return (dx * (y - s.ay) - dy * (x - s.ax)) / std::hypot(dx, dy);
}

enum Where { kOutside, kInside, kUnknown };

Where classify(const std::vector<Seg>& segs, const Paths& contours, const Edge& e) {
    const Cell& c1 = *e.cell();
    const Cell& c2 = *e.twin()->cell();
    const Vertex* v0 = e.vertex0();
    const Vertex* v1 = e.vertex1();
    const Cell* sc = c1.contains_segment() ? &c1 : (c2.contains_segment() ? &c2 : nullptr);
    if (sc) {
        const Seg& s = segs[sc->source_index()];
        const double d0 = v0 ? side(s, v0->x(), v0->y()) : 0.0;
        const double d1 = v1 ? side(s, v1->x(), v1->y()) : 0.0;
        const double d = std::abs(d0) >= std::abs(d1) ? d0 : d1;
        if (d > 1e-3) return kInside;
        if (d < -1e-3) return kOutside;
        return kUnknown;
    }
    const Seg& s = segs[vertex_segment(segs, c1)];
    if (!s.shared) return s.reflex ? kInside : kOutside;
    // A vertex shared by touching contours: which of its wedges holds the edge decides.
    if (!v0 || !v1) return kUnknown;
    const Point mid(std::llround(0.5 * (v0->x() + v1->x())),
                    std::llround(0.5 * (v0->y() + v1->y())));
    int winding = 0;
    for (const Path& c : contours) {
        const int r = ClipperLib::PointInPolygon(mid, c);
        if (r == -1) return kUnknown;
        if (r == 1) winding += ClipperLib::Orientation(c) ? 1 : -1;
    }
    return winding != 0 ? kInside : kOutside;
}

// Chords of the parabola equidistant from focus f and the line of segment s, from p0 to p1,
// appended as nodes after `from`; returns the last node (to be joined to the edge's end).
int add_parabola(AxisGraph& g, int from, const Vertex& p0, const Vertex& p1, const AxisSite& focus,
                 const Seg& s, double max_error) {
    const double len = std::hypot(s.bx - s.ax, s.by - s.ay);
    const double ux = (s.bx - s.ax) / len, uy = (s.by - s.ay) / len;
    const double nx = -uy, ny = ux;
    const double fx = (focus.ax - s.ax) * ux + (focus.ay - s.ay) * uy;
    const double fy = (focus.ax - s.ax) * nx + (focus.ay - s.ay) * ny;
    const double x0 = (p0.x() - s.ax) * ux + (p0.y() - s.ay) * uy;
    const double x1 = (p1.x() - s.ax) * ux + (p1.y() - s.ay) * uy;
    if (std::abs(fy) < 1e-9) return from;
    // y = ((x - fx)^2 + fy^2) / (2 fy) has second derivative 1 / fy: a chord of width w deviates
    // by w^2 / (8 |fy|) at most.
    const double w = std::sqrt(8.0 * std::abs(fy) * std::max(max_error, 1e-3));
    const int pieces = std::clamp(int(std::ceil(std::abs(x1 - x0) / w)), 1, 512);
    int last = from;
    for (int k = 1; k < pieces; ++k) {
        const double x = x0 + (x1 - x0) * k / pieces;
        const double y = ((x - fx) * (x - fx) + fy * fy) / (2.0 * fy);
        const int node = g.add_node(s.ax + x * ux + y * nx, s.ay + x * uy + y * ny, std::abs(y));
        g.add_edge(last, node, focus);
        last = node;
    }
    return last;
}

}  // namespace

AxisStatus build_axis(const Paths& contours, double max_arc_error, VoronoiWorkspace& ws,
                      AxisGraph& g) {
    StageTimer timer(Stage::kVoronoi);
    g.clear();
    auto& segs = ws.segs;
    segs.clear();
    for (const Path& c : contours) {
        const int n = int(c.size());
        if (n < 3) continue;
        const int base = int(segs.size());
        for (int j = 0; j < n; ++j) {
            const Point& p = c[(j + n - 1) % n];
            const Point& a = c[j];
            const Point& b = c[(j + 1) % n];
            if (std::abs(a.X) >= kMaxCoord || std::abs(a.Y) >= kMaxCoord)
                return AxisStatus::kOutOfRange;
            const double turn =
                double(a.X - p.X) * double(b.Y - a.Y) - double(a.Y - p.Y) * double(b.X - a.X);
            segs.push_back({double(a.X), double(a.Y), double(b.X), double(b.Y), base + (j + 1) % n,
                            turn < 0, false});
        }
    }
    if (segs.empty()) return AxisStatus::kOk;

    ws.keys.clear();
    for (int i = 0; i < int(segs.size()); ++i)
        ws.keys.push_back({Coord(segs[i].ax), Coord(segs[i].ay), i});
    std::sort(ws.keys.begin(), ws.keys.end(), [](const VertexKey& p, const VertexKey& q) {
        return p.x != q.x ? p.x < q.x : p.y < q.y;
    });
    for (size_t i = 1; i < ws.keys.size(); ++i)
        if (ws.keys[i].x == ws.keys[i - 1].x && ws.keys[i].y == ws.keys[i - 1].y)
            segs[ws.keys[i].seg].shared = segs[ws.keys[i - 1].seg].shared = true;

    if (!ws.builder) ws.builder.emplace();
    ws.builder->clear();
    for (const Seg& s : segs)
        ws.builder->insert_segment(int32_t(s.ax), int32_t(s.ay), int32_t(s.bx), int32_t(s.by));
    auto& vd = ws.diagram;
    vd.clear();
    vd.segs_ = &segs;
    try {
        ws.builder->construct(&vd);
    } catch (const BuildFailure&) {
        ws.builder.reset();  // its sweep state is left half-way
        vd.clear();
        return AxisStatus::kBuilderAborted;
    }

    ws.seen.assign(segs.size(), 0);
    for (const Cell& cell : vd.cells())
        if (cell.contains_segment() && !cell.is_degenerate()) ws.seen[cell.source_index()] = 1;
    for (uint8_t s : ws.seen)
        if (!s) return AxisStatus::kMissingCell;

    const Vertex* vbase = vd.vertices().data();
    ws.vertex_node.assign(vd.num_vertices(), -1);
    bool equidistant = true;
    // A vertex on the boundary (a corner, or a point where contours touch) ends every axis
    // branch that reaches it: one node per branch, so that no fire passes through the wall.
    auto node_of = [&](const Vertex& v, const Cell& c1, const Cell& c2) {
        int& id = ws.vertex_node[size_t(&v - vbase)];
        if (id >= 0) return id;
        const double r1 = site_distance(cell_site(segs, c1), v.x(), v.y());
        const double r2 = site_distance(cell_site(segs, c2), v.x(), v.y());
        if (std::abs(r1 - r2) > 1e-6 * r1 + 0.05) equidistant = false;
        const double r = 0.5 * (r1 + r2);
        const int node = g.add_node(v.x(), v.y(), r);
        if (r > kOnBoundary) id = node;
        return node;
    };

    const auto& edges = vd.edges();
    for (size_t i = 0; i < edges.size(); ++i) {
        const Edge& e = edges[i];
        if (e.twin() < &e || !e.is_primary())
            continue;  // each pair once; secondary edges end
                       // at the vertex of their own segment
        const Where where = classify(segs, contours, e);
        if (!e.is_finite()) {
            if (where == kInside) return AxisStatus::kInteriorRay;
            continue;
        }
        if (where != kInside) continue;
        const Cell& c1 = *e.cell();
        const Cell& c2 = *e.twin()->cell();
        const int a = node_of(*e.vertex0(), c1, c2);
        const int b = node_of(*e.vertex1(), c1, c2);
        if (e.is_linear()) {
            g.add_edge(a, b, cell_site(segs, c1));
            continue;
        }
        const Cell& point_cell = c1.contains_point() ? c1 : c2;
        const Cell& seg_cell = c1.contains_point() ? c2 : c1;
        const AxisSite focus = cell_site(segs, point_cell);
        const int last = add_parabola(g, a, *e.vertex0(), *e.vertex1(), focus,
                                      segs[seg_cell.source_index()], max_arc_error);
        g.add_edge(last, b, focus);
    }
    if (!equidistant) return AxisStatus::kNotEquidistant;

    // Every end of a polygon's inner medial axis is a convex boundary vertex (R = 0); an end
    // with R > 0 means the builder dropped an edge.
    ws.degree.assign(g.nodes.size(), 0);
    for (const AxisEdge& e : g.edges) ++ws.degree[e.a], ++ws.degree[e.b];
    for (size_t v = 0; v < g.nodes.size(); ++v)
        if (ws.degree[v] == 1 && g.nodes[v].r > kOnBoundary) return AxisStatus::kDanglingAxis;
    return AxisStatus::kOk;
}

}  // namespace carve::skel

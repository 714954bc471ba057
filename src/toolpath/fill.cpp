// Solid cover fill: scanlines per component, joined along the boundary into zig-zags.
//
// The scanline/edge intersections are computed on the original integer edges (as an edge index
// and a parameter), so the line ends land exactly on the region's boundary and the connectors
// can follow the boundary contour between two consecutive ends without any inside test.
#include "toolpath/fill.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <utility>

#include "geometry/polygon.hpp"
#include "skeleton/skeleton.hpp"
#include "toolpath/beads.hpp"

namespace carve {

namespace {

// The widest thin-strip bead, in line widths.
constexpr double kMaxThinFlow = 1.6;

struct Hit {
    double u;  // position along the scanline
    int contour;
    int edge;
    double t;  // parameter on the edge
};

// One end of a scanline segment, on the boundary of the region.
struct End {
    int line = 0;
    int contour = 0;
    int edge = 0;
    double param = 0;  // arc length from the contour's first vertex
    Point xy;
};

double edge_length(const Point& a, const Point& b) {
    return std::hypot(double(b.X - a.X), double(b.Y - a.Y));
}

void push_unique(Path& path, const Point& p) {
    if (path.empty() || path.back() != p) path.push_back(p);
}

// The scanlines across a component at an angle: n lines at v = v0 + k dv in the frame turned
// by it (u along the lines), each flow times the line width wide.
struct ScanFrame {
    double cs = 1, sn = 0;
    int n = 1;
    double v0 = 0, dv = 0, flow = 1.0;
    double u_of(const Point& p) const { return cs * double(p.X) + sn * double(p.Y); }
    double v_of(const Point& p) const { return -sn * double(p.X) + cs * double(p.Y); }
};

// Lines just inside the component's extremes (a line exactly through an extreme vertex has no
// length); none when it has no extent across them.
std::optional<ScanFrame> scan_frame(const Paths& comp, double angle, Coord w) {
    ScanFrame f;
    f.cs = std::cos(angle), f.sn = std::sin(angle);
    double vmin = std::numeric_limits<double>::max(), vmax = std::numeric_limits<double>::lowest();
    for (const Point& p : comp.front()) {
        vmin = std::min(vmin, f.v_of(p));
        vmax = std::max(vmax, f.v_of(p));
    }
    if (!(vmax > vmin)) return std::nullopt;
    const double eps = 2.0;
    const double lo = vmin + eps, hi = vmax - eps, width = double(w);
    f.v0 = 0.5 * (vmin + vmax);
    if (hi - lo > 0.5 * width) {
        f.n = static_cast<int>(std::ceil((hi - lo) / width - 1e-9)) + 1;
        f.v0 = lo;
        f.dv = (hi - lo) / (f.n - 1);
        // n lines of width flow * w cover the component's extent plus half a line each side.
        f.flow = std::min(1.0, (vmax - vmin + width) / (f.n * width));
    }
    return f;
}

// Scanline hits, bucketed per line, and each contour's arc length at its vertices.
struct ScanHits {
    std::vector<std::vector<Hit>> hits;
    std::vector<std::vector<double>> cum;
};

ScanHits scan_hits(const Paths& comp, const ScanFrame& f) {
    ScanHits out;
    out.hits.resize(size_t(f.n));
    out.cum.resize(comp.size());
    for (size_t ci = 0; ci < comp.size(); ++ci) {
        const Path& c = comp[ci];
        const size_t m = c.size();
        std::vector<double>& cum = out.cum[ci];
        cum.resize(m + 1, 0.0);
        for (size_t e = 0; e < m; ++e) {
            const Point& a = c[e];
            const Point& b = c[(e + 1) % m];
            cum[e + 1] = cum[e] + edge_length(a, b);
            const double va = f.v_of(a), vb = f.v_of(b);
            if (va == vb) continue;
            const double elo = std::min(va, vb), ehi = std::max(va, vb);
            int k0 = 0;
            if (f.dv > 0) k0 = std::max(0, static_cast<int>(std::floor((elo - f.v0) / f.dv)));
            // Half-open [elo, ehi): a vertex is counted once, a local extreme twice or not at all.
            for (int k = k0; k < f.n; ++k) {
                const double vk = f.v0 + k * f.dv;
                if (vk >= ehi) break;
                if (vk < elo) continue;
                const double t = (vk - va) / (vb - va);
                const double ua = f.u_of(a), ub = f.u_of(b);
                out.hits[size_t(k)].push_back({ua + t * (ub - ua), int(ci), int(e), t});
                if (f.dv == 0) break;
            }
        }
    }
    return out;
}

// The scanlines' segments inside the component: ends 2i and 2i + 1.
std::vector<End> segment_ends(const Paths& comp, ScanHits& scan) {
    std::vector<End> ends;
    auto make_end = [&](int line, const Hit& h) {
        const Path& c = comp[h.contour];
        const Point& a = c[h.edge];
        const Point& b = c[(h.edge + 1) % c.size()];
        const std::vector<double>& cum = scan.cum[h.contour];
        End e;
        e.line = line;
        e.contour = h.contour;
        e.edge = h.edge;
        e.param = cum[h.edge] + h.t * (cum[h.edge + 1] - cum[h.edge]);
        e.xy = Point(static_cast<Coord>(std::llround(double(a.X) + h.t * double(b.X - a.X))),
                     static_cast<Coord>(std::llround(double(a.Y) + h.t * double(b.Y - a.Y))));
        return e;
    };
    for (int k = 0; k < int(scan.hits.size()); ++k) {
        auto& hk = scan.hits[size_t(k)];
        std::sort(hk.begin(), hk.end(), [](const Hit& a, const Hit& b) { return a.u < b.u; });
        for (size_t i = 0; i + 1 < hk.size(); i += 2) {
            if (hk[i + 1].u - hk[i].u < 1.0) continue;  // touching a local minimum vertex
            ends.push_back(make_end(k, hk[i]));
            ends.push_back(make_end(k, hk[i + 1]));
        }
    }
    return ends;
}

// Connectors join consecutive ends along a contour that lie on adjacent lines. Nothing crosses
// the contour between them, so that arc stays inside the strip between the two lines; it may be
// long where the boundary runs almost along the lines, and then it deposits exactly the part of
// the strip that neither line reaches (thin bands would be lost otherwise).
class FillChains {
  public:
    FillChains(const Paths& comp, const std::vector<End>& ends,
               const std::vector<std::vector<double>>& cum)
        : comp_(comp),
          ends_(ends),
          cum_(cum),
          per_contour_(comp.size()),
          slot_(ends.size(), 0),
          used_(ends.size() / 2, 0) {
        for (int i = 0; i < int(ends.size()); ++i) per_contour_[ends[i].contour].push_back(i);
        for (size_t ci = 0; ci < comp.size(); ++ci) {
            auto& list = per_contour_[ci];
            std::sort(list.begin(), list.end(),
                      [&](int a, int b) { return ends[a].param < ends[b].param; });
            for (size_t i = 0; i < list.size(); ++i) slot_[list[i]] = static_cast<int>(i);
        }
    }

    // Segments in line order (they were made line by line); a chain starts preferably at an
    // end with nowhere to go, and grows from both ends. Chains shorter than `width` are left
    // out.
    void chain(double width, Feature feature, double flow, std::vector<Extrusion>& out) {
        const int segs = static_cast<int>(ends_.size() / 2);
        for (int sgm = 0; sgm < segs; ++sgm) {
            if (used_[sgm]) continue;
            used_[sgm] = 1;
            const int entry = has_next(2 * sgm) && !has_next(2 * sgm + 1) ? 2 * sgm + 1 : 2 * sgm;
            Path forward_part{ends_[entry].xy};
            push_unique(forward_part, ends_[entry ^ 1].xy);
            walk(entry ^ 1, forward_part);
            Path backward_part;
            walk(entry, backward_part);
            Path path;
            for (auto it = backward_part.rbegin(); it != backward_part.rend(); ++it)
                push_unique(path, *it);
            for (const Point& p : forward_part) push_unique(path, p);
            if (path.size() >= 2 && length(Paths{path}, false) >= width) {
                Extrusion ex;
                ex.feature = feature;
                ex.points = std::move(path);
                ex.flow = flow;
                out.push_back(std::move(ex));
            }
        }
    }

  private:
    // Forward arc length along the contour from end p to end q.
    double arc_length(int p, int q) const {
        double arc = ends_[q].param - ends_[p].param;
        if (arc <= 0) arc += cum_[ends_[p].contour].back();
        return arc;
    }
    // Contour vertices strictly between ends p and q, walking forward from p to q.
    void arc_points(int p, int q, Path& into) const {
        const End& a = ends_[p];
        const End& b = ends_[q];
        const Path& c = comp_[a.contour];
        const int m = static_cast<int>(c.size());
        int count = ((b.edge - a.edge) % m + m) % m;
        if (count == 0 && b.param <= a.param) count = m;
        for (int i = 1; i <= count; ++i) push_unique(into, c[(a.edge + i) % m]);
    }
    // The nearest unused end reachable from end x by a connector, or -1.
    int next_end(int x, bool& forward) const {
        const auto& list = per_contour_[ends_[x].contour];
        const int n = static_cast<int>(list.size());
        int best = -1;
        double best_arc = 0;
        if (n < 2) return best;
        for (int dir : {1, -1}) {
            const int y = list[((slot_[x] + dir) % n + n) % n];
            if (used_[y / 2] || std::abs(ends_[y].line - ends_[x].line) != 1) continue;
            const double arc = dir > 0 ? arc_length(x, y) : arc_length(y, x);
            if (best < 0 || arc < best_arc) best = y, best_arc = arc, forward = dir > 0;
        }
        return best;
    }
    // Leaves through end x: connector, next line across, and so on. Because every line is left
    // by its other end, the chain zig-zags.
    void walk(int x, Path& path) {
        bool forward = true;
        for (int y = next_end(x, forward); y >= 0; y = next_end(x, forward)) {
            if (forward) {
                arc_points(x, y, path);
            } else {
                Path back;
                arc_points(y, x, back);
                for (auto it = back.rbegin(); it != back.rend(); ++it) push_unique(path, *it);
            }
            used_[y / 2] = 1;
            push_unique(path, ends_[y].xy);
            push_unique(path, ends_[y ^ 1].xy);
            x = y ^ 1;
        }
    }
    bool has_next(int x) const {
        bool forward = true;
        return next_end(x, forward) >= 0;
    }

    const Paths& comp_;
    const std::vector<End>& ends_;
    const std::vector<std::vector<double>>& cum_;
    std::vector<std::vector<int>> per_contour_;
    std::vector<int> slot_;  // position of each end in its contour's list
    std::vector<char> used_;
};

void fill_component(const Paths& comp, double angle, Coord w, Feature feature,
                    std::vector<Extrusion>& out) {
    const std::optional<ScanFrame> frame = scan_frame(comp, angle, w);
    if (!frame) return;
    ScanHits scan = scan_hits(comp, *frame);
    const std::vector<End> ends = segment_ends(comp, scan);
    if (ends.size() / 2 == 0) return;
    FillChains(comp, ends, scan.cum).chain(double(w), feature, frame->flow, out);
}

}  // namespace

std::vector<Extrusion> fill_solid(const Paths& region, double angle_deg, Coord spacing,
                                  Feature feature) {
    std::vector<Extrusion> out;
    if (region.empty() || spacing <= 0) return out;
    const double angle = angle_deg * std::numbers::pi / 180.0;
    for (const Paths& comp : components(region)) fill_component(comp, angle, spacing, feature, out);
    return out;
}

std::vector<Extrusion> fill_thin(const Paths& region, Coord line_width, Coord overlap,
                                 Coord min_width, Feature feature) {
    std::vector<Extrusion> out;
    if (region.empty() || line_width <= 0) return out;
    const double w = double(line_width);
    // A strip's branches shorter than a line width are corners of its outline, not strips.
    SkeletonOptions options;
    options.prune_threshold = line_width;
    options.max_arc_error = 20;  // um: the contours' vertices cost, not a bead's width
    const double step = w;       // the width is sampled at least every line width along the axis
    const double tolerance = 0.1 * w;
    auto line = [&](Path points, double mean_width) {
        Extrusion e;
        e.feature = feature;
        e.points = std::move(points);
        e.flow = std::min(kMaxThinFlow, (mean_width + double(overlap)) / w);
        out.push_back(std::move(e));
    };
    // Half-widths beyond 1.5 w are not thin strips; the flow is capped there.
    const EdgeDistance distance(region, static_cast<Coord>(1.5 * w));
    // Each end goes on while the strip is at least min_width wide ahead, in steps of a quarter
    // of that: a step that crossed the strip's edge would end nearer to it than half min_width,
    // so every point stays inside.
    auto wide = [&](const Point&, const Point& q) { return 2 * distance(q) >= double(min_width); };
    auto width = [&](const Point& q) { return 2 * distance(q); };
    for (const Path& axis : medial_axis(region, options))
        for (Bead& b : axis_beads(extended_axis(axis, wide, 0.25 * double(min_width), w), width,
                                  step, tolerance, double(min_width)))
            line(std::move(b.points), b.width);
    std::vector<BBox2> drawn;
    for (const Extrusion& e : out) drawn.push_back(bounds(e.points));
    for (const Paths& comp : components(region)) {
        const BBox2 box = bounds(comp);
        if (std::any_of(drawn.begin(), drawn.end(),
                        [&](const BBox2& d) { return carve::overlap(d, box); }))
            continue;
        // A piece whose axis was all pruned (its ends were nearer than the pruning reaches):
        // one line across its longest extent, if that is a line width at least.
        const double a = area(comp);
        if (a < double(min_width) * double(min_width)) continue;
        Point p = comp.front().front(), q = p;
        double best = -1;
        for (const Path& c : comp)
            for (const Point& u : c)
                for (const Point& v : c) {
                    const double d = std::hypot(double(u.X - v.X), double(u.Y - v.Y));
                    if (d > best) best = d, p = u, q = v;
                }
        if (best < w) continue;  // a corner's speck: no line to draw in it
        const double width = a / best;
        const double cut = std::min(0.5 * width, 0.5 * best - 1) / best;
        if (cut < 0) continue;
        const Point from(p.X + static_cast<Coord>(std::llround(cut * double(q.X - p.X))),
                         p.Y + static_cast<Coord>(std::llround(cut * double(q.Y - p.Y))));
        const Point to(q.X - static_cast<Coord>(std::llround(cut * double(q.X - p.X))),
                       q.Y - static_cast<Coord>(std::llround(cut * double(q.Y - p.Y))));
        if (from != to) line(Path{from, to}, width);
    }
    return out;
}

}  // namespace carve

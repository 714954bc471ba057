// The side view of the tallest internal support (see html_side.hpp).
#include "report/html_side.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "report/palette.hpp"

namespace carve::html {

namespace {

struct Box {
    Coord x0, y0, x1, y1;
};

Box box_of(const Path& p, Coord grow) {
    Box b{p.front().X, p.front().Y, p.front().X, p.front().Y};
    for (const Point& q : p) {
        b.x0 = std::min(b.x0, q.X), b.y0 = std::min(b.y0, q.Y);
        b.x1 = std::max(b.x1, q.X), b.y1 = std::max(b.y1, q.Y);
    }
    b.x0 -= grow, b.y0 -= grow, b.x1 += grow, b.y1 += grow;
    return b;
}

// Each piece stands on the piece of the layer below whose box meets its own and that stands
// highest already (the nearest of those): one column per top piece, one piece a layer, as a rib
// is printed. `order`: the pieces by layer.
struct PieceStacks {
    std::vector<int> depth;    // pieces in the column down from each, itself included
    std::vector<size_t> prev;  // the piece each stands on, or ribs.size()
};

PieceStacks stack_pieces(const std::vector<RibPiece>& ribs, const std::vector<size_t>& order,
                         const std::vector<Box>& boxes) {
    auto centre_units = [&](size_t i) {
        return std::pair{(boxes[i].x0 + boxes[i].x1) / 2, (boxes[i].y0 + boxes[i].y1) / 2};
    };
    PieceStacks out;
    std::vector<int>& depth = out.depth;
    std::vector<size_t>& prev = out.prev;
    depth.assign(ribs.size(), 0);
    prev.assign(ribs.size(), ribs.size());
    size_t below_begin = 0, below_end = 0;  // the previous layer's run of `order`
    for (size_t k = 0; k < order.size();) {
        size_t end = k;
        while (end < order.size() && ribs[order[end]].layer == ribs[order[k]].layer) ++end;
        const bool consecutive =
            below_end > below_begin && ribs[order[below_begin]].layer + 1 == ribs[order[k]].layer;
        for (size_t a = k; a < end; ++a) {
            const size_t i = order[a];
            depth[i] = 1;
            double nearest = 1e300;
            for (size_t c = below_begin; consecutive && c < below_end; ++c) {
                const size_t j = order[c];
                const Box &p = boxes[i], &q = boxes[j];
                if (!(p.x0 <= q.x1 && q.x0 <= p.x1 && p.y0 <= q.y1 && q.y0 <= p.y1)) continue;
                const auto [ix, iy] = centre_units(i);
                const auto [jx, jy] = centre_units(j);
                const double d = std::hypot(double(ix - jx), double(iy - jy));
                if (depth[j] + 1 > depth[i] || (depth[j] + 1 == depth[i] && d < nearest)) {
                    depth[i] = depth[j] + 1;
                    prev[i] = j;
                    nearest = d;
                }
            }
        }
        below_begin = k, below_end = end;
        k = end;
    }
    return out;
}

}  // namespace

std::string tallest_support_svg(const std::vector<RibPiece>& ribs,
                                const std::vector<SideLayer>& layers, double layer_height,
                                double line_width, TallestSupport& found) {
    found = {};
    std::vector<size_t> order;
    for (size_t i = 0; i < ribs.size(); ++i)
        if (!ribs[i].points.empty()) order.push_back(i);
    if (order.empty()) return {};
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return ribs[a].layer < ribs[b].layer; });
    const Coord grow = to_units(line_width / 2);
    std::vector<Box> boxes(ribs.size());
    for (size_t i : order) boxes[i] = box_of(ribs[i].points, grow);
    const PieceStacks stacks = stack_pieces(ribs, order, boxes);
    const std::vector<int>& depth = stacks.depth;
    const std::vector<size_t>& prev = stacks.prev;
    size_t best = order.front();
    for (size_t i : order)
        if (depth[i] > depth[best]) best = i;
    std::vector<bool> mine(ribs.size(), false);
    size_t first = best;
    for (size_t i = best; i < ribs.size(); i = prev[i]) mine[i] = true, first = i;
    const RibPiece &bottom = ribs[first], &top = ribs[best];
    auto centre = [&](const RibPiece& p) {
        const Box& b = boxes[&p - ribs.data()];
        return std::pair{to_mm((b.x0 + b.x1) / 2), to_mm((b.y0 + b.y1) / 2)};
    };
    // Plain doubles, not a structured binding: clang 14 cannot capture those in the lambdas
    // below (the sanitizer tree is clang's).
    const double bx = centre(bottom).first, by = centre(bottom).second;
    const double tx = centre(top).first, ty = centre(top).second;
    found.layers = depth[best];
    found.z_from = bottom.z - layer_height;
    found.z_to = top.z;
    found.height_mm = found.layers * layer_height;
    found.x0 = bx, found.y0 = by, found.x1 = tx, found.y1 = ty;

    // The plane: through the lowest piece's centre, towards the highest's (along x when the
    // support stands straight up). s: mm along it.
    double ux = tx - bx, uy = ty - by;
    const double run = std::hypot(ux, uy);
    if (run < 1.0)
        ux = 1, uy = 0;
    else
        ux /= run, uy /= run;
    auto s_of = [&](const Point& p) { return (to_mm(p.X) - bx) * ux + (to_mm(p.Y) - by) * uy; };
    auto d_of = [&](const Point& p) { return -(to_mm(p.X) - bx) * uy + (to_mm(p.Y) - by) * ux; };

    const double margin = std::max(3.0, 0.15 * found.height_mm);
    const double z_lo = std::max(0.0, found.z_from - margin), z_hi = found.z_to + margin;
    // The support spans s from 0 to `run`; the section is shown so far to either side.
    const double s_reach = std::max(10.0, 0.6 * found.height_mm);
    const double s_lo = -s_reach, s_hi = run + s_reach;
    struct Bar {
        double s0, s1, z;
        int kind;  // 0 section, 1 other rib, 2 the support
    };
    std::vector<Bar> bars;
    for (const SideLayer& l : layers) {
        if (l.z < z_lo || l.z > z_hi + layer_height) continue;
        std::vector<double> cuts;
        for (const Path& p : l.outline)
            for (size_t i = 0; i < p.size(); ++i) {
                const Point &a = p[i], &b = p[(i + 1) % p.size()];
                const double da = d_of(a), db = d_of(b);
                if ((da < 0) == (db < 0)) continue;
                const double t = da / (da - db);
                cuts.push_back(s_of(a) + t * (s_of(b) - s_of(a)));
            }
        std::sort(cuts.begin(), cuts.end());
        for (size_t i = 0; i + 1 < cuts.size(); i += 2)
            bars.push_back({std::max(cuts[i], s_lo), std::min(cuts[i + 1], s_hi), l.z, 0});
    }
    for (size_t i : order) {
        const RibPiece& p = ribs[i];
        if (p.z < z_lo || p.z > z_hi + layer_height) continue;
        double s0 = 1e300, s1 = -1e300, near = 1e300;
        for (const Point& q : p.points) {
            s0 = std::min(s0, s_of(q)), s1 = std::max(s1, s_of(q));
            near = std::min(near, std::fabs(d_of(q)));
        }
        if (!mine[i] && near > 1.0) continue;  // other ribs only where they cross the plane
        s0 -= line_width / 2, s1 += line_width / 2;
        if (s1 < s_lo || s0 > s_hi) continue;
        bars.push_back({std::max(s0, s_lo), std::min(s1, s_hi), p.z, mine[i] ? 2 : 1});
    }
    // Equal scales: a slender support looks as slender as it is.
    double used_lo = 0, used_hi = 0;
    for (const Bar& b : bars) used_lo = std::min(used_lo, b.s0), used_hi = std::max(used_hi, b.s1);
    const double width_mm = std::max(used_hi - used_lo, 1.0), height_mm = z_hi - z_lo;
    const double scale = std::min(640.0 / width_mm, 420.0 / height_mm);
    const double W = width_mm * scale, H = height_mm * scale, pad = 36;
    std::string svg = fmt::format(
        "<svg class=\"side\" viewBox=\"0 0 {:.0f} {:.0f}\" width=\"{:.0f}\" height=\"{:.0f}\" "
        "role=\"img\" aria-label=\"side view of the tallest internal support\">",
        W + 2 * pad, H + 2 * pad, W + 2 * pad, H + 2 * pad);
    const char* fills[] = {"#dfe3e8", kRibColour, kRibColour};
    const char* opacity[] = {"1", "0.2", "1"};
    for (int kind = 0; kind < 3; ++kind) {
        std::string d;
        for (const Bar& b : bars) {
            if (b.kind != kind || b.s1 <= b.s0) continue;
            const double x = pad + (b.s0 - used_lo) * scale, y = pad + (z_hi - b.z) * scale;
            d += fmt::format("M{:.1f} {:.1f}h{:.2f}v{:.2f}h{:.2f}z", x, y, (b.s1 - b.s0) * scale,
                             layer_height * scale, -(b.s1 - b.s0) * scale);
        }
        if (!d.empty())
            svg += fmt::format("<path d=\"{}\" fill=\"{}\" fill-opacity=\"{}\"/>", d, fills[kind],
                               opacity[kind]);
    }
    // z at the support's ends.
    for (double z : {found.z_from, found.z_to})
        svg += fmt::format(
            "<line x1=\"{0:.1f}\" x2=\"{1:.1f}\" y1=\"{2:.1f}\" y2=\"{2:.1f}\" stroke=\"#868e96\" "
            "stroke-dasharray=\"3 3\"/><text x=\"2\" y=\"{3:.1f}\" font-size=\"11\">z "
            "{4:.1f}</text>",
            pad - 4, W + pad, pad + (z_hi - z) * scale, pad + (z_hi - z) * scale + 4, z);
    svg += fmt::format(
        "<line x1=\"{0:.1f}\" x2=\"{1:.1f}\" y1=\"{2:.1f}\" y2=\"{2:.1f}\" stroke=\"#495057\"/>"
        "<text x=\"{0:.1f}\" y=\"{3:.1f}\" font-size=\"11\">10 mm</text>",
        pad, pad + 10 * scale, H + pad + 14, H + pad + 28);
    svg += "</svg>";
    return svg;
}

}  // namespace carve::html

// Free-standing thin columns, skins left open and the longest bridge (see printability.hpp).
#include "check/printability.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "check/footprint.hpp"

namespace carve::check {

using ClipperLib::Clipper;
using ClipperLib::ClipperOffset;

namespace {

constexpr double kThinAreaMm2 = 3.0;    // a piece under this area is thin
constexpr double kThinSideMm = 2.0;     // or one whose rectangle's narrow side is under this
constexpr double kInteriorMm = 0.3;     // interior: farther than this from the slice boundary
constexpr double kOpeningMm = 0.1;      // open skin narrower than twice this does not count
constexpr double kHoleMm2 = 1.0;        // open pieces counted as holes
constexpr double kOverlapUnits2 = 100;  // 0.0001 mm2: less is Clipper's rounding, not overlap

double signed_area_units(const Paths& piece) {
    double a = 0;
    for (const Path& p : piece) a += ClipperLib::Area(p);
    return a;
}

struct Box {
    Coord min_x = std::numeric_limits<Coord>::max(), min_y = std::numeric_limits<Coord>::max();
    Coord max_x = std::numeric_limits<Coord>::min(), max_y = std::numeric_limits<Coord>::min();
    void add(const Path& p) {
        for (const Point& q : p) {
            min_x = std::min(min_x, q.X), max_x = std::max(max_x, q.X);
            min_y = std::min(min_y, q.Y), max_y = std::max(max_y, q.Y);
        }
    }
    bool meets(const Box& o) const {
        return min_x <= o.max_x && o.min_x <= max_x && min_y <= o.max_y && o.min_y <= max_y;
    }
};

// The contours of `region` whose boxes meet `box`: the region is unchanged inside `box` (a
// contour left out lies wholly outside it, and so do the holes inside it), and a boolean
// operation with something inside `box` need not read a whole layer.
Paths near(const Paths& region, const Box& box) {
    Paths out;
    for (const Path& p : region) {
        Box b;
        b.add(p);
        if (b.meets(box)) out.push_back(p);
    }
    return out;
}

Box box_of(const Paths& region, Coord grow = 0) {
    Box b;
    for (const Path& p : region) b.add(p);
    b.min_x -= grow, b.min_y -= grow, b.max_x += grow, b.max_y += grow;
    return b;
}

double cross(const Point& o, const Point& a, const Point& b) {
    return double(a.X - o.X) * double(b.Y - o.Y) - double(a.Y - o.Y) * double(b.X - o.X);
}

}  // namespace

double narrow_side(const Path& points) {
    // Convex hull (monotone chain), counter-clockwise.
    Path p = points;
    std::sort(p.begin(), p.end(),
              [](const Point& a, const Point& b) { return a.X != b.X ? a.X < b.X : a.Y < b.Y; });
    p.erase(std::unique(p.begin(), p.end()), p.end());
    if (p.size() < 3) return 0;
    Path hull(2 * p.size());
    size_t k = 0;
    for (size_t i = 0; i < p.size(); ++i) {
        while (k >= 2 && cross(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
        hull[k++] = p[i];
    }
    for (size_t i = p.size() - 1, t = k + 1; i-- > 0;) {
        while (k >= t && cross(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
        hull[k++] = p[i];
    }
    hull.resize(k - 1);
    const size_t h = hull.size();
    if (h < 3) return 0;
    // Rotating calipers: the minimum-area rectangle has a side on a hull edge. For each edge,
    // the extreme points along it (right, left) and away from it (far) only move forward.
    auto at = [&](size_t i) { return hull[i % h]; };
    double best_area = std::numeric_limits<double>::infinity(), best_side = 0;
    size_t right = 0, far = 0, left = 0;
    for (size_t i = 0; i < h; ++i) {
        const Point a = at(i), b = at(i + 1);
        double ex = double(b.X - a.X), ey = double(b.Y - a.Y);
        const double len = std::hypot(ex, ey);
        if (len == 0) continue;
        ex /= len, ey /= len;
        const double nx = -ey, ny = ex;  // inward for a counter-clockwise hull
        auto dot = [](double x, double y, const Point& p, const Point& q) {
            return x * double(q.X - p.X) + y * double(q.Y - p.Y);
        };
        if (right < i) right = i;
        for (size_t s = 0; s < h && dot(ex, ey, at(right), at(right + 1)) > 0; ++s) ++right;
        if (i == 0) far = right;
        if (far < right) far = right;
        for (size_t s = 0; s < h && dot(nx, ny, at(far), at(far + 1)) > 0; ++s) ++far;
        if (i == 0) left = far;
        if (left < far) left = far;
        for (size_t s = 0; s < h && dot(ex, ey, at(left), at(left + 1)) < 0; ++s) ++left;
        const double width = dot(nx, ny, a, at(far));
        const double length = dot(ex, ey, at(left), at(right));
        if (width * length < best_area) {
            best_area = width * length;
            best_side = std::min(width, length);
        }
    }
    return best_side;
}

std::vector<Paths> connected_pieces(const Paths& region) {
    std::vector<Paths> pieces;
    if (region.empty()) return pieces;
    Clipper c;
    c.AddPaths(region, ClipperLib::ptSubject, true);
    ClipperLib::PolyTree tree;
    c.Execute(ClipperLib::ctUnion, tree, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
    // Outer contours are at even depths; islands in holes are pieces of their own.
    std::vector<const ClipperLib::PolyNode*> todo(tree.Childs.begin(), tree.Childs.end());
    while (!todo.empty()) {
        const ClipperLib::PolyNode* outer = todo.back();
        todo.pop_back();
        Paths piece{outer->Contour};
        for (const ClipperLib::PolyNode* hole : outer->Childs) {
            piece.push_back(hole->Contour);
            todo.insert(todo.end(), hole->Childs.begin(), hole->Childs.end());
        }
        pieces.push_back(std::move(piece));
    }
    return pieces;
}

Paths offset_round(const Paths& region, Coord delta) {
    if (region.empty() || delta == 0) return region;
    ClipperOffset off(2.0, kArcToleranceUnits);
    off.AddPaths(region, ClipperLib::jtRound, ClipperLib::etClosedPolygon);
    Paths out;
    off.Execute(out, static_cast<double>(delta));
    return out;
}

Paths opening(const Paths& region, Coord r) {
    return offset_round(offset_round(region, -r), r);
}

size_t PrintabilityMeter::root(size_t n) {
    while (nodes_[n].parent != n) {
        nodes_[n].parent = nodes_[nodes_[n].parent].parent;
        n = nodes_[n].parent;
    }
    return n;
}

void PrintabilityMeter::layer(double z, double height, const Paths& footprint, const Paths& model) {
    window_.push_back({z, height, footprint, model});
    const size_t n = window_.size();
    // Bottom region: over what is not inside both slices below (the first 2 layers: all).
    // Those two slices were the two above the layer under them: their common part is known
    // from the step before, but on the third layer.
    if (index_ < 2 || n < 3) {
        skin(model, footprint, z, figures_.bottom);
    } else {
        if (index_ == 2) both_above_ = intersection(window_[0].model, window_[1].model);
        skin(difference(model, both_above_), footprint, z, figures_.bottom);
    }
    // Top region of the layer two below, now that both slices above it are known.
    if (n == 3) {
        const Layer& l = window_.front();
        both_above_ = intersection(window_[1].model, window_[2].model);
        skin(difference(l.model, both_above_), l.footprint, l.z, figures_.top);
        window_.pop_front();
    }
    columns(window_.back());
    ++index_;
}

void PrintabilityMeter::finish() {
    // The last two layers have nothing above on both: their whole slice is top.
    for (const Layer& l : window_) skin(l.model, l.footprint, l.z, figures_.top);
    window_.clear();
    below_.clear();

    struct Column {
        int lo = std::numeric_limits<int>::max(), hi = -1;
        double height = 0;
        std::vector<double> widths;
        size_t bottom = 0, top = 0;
    };
    std::vector<Column> columns(nodes_.size());
    for (size_t i = 0; i < nodes_.size(); ++i) {
        Column& c = columns[root(i)];
        const Node& n = nodes_[i];
        c.widths.push_back(n.width);
        if (n.layer < c.lo) c.lo = n.layer, c.bottom = i;
        if (n.layer > c.hi) c.hi = n.layer, c.top = i;
    }
    // Height: the layers from its lowest to its highest, each counted once (a column may be
    // two pieces in a layer where it forks).
    std::vector<double> layer_height(static_cast<size_t>(index_), 0.0);
    for (const Node& n : nodes_) layer_height[static_cast<size_t>(n.layer)] = n.height;
    ColumnFigures& f = figures_.columns;
    for (size_t i = 0; i < nodes_.size(); ++i) {
        if (root(i) != i) continue;
        Column& c = columns[i];
        for (int k = c.lo; k <= c.hi; ++k) c.height += layer_height[static_cast<size_t>(k)];
        ++f.thin_interior;
        if (c.height > 5 + 1e-6) ++f.over_5mm;
        if (c.height > 10 + 1e-6) ++f.over_10mm;
        if (c.height > f.tallest_mm) {
            const Node& b = nodes_[c.bottom];
            const Node& t = nodes_[c.top];
            f.tallest_mm = c.height;
            f.tallest_layers = c.hi - c.lo + 1;
            // Its typical width: the median of its pieces' narrow sides (a fork or a joint
            // makes a few pieces wider than the column).
            std::nth_element(c.widths.begin(), c.widths.begin() + c.widths.size() / 2,
                             c.widths.end());
            f.tallest_width_mm = c.widths[c.widths.size() / 2];
            f.tallest_z_from_mm = b.z - b.height;
            f.tallest_z_to_mm = t.z;
            f.tallest_x_mm = b.x, f.tallest_y_mm = b.y;
            f.tallest_top_x_mm = t.x, f.tallest_top_y_mm = t.y;
        }
    }
}

void PrintabilityMeter::columns(const Layer& l) {
    // Thin pieces first (cheap), then which of them are interior, in one Clipper run: a thin
    // piece is interior when none of it lies outside the slice eroded by 0.3 mm.
    const std::vector<Paths> pieces = connected_pieces(l.footprint);
    std::vector<size_t> thin;
    for (size_t i = 0; i < pieces.size(); ++i) {
        const double area_mm2 = signed_area_units(pieces[i]) / (kUnitsPerMm * kUnitsPerMm);
        if (area_mm2 < kThinAreaMm2 || narrow_side(pieces[i].front()) < kThinSideMm * kUnitsPerMm)
            thin.push_back(i);
    }
    std::vector<Piece> now;
    if (!thin.empty() && !l.model.empty()) {
        Paths outers;
        for (size_t i : thin) outers.push_back(pieces[i].front());
        // The slice near the thin pieces only: cut by a box 1 mm wider than theirs, its
        // erosion is exact where they are.
        const Box around = box_of(outers, to_units(1.0));
        const Path cut{Point(around.min_x, around.min_y), Point(around.max_x, around.min_y),
                       Point(around.max_x, around.max_y), Point(around.min_x, around.max_y)};
        const Paths inner =
            offset_round(intersection(near(l.model, around), Paths{cut}), -to_units(kInteriorMm));
        Paths outside = difference(outers, inner);
        std::vector<bool> interior(thin.size(), true);
        std::vector<Box> boxes(thin.size());
        for (size_t t = 0; t < thin.size(); ++t) boxes[t].add(outers[t]);
        for (const Path& o : outside) {
            if (std::fabs(ClipperLib::Area(o)) < kOverlapUnits2 || o.empty()) continue;
            for (size_t t = 0; t < thin.size(); ++t) {
                const Point& q = o.front();
                if (!interior[t] || q.X < boxes[t].min_x || q.X > boxes[t].max_x ||
                    q.Y < boxes[t].min_y || q.Y > boxes[t].max_y)
                    continue;
                if (ClipperLib::PointInPolygon(q, outers[t]) != 0) {
                    interior[t] = false;
                    break;
                }
            }
        }
        for (size_t t = 0; t < thin.size(); ++t) {
            if (!interior[t]) continue;
            const Box& b = boxes[t];
            const size_t id = nodes_.size();
            nodes_.push_back({id, index_, l.z, l.height, narrow_side(outers[t]) / kUnitsPerMm,
                              to_mm((b.min_x + b.max_x) / 2), to_mm((b.min_y + b.max_y) / 2)});
            now.push_back({pieces[thin[t]], b.min_x, b.min_y, b.max_x, b.max_y, id});
        }
    }
    // Chain to the thin interior pieces of the layer below that this one's overlap.
    for (const Piece& p : now) {
        for (const Piece& q : below_) {
            if (p.min_x > q.max_x || q.min_x > p.max_x || p.min_y > q.max_y || q.min_y > p.max_y)
                continue;
            if (signed_area_units(intersection(p.shape, q.shape)) <= kOverlapUnits2) continue;
            const size_t a = root(p.node), b = root(q.node);
            if (a != b) nodes_[a].parent = b;
        }
    }
    below_ = std::move(now);
}

void PrintabilityMeter::skin(const Paths& region, const Paths& footprint, double z,
                             SkinFigures& out) {
    const double area = region_area_mm2(region);
    if (area <= 0) return;
    out.region_mm2 += area;
    const Paths open =
        opening(difference(region, near(footprint, box_of(region))), to_units(kOpeningMm));
    for (const Paths& piece : connected_pieces(open)) {
        const double a = signed_area_units(piece) / (kUnitsPerMm * kUnitsPerMm);
        out.open_mm2 += a;
        if (a >= kHoleMm2) ++out.holes_1mm2;
        if (a > out.largest_hole_mm2) {
            out.largest_hole_mm2 = a;
            out.largest_hole_z_mm = z;
        }
    }
}

Bridge longest_bridge(const std::vector<Path>& polylines, const Paths& unsupported) {
    Bridge best;
    if (unsupported.empty()) return best;
    Box box;
    for (const Path& p : unsupported) box.add(p);
    Paths segments;
    for (const Path& l : polylines) {
        for (size_t i = 1; i < l.size(); ++i) {
            Box s;
            s.add({l[i - 1], l[i]});
            if (s.meets(box)) segments.push_back({l[i - 1], l[i]});
        }
    }
    if (segments.empty()) return best;
    const Paths stretches = clip_open(segments, unsupported, true);
    // A stretch that reaches a move's end is not held there (the move ends over nothing).
    std::vector<Point> ends;
    for (const Path& s : segments) ends.push_back(s.front()), ends.push_back(s.back());
    auto less = [](const Point& a, const Point& b) { return a.X != b.X ? a.X < b.X : a.Y < b.Y; };
    std::sort(ends.begin(), ends.end(), less);
    auto is_end = [&](const Point& q) {
        auto it = std::lower_bound(ends.begin(), ends.end(), Point(q.X - 1, q.Y - 1), less);
        for (; it != ends.end() && it->X <= q.X + 1; ++it)
            if (std::llabs(it->Y - q.Y) <= 1) return true;
        return false;
    };
    for (const Path& s : stretches) {
        if (s.size() < 2 || is_end(s.front()) || is_end(s.back())) continue;
        const double length = distance(s.front(), s.back()) / kUnitsPerMm;
        if (length > best.length_mm) {
            best.length_mm = length;
            best.x_mm = to_mm((s.front().X + s.back().X) / 2);
            best.y_mm = to_mm((s.front().Y + s.back().Y) / 2);
        }
    }
    return best;
}

}  // namespace carve::check

namespace carve {

std::vector<std::string> failed_rules(const GcodeAnalysis& a) {
    std::vector<std::string> failed;
    if (!a.model_checked) return failed;
    const PrintabilityFigures& p = a.printability;
    if (p.columns.over_5mm > 0)
        failed.push_back(fmt::format(
            "free-standing thin columns: {} taller than {:g} mm (the tallest {:.1f} mm)",
            p.columns.over_5mm, kStrictColumnMm, p.columns.tallest_mm));
    if (p.top.open_percent() > kStrictSkinOpenPercent)
        failed.push_back(fmt::format("top skin left open: {:.2f} % of the region (limit {:g} %)",
                                     p.top.open_percent(), kStrictSkinOpenPercent));
    if (p.bottom.open_percent() > kStrictSkinOpenPercent)
        failed.push_back(fmt::format("bottom skin left open: {:.2f} % of the region (limit {:g} %)",
                                     p.bottom.open_percent(), kStrictSkinOpenPercent));
    if (a.hanging_inside_mm2 > kStrictHangingInsideMm2)
        failed.push_back(fmt::format("hanging inside: {:.1f} mm2 (limit {:g} mm2)",
                                     a.hanging_inside_mm2, kStrictHangingInsideMm2));
    const UncoveredFigures& u = p.uncovered;
    if (u.wide_pieces > 0)
        failed.push_back(fmt::format(
            "model left unprinted: {} piece{} wider than a line ({:.2f} mm) on {} layer{}, "
            "{:.1f} mm2; the largest {:.2f} mm2 at z {:.2f} (x {:.1f} y {:.1f})",
            u.wide_pieces, u.wide_pieces > 1 ? "s" : "", u.line_width_mm, u.wide_layers,
            u.wide_layers > 1 ? "s" : "", u.wide_mm2, u.largest_wide.area_mm2, u.largest_wide.z_mm,
            u.largest_wide.x_mm, u.largest_wide.y_mm));
    return failed;
}

std::string describe_printability(const GcodeAnalysis& a) {
    std::string out;
    if (a.model_checked) {
        const ColumnFigures& c = a.printability.columns;
        out += fmt::format("thin columns     {} free-standing over 5 mm, {} over 10 mm", c.over_5mm,
                           c.over_10mm);
        if (c.tallest_layers > 0)
            out += fmt::format(
                "; tallest {:.1f} mm ({} layers, {:.2f} mm wide), z {:.2f} .. {:.2f} at x {:.1f} "
                "y {:.1f} (top x {:.1f} y {:.1f})",
                c.tallest_mm, c.tallest_layers, c.tallest_width_mm, c.tallest_z_from_mm,
                c.tallest_z_to_mm, c.tallest_x_mm, c.tallest_y_mm, c.tallest_top_x_mm,
                c.tallest_top_y_mm);
        out += "\n";
        for (auto [name, s] : {std::pair{"top skin   ", &a.printability.top},
                               std::pair{"bottom skin", &a.printability.bottom}}) {
            out += fmt::format("{}      {:.2f} % of {:.0f} mm2 left open, {} holes >= 1 mm2", name,
                               s->open_percent(), s->region_mm2, s->holes_1mm2);
            if (s->largest_hole_mm2 > 0)
                out += fmt::format(" (largest {:.2f} mm2 at z {:.2f})", s->largest_hole_mm2,
                                   s->largest_hole_z_mm);
            out += "\n";
        }
        const UncoveredFigures& u = a.printability.uncovered;
        out += fmt::format(
            "uncovered        {:.2f} mm2, {:.3f} % of the slices (shrunk by 0.1 mm, {:.0f} mm2) "
            "open to the surface",
            u.uncovered_mm2, u.percent(), u.slice_mm2);
        if (u.largest.layer >= 0)
            out += fmt::format("; largest {:.2f} mm2 at layer {} z {:.2f} (x {:.1f} y {:.1f})",
                               u.largest.area_mm2, u.largest.layer, u.largest.z_mm, u.largest.x_mm,
                               u.largest.y_mm);
        if (u.layers_above_print > 0)
            out += fmt::format("; {} layers of the model above the print's last",
                               u.layers_above_print);
        out += fmt::format(
            "; {} piece{} wider than a line ({:.2f} mm, {}); {:.0f} mm2 enclosed by printed "
            "lines (the interior, not counted)",
            u.wide_pieces, u.wide_pieces == 1 ? "" : "s", u.line_width_mm,
            u.line_width_source == "nozzle" ? "1.125 x the nozzle" : "the lines' mean",
            u.enclosed_mm2);
        if (u.deep_mm2 > 0)
            out += fmt::format(", {:.0f} mm2 open but over 1 mm from the surface (not counted)",
                               u.deep_mm2);
        out += "\n";
    }
    out += fmt::format("longest bridge   {:.1f} mm", a.longest_bridge_mm);
    if (a.longest_bridge_mm > 0)
        out += fmt::format(" at z {:.2f} (x {:.1f} y {:.1f})", a.longest_bridge_z_mm,
                           a.longest_bridge_x_mm, a.longest_bridge_y_mm);
    out += "\n";
    if (a.model_checked) {
        const std::vector<std::string> failed = failed_rules(a);
        if (failed.empty()) {
            out +=
                "verdict          passes (thin columns <= 5 mm, skins open <= 0.25 %, "
                "hanging inside <= 1 mm2, nothing a line wide unprinted)\n";
        } else {
            out += fmt::format("verdict          fails {} rule{}\n", failed.size(),
                               failed.size() > 1 ? "s" : "");
            for (const std::string& f : failed) out += "  fails: " + f + "\n";
        }
    }
    return out;
}

}  // namespace carve

// The model's slice left out of a print (see uncovered.hpp).
#include "check/uncovered.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "check/footprint.hpp"
#include "check/printability.hpp"
#include "geometry/polygon.hpp"

namespace carve::check {

using ClipperLib::Clipper;

namespace {

constexpr double kShrinkMm = 0.1;  // the slice is measured this far inside the model's surface
// The band along the measured slice's boundary that an open piece reaches: 5 um, far below any
// line, far above Clipper's 1 um rounding.
constexpr Coord kBandUnits = 5;
constexpr double kLeftUnits2 = 100;
// How far from where it meets the surface an uncovered piece counts (see uncovered.hpp).
constexpr double kReachMm = 1.0;  // 0.0001 mm2: what an erosion leaves by rounding alone

Paths union_nonzero(const Paths& region) {
    Clipper c;
    c.AddPaths(region, ClipperLib::ptSubject, true);
    Paths out;
    c.Execute(ClipperLib::ctUnion, out, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
    return out;
}

bool holds(const BBox2& box, const Point& q) {
    return q.X >= box.min_x && q.X <= box.max_x && q.Y >= box.min_y && q.Y <= box.max_y;
}

// Whether q lies in the piece or on its boundary: inside its outer contour, not strictly inside
// one of its holes.
bool in_piece(const Point& q, const Paths& piece) {
    if (ClipperLib::PointInPolygon(q, piece.front()) == 0) return false;
    for (size_t h = 1; h < piece.size(); ++h)
        if (ClipperLib::PointInPolygon(q, piece[h]) == 1) return false;
    return true;
}

}  // namespace

std::vector<OpenPiece> open_pieces(const Paths& slice, const Paths& uncovered) {
    std::vector<Paths> pieces = connected_pieces(uncovered);
    std::vector<OpenPiece> out;
    if (pieces.empty()) return out;
    // Where the uncovered region meets the band inside the slice's boundary, it reaches the
    // boundary: each part of that meeting lies in one piece, found by a vertex of it (a vertex
    // may be rounded off a thin piece by a unit, so each is tried in turn).
    const Paths band = difference(slice, offset_round(slice, -kBandUnits));
    const Paths touching = intersection(uncovered, band);
    std::vector<BBox2> boxes;
    boxes.reserve(pieces.size());
    for (const Paths& p : pieces) boxes.push_back(bounds(p.front()));
    std::vector<int> at(pieces.size(), -1);  // the piece's index in out
    for (const Path& t : touching) {
        for (const Point& q : t) {
            size_t i = 0;
            while (i < pieces.size() && !(holds(boxes[i], q) && in_piece(q, pieces[i]))) ++i;
            if (i == pieces.size()) continue;
            if (at[i] < 0) at[i] = static_cast<int>(out.size()), out.push_back({{}, q, {}});
            out[at[i]].meets.push_back(t);
            break;
        }
    }
    for (size_t i = 0; i < pieces.size(); ++i)
        if (at[i] >= 0) out[at[i]].piece = std::move(pieces[i]);
    return out;
}

InteriorTest::InteriorTest(const Paths& footprint, const Paths& model, Coord width)
    : model_(model), width_(width) {
    for (const Paths& piece : connected_pieces(footprint)) {
        for (size_t h = 1; h < piece.size(); ++h) {
            const BBox2 b = bounds(piece[h]);
            holes_.push_back({piece[h], b.min_x, b.min_y, b.max_x, b.max_y,
                              std::fabs(ClipperLib::Area(piece[h]))});
        }
    }
}

bool InteriorTest::operator()(const Point& q) {
    // The innermost hole around q: the smallest that holds it.
    Hole* in = nullptr;
    for (Hole& h : holes_) {
        if (q.X < h.min_x || q.X > h.max_x || q.Y < h.min_y || q.Y > h.max_y) continue;
        if (in && h.area >= in->area) continue;
        if (ClipperLib::PointInPolygon(q, h.contour) != 0) in = &h;
    }
    if (!in) return false;  // outside the print
    if (in->interior < 0) {
        Path region = in->contour;
        std::reverse(region.begin(), region.end());  // a hole runs clockwise
        bool model_hole = false;
        for (const Paths& outside : connected_pieces(difference(Paths{region}, model_)))
            if ((model_hole = holds_disk(outside, 2 * width_))) break;
        in->interior = model_hole ? 0 : 1;
    }
    return in->interior == 1;
}

UncoveredPiece measure_piece(const Paths& piece) {
    // Signed sums over every contour: the holes (clockwise) take their share off.
    double a2 = 0, cx = 0, cy = 0;
    for (const Path& p : piece) {
        for (size_t i = 0, n = p.size(); i < n; ++i) {
            const double x0 = to_mm(p[i].X), y0 = to_mm(p[i].Y);
            const double x1 = to_mm(p[(i + 1) % n].X), y1 = to_mm(p[(i + 1) % n].Y);
            const double c = x0 * y1 - x1 * y0;
            a2 += c;
            cx += (x0 + x1) * c;
            cy += (y0 + y1) * c;
        }
    }
    UncoveredPiece out;
    out.area_mm2 = a2 / 2;
    if (a2 != 0) out.x_mm = cx / (3 * a2), out.y_mm = cy / (3 * a2);
    return out;
}

bool holds_disk(const Paths& piece, Coord width) {
    // A piece narrower than the disk in some direction cannot hold it: most pieces (specks at
    // corners, slivers along a faceted wall) are settled without an erosion.
    Path all;
    for (const Path& p : piece) all.insert(all.end(), p.begin(), p.end());
    if (all.empty() || narrow_side(all) < static_cast<double>(width)) return false;
    double left = 0;
    for (const Path& p : offset_round(piece, -width / 2)) left += ClipperLib::Area(p);
    return left >= kLeftUnits2;
}

double UncoveredMeter::layer(int index, double z, const Paths& model, const Paths& footprint,
                             double width_mm) {
    if (model.empty()) return 0;
    // The slicers' slices overlap where a mesh's shells do: shrink their union, not each shell.
    const Paths whole = union_nonzero(model);
    const Paths slice = offset_round(whole, -to_units(kShrinkMm));
    const double slice_mm2 = region_area_mm2(slice);
    if (slice_mm2 <= 0) return 0;
    UncoveredFigures& f = figures_;
    f.slice_mm2 += slice_mm2;
    f.line_width_mm = width_mm;
    const Paths uncovered = difference(slice, footprint);
    const double all_mm2 = region_area_mm2(uncovered);
    if (all_mm2 <= 0) return 0;
    double open_mm2 = 0, deep_mm2 = 0;
    bool wide_here = false;
    const Coord width = to_units(width_mm), reach = to_units(kReachMm);
    const std::vector<OpenPiece> open = open_pieces(slice, uncovered);
    std::optional<InteriorTest> interior;
    if (!open.empty() && !footprint.empty()) interior.emplace(footprint, whole, width);
    for (const OpenPiece& o : open) {
        if (interior && (*interior)(o.contact)) continue;  // enclosed after all
        // Within reach of where it meets the surface: a gap in a wall opens the interior behind
        // it, which is not the model left out (its area beyond is `deep`).
        const Paths piece =
            footprint.empty() ? o.piece : intersection(o.piece, dilate_round(o.meets, reach));
        UncoveredPiece p = measure_piece(piece);
        deep_mm2 += std::max(0.0, measure_piece(o.piece).area_mm2 - p.area_mm2);
        p.layer = index;
        p.z_mm = z;
        open_mm2 += p.area_mm2;
        if (p.area_mm2 > f.largest.area_mm2) f.largest = p;
        if (!holds_disk(piece, width)) continue;
        ++f.wide_pieces;
        f.wide_mm2 += p.area_mm2;
        wide_here = true;
        if (p.area_mm2 > f.largest_wide.area_mm2) f.largest_wide = p;
    }
    if (wide_here) ++f.wide_layers;
    f.uncovered_mm2 += open_mm2;
    f.deep_mm2 += deep_mm2;
    f.enclosed_mm2 += std::max(0.0, all_mm2 - open_mm2 - deep_mm2);
    return open_mm2;
}

}  // namespace carve::check

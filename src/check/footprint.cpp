// Footprints, far regions and travel figures of carve check (see footprint.hpp).
#include "check/footprint.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>

#include "check/grids.hpp"

namespace carve::check {

namespace {
constexpr double kMaxLineWidthMm = 10;
}  // namespace

using ClipperLib::Clipper;
using ClipperLib::ClipperOffset;

double region_area_mm2(const Paths& region) {
    double a = 0;
    for (const Path& p : region) a += ClipperLib::Area(p);
    return a / (kUnitsPerMm * kUnitsPerMm);
}

Paths dilate_round(const Paths& region, Coord delta) {
    if (region.empty() || delta <= 0) return region;
    ClipperOffset off(2.0, kArcToleranceUnits);
    off.AddPaths(region, ClipperLib::jtRound, ClipperLib::etClosedPolygon);
    Paths out;
    off.Execute(out, static_cast<double>(delta));
    return out;
}

Paths difference(const Paths& a, const Paths& b) {
    if (a.empty() || b.empty()) return a;
    Clipper c;
    c.AddPaths(a, ClipperLib::ptSubject, true);
    c.AddPaths(b, ClipperLib::ptClip, true);
    Paths out;
    c.Execute(ClipperLib::ctDifference, out, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
    return out;
}

Paths clip_open(const Paths& lines, const Paths& region, bool inside) {
    Clipper c;
    c.AddPaths(lines, ClipperLib::ptSubject, false);
    c.AddPaths(region, ClipperLib::ptClip, true);
    ClipperLib::PolyTree tree;
    c.Execute(inside ? ClipperLib::ctIntersection : ClipperLib::ctDifference, tree,
              ClipperLib::pftNonZero, ClipperLib::pftNonZero);
    Paths out;
    ClipperLib::OpenPathsFromPolyTree(tree, out);
    return out;
}

// Total length of open paths, mm.
double open_length_mm(const Paths& paths) {
    double l = 0;
    for (const Path& p : paths)
        for (size_t i = 1; i < p.size(); ++i)
            l += std::hypot(double(p[i].X - p[i - 1].X), double(p[i].Y - p[i - 1].Y));
    return l / kUnitsPerMm;
}

Paths intersection(const Paths& a, const Paths& b) {
    if (a.empty() || b.empty()) return {};
    Clipper c;
    c.AddPaths(a, ClipperLib::ptSubject, true);
    c.AddPaths(b, ClipperLib::ptClip, true);
    Paths out;
    c.Execute(ClipperLib::ctIntersection, out, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
    return out;
}

double line_width(double volume_per_mm, double height, BeadModel bead) {
    double w = volume_per_mm / height;
    return bead == BeadModel::kRounded ? w + height * (1 - std::numbers::pi / 4) : w;
}

Paths widen(const std::vector<Polyline>& lines, double height_mm, double filament_area,
            BeadModel bead) {
    // One offset per integer half-width (in um) keeps the count of Clipper runs small while the
    // width stays exact to the unit.
    std::map<Coord, Paths> by_half_width;
    for (const Polyline& l : lines) {
        if (l.length <= 0 || l.points.empty()) continue;
        double width =
            line_width(l.e * filament_area / l.length, l.height > 0 ? l.height : height_mm, bead);
        // A few millimetres at most on any printer; a hostile E over a tiny move would make
        // a line of any width, and the work on it grows with its area.
        width = std::min(width, kMaxLineWidthMm);
        Coord half = static_cast<Coord>(std::llround(width * kUnitsPerMm / 2));
        if (half < 1) continue;
        by_half_width[half].push_back(l.points);
    }
    Clipper all;
    for (auto& [half, paths] : by_half_width) {
        ClipperOffset off(2.0, kArcToleranceUnits);
        off.AddPaths(paths, ClipperLib::jtRound, ClipperLib::etOpenRound);
        Paths out;
        off.Execute(out, static_cast<double>(half));
        all.AddPaths(out, ClipperLib::ptSubject, true);
    }
    Paths footprint;
    all.Execute(ClipperLib::ctUnion, footprint, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
    return footprint;
}

// Unsupported extrusion farther than the far radius from the previous layer's footprint `below`.
// Offsetting a whole layer by 2 mm is the expensive part of the analysis, and most unsupported
// extrusion (slopes, skins over infill) lies well within 2 mm of the layer below, so that is first
// proven with samples: every point of U lies within m = s (1/sqrt2 + 1/2) of a sample (grid
// points inside U at spacing s, points every s along its edges), and distance is 1-Lipschitz,
// so a far point needs a sample farther than R - m. Only the tiles holding such samples go
// through the exact Clipper computation, on the previous footprint clipped near them.
Paths far_region(const Paths& unsupported, const Paths& below, Coord far_units) {
    constexpr double kSampleMm = 0.2, kCellMm = 0.25, kTileMm = 1.0;
    const double s = kSampleMm * kUnitsPerMm;
    const double margin = s * (std::numbers::sqrt2 / 2 + 0.5) + 2;
    const double threshold = static_cast<double>(far_units) - margin;
    if (threshold <= 0) return difference(unsupported, dilate_round(below, far_units));

    const NearMap near(below, kCellMm * kUnitsPerMm);
    const double tile = kTileMm * kUnitsPerMm;
    std::vector<std::pair<long, long>> tiles;
    auto test = [&](double x, double y) {
        if (near.within(x, y, threshold)) return;
        tiles.emplace_back(static_cast<long>(std::floor(x / tile)),
                           static_cast<long>(std::floor(y / tile)));
    };
    // Along the edges.
    std::vector<std::pair<long, double>> crossings;  // (grid row, x) where an edge crosses it
    for (const Path& p : unsupported) {
        for (size_t i = 0; i < p.size(); ++i) {
            const Point& a = p[i];
            const Point& b = p[(i + 1) % p.size()];
            double dx = double(b.X - a.X), dy = double(b.Y - a.Y);
            int n = std::max(1, static_cast<int>(std::ceil(std::hypot(dx, dy) / s)));
            for (int k = 0; k < n; ++k) test(a.X + dx * k / n, a.Y + dy * k / n);
            if (a.Y == b.Y) continue;
            // Rows y = j*s with min(a.Y, b.Y) <= y < max(a.Y, b.Y): even-odd crossings.
            double lo = std::min(a.Y, b.Y), hi = std::max(a.Y, b.Y);
            for (long j = static_cast<long>(std::ceil(lo / s)); j * s < hi; ++j) {
                double y = j * s;
                crossings.emplace_back(j, a.X + (y - a.Y) * dx / dy);
            }
        }
    }
    // Inside: grid points between pairs of crossings of each row (Clipper's output has no
    // overlapping contours, so even-odd parity is the region).
    std::sort(crossings.begin(), crossings.end());
    for (size_t i = 0; i + 1 < crossings.size(); i += 2) {
        if (crossings[i].first != crossings[i + 1].first) {
            --i;  // unpaired crossing (numerical): resynchronise on the next row
            continue;
        }
        double y = crossings[i].first * s;
        for (long k = static_cast<long>(std::ceil(crossings[i].second / s));
             k * s <= crossings[i + 1].second; ++k)
            test(k * s, y);
    }
    if (tiles.empty()) return {};

    std::sort(tiles.begin(), tiles.end());
    tiles.erase(std::unique(tiles.begin(), tiles.end()), tiles.end());
    // Runs of tiles along x become one rectangle each.
    auto rectangles = [&](double grow) {
        Paths rects;
        for (size_t i = 0; i < tiles.size();) {
            size_t j = i;
            while (j + 1 < tiles.size() && tiles[j + 1].first == tiles[i].first &&
                   tiles[j + 1].second == tiles[j].second + 1)
                ++j;
            // tiles are (tx, ty) sorted by tx then ty: runs go along y
            Coord x0 = static_cast<Coord>(tiles[i].first * tile - grow);
            Coord x1 = static_cast<Coord>((tiles[i].first + 1) * tile + grow);
            Coord y0 = static_cast<Coord>(tiles[i].second * tile - grow);
            Coord y1 = static_cast<Coord>((tiles[j].second + 1) * tile + grow);
            rects.push_back({Point(x0, y0), Point(x1, y0), Point(x1, y1), Point(x0, y1)});
            i = j + 1;
        }
        return rects;
    };
    Paths suspect = intersection(unsupported, rectangles(margin + 2));
    Paths local = intersection(below, rectangles(margin + far_units + 20));
    return difference(suspect, dilate_round(local, far_units));
}

// Travel against the model's slice grown by the outside tolerance (the outer wall's bead
// centres lie half a line width inside the slice, so travel along the wall stays in).
// A wall crossing is a piece of a travel path outside the grown slice that has the path
// inside at both of its ends: the nozzle leaves the object through its outer wall and comes
// back through it within one travel, e.g. across the mouth of a C, or from one island of a
// layer to another (the cat's legs): a strand can be dragged over the outside of the print
// either way. A path that starts outside (from a prime line, the home position) or ends
// outside (parking) is not a crossing.
TravelFigures measure_travel(const Paths& travel, const Paths& grown) {
    TravelFigures t;
    double total = 0;
    for (const Path& p : travel) total += open_length_mm(Paths{p});
    if (travel.empty()) return t;
    const Paths out = clip_open(travel, grown, false);
    t.outside_mm = open_length_mm(out);
    t.inside_mm = std::max(0.0, total - t.outside_mm);
    // Ends of the paths: a piece ending at one did not come back in (or never was in).
    std::vector<Point> ends;
    for (const Path& p : travel) {
        ends.push_back(p.front());
        ends.push_back(p.back());
    }
    std::sort(ends.begin(), ends.end(),
              [](const Point& a, const Point& b) { return a.X != b.X ? a.X < b.X : a.Y < b.Y; });
    auto is_end = [&](const Point& q) {
        auto it = std::lower_bound(
            ends.begin(), ends.end(), Point(q.X - 1, q.Y - 1),
            [](const Point& a, const Point& b) { return a.X != b.X ? a.X < b.X : a.Y < b.Y; });
        for (; it != ends.end() && it->X <= q.X + 1; ++it)
            if (std::llabs(it->Y - q.Y) <= 1) return true;
        return false;
    };
    for (const Path& piece : out) {
        if (piece.size() < 2 || open_length_mm(Paths{piece}) < 0.01) continue;
        if (!is_end(piece.front()) && !is_end(piece.back())) ++t.wall_crossings;
    }
    return t;
}

double max_distance_outside(const Paths& footprint, const Paths& model) {
    // The farthest point outside lies at a vertex of footprint minus model (up to the
    // polygonal approximation); its distance to the model's boundary is what is reported.
    // A layer with no slice of the model (a raft's, a skirt's under it, a support's under a
    // part that starts higher) has no distance to it: "inf mm" said nothing, and JSON cannot
    // hold it. Its area outside is counted all the same.
    if (model.empty()) return 0;
    const Paths outside = difference(footprint, model);
    if (outside.empty()) return 0;
    const EdgeGrid grid(model);
    double best = 0;
    for (const Path& p : outside)
        for (const Point& q : p) best = std::max(best, grid.distance(q));
    return std::isfinite(best) ? best / kUnitsPerMm : 0.0;
}

}  // namespace carve::check

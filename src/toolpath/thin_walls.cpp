// Thin walls: see thin_walls.hpp.
#include "toolpath/thin_walls.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"
#include "geometry/simplify.hpp"
#include "skeleton/skeleton.hpp"
#include "toolpath/beads.hpp"

namespace carve {

namespace {

// um: how far a bead's path may leave its axis when its samples are joined.
constexpr double kBeadTolerance = 5;

// um: four times how far the 24-gon disk's sides fall inside a circle of radius w (3.9 um), so
// that an opening's erosion and dilation, each short of the circle by that much, stay inside it.
constexpr Coord kClearance = 16;

double axis_length(const Paths& axis) {
    double total = 0;
    for (const Path& p : axis) total += length(Paths{p}, false);
    return total;
}

// The beads of one thin piece, along its medial axis. Widths are twice the distance to the
// slice's own outline (the piece's boundary where it meets the wide part is no edge of the
// model). Each open end goes on to where the outline ahead is nearer than 0.9 of the half
// width at the axis' end (a bead's end spreads about half its width beyond it), and no further
// than s beyond the piece: the end that meets the wide part then reaches the outer wall's
// centreline, so the bead joins the wall instead of stopping short of it.
void piece_beads(const Paths& piece, const EdgeDistance& to_outline, const Settings& settings,
                 const Paths& axis, std::vector<Extrusion>& out) {
    const double w = double(settings.line_width()), s = double(settings.nozzle_radius());
    const double min_feature = double(to_units(settings.min_feature_mm()));
    const double min_bead = double(to_units(settings.min_bead_mm()));
    const double widest = double(to_units(2 * settings.nozzle));
    const EdgeDistance to_piece(piece, static_cast<Coord>(s));
    auto keep = [&](const Point& end, const Point& q) {
        const double ahead = to_outline(q);
        if (2 * ahead < min_feature || ahead < 0.9 * to_outline(end)) return false;
        return to_piece(q) < s || point_in_region(q, piece);
    };
    auto width = [&](const Point& q) { return 2 * to_outline(q); };
    for (const Path& a : axis)
        for (Bead& b : axis_beads(extended_axis(a, keep, 0.25 * min_feature, w), width, w, 0.1 * w,
                                  min_feature)) {
            Extrusion e;
            e.feature = Feature::OuterWall;
            // The samples of a straight stretch are one move.
            e.points = douglas_peucker(b.points, false, kBeadTolerance);
            // Narrower than the narrowest bead: widened to it, not dropped.
            e.flow = std::clamp(b.width, min_bead, widest) / w;
            e.closed = e.points.size() > 2 && e.points.front() == e.points.back();
            if (e.closed) e.points.pop_back();
            out.push_back(std::move(e));
        }
}

}  // namespace

ThinWalls thin_walls(const Paths& outline, const Paths& wall_region, const Settings& settings) {
    ThinWalls out;
    out.wall_region = wall_region;
    if (outline.empty()) return out;
    const Coord s = settings.nozzle_radius(), w = settings.line_width();
    const Coord min_feature = std::max<Coord>(1, to_units(settings.min_feature_mm()));
    // Specks at the tips of corners are not parts of the model worth naming.
    const double speck = double(min_feature) * double(min_feature);
    auto tally = [&](const Paths& lost) {
        for (const Paths& piece : components(lost))
            if (const double a = area(piece); a >= speck)
                out.unprinted_mm2 += a / kUnitsPerMm / kUnitsPerMm;
    };
    if (!settings.thin_walls) {
        // The wall loop prints what lies within s of its centreline region; the rest is lost.
        tally(subtract_positive(outline, dilation(wall_region, s + kClearance)));
        return out;
    }
    // open(O, w): erode(O, w) is erode(wall_region, w - s), one erosion of the smaller region.
    // The opening's dilation is read once, unresolved: its union would cost a Clipper pass. It
    // reaches kClearance past w, so that along the wide parts its boundary runs clear of the
    // outline's instead of within the disk's rounding of it: the difference then has no slivers
    // there to open and sort (on the man the thin walls cost 29 % less with it).
    const Paths narrow =
        subtract_positive(outline, dilation(erode(wall_region, w - s), w + kClearance));
    if (narrow.empty()) return out;
    // What is narrower than the smallest feature goes: the rest holds a bead.
    const Paths printable = open(narrow, min_feature / 2);
    SkeletonOptions options;
    options.prune_threshold = w;  // shorter branches go to the corners of a piece
    options.max_arc_error = 20;   // um: the contours' vertices cost, not a bead's width
    std::optional<EdgeDistance> to_outline;
    Paths cut;
    for (const Paths& piece : components(printable)) {
        // A piece that holds no bead a line long is the tip of a corner: the wall has it.
        if (area(piece) < double(min_feature) * double(w)) continue;
        const Paths axis = medial_axis(piece, options);
        if (axis_length(axis) < double(w)) continue;
        // Half-widths beyond 1.5 w are no thin parts; the bead is capped there.
        if (!to_outline) to_outline.emplace(outline, static_cast<Coord>(1.5 * double(w)));
        const size_t before = out.beads.size();
        piece_beads(piece, *to_outline, settings, axis, out.beads);
        if (out.beads.size() > before) cut.insert(cut.end(), piece.begin(), piece.end());
    }
    // The dilations below are read unresolved, as the opening's: one Clipper pass each.
    if (!cut.empty()) out.wall_region = subtract_positive(wall_region, dilation(cut, s));
    Paths lines;
    for (const Extrusion& e : out.beads) {
        lines.push_back(e.points);
        if (e.closed) lines.back().push_back(e.points.front());
    }
    // Half the narrowest bead: the corridor stays on what the bead printed.
    if (!lines.empty()) out.corridors = dilate_lines(lines, to_units(settings.min_bead_mm()) / 2);
    // What the opening dropped bounds what is left unprinted: below one speck, no piece is one.
    if (area(narrow) - area(printable) >= speck)
        tally(subtract_positive(narrow, dilation(printable, min_feature / 2)));
    return out;
}

void UnprintedTally::add(int layer, double z, double unprinted_mm2) {
    if (unprinted_mm2 <= 0) return;
    if (layers_ == 0) first_ = layer, z_first_ = z;
    last_ = layer, z_last_ = z;
    ++layers_;
    area_mm2_ += unprinted_mm2;
}

std::string UnprintedTally::warning(const Settings& settings) const {
    // Less than a 0.1 mm square on a layer or two is rounding at a facet's edge.
    if (area_mm2_ < 0.05) return {};
    const int lo = std::min(first_, last_), hi = std::max(first_, last_);
    const double zlo = std::min(z_first_, z_last_), zhi = std::max(z_first_, z_last_);
    const bool thin = settings.thin_walls;
    return fmt::format(
        "{:.2f} mm2 of the model's slices is narrower than {:g} mm and is not printed, on {} "
        "layers between layer {} and {} (z {:.2f}-{:.2f} mm); {}",
        area_mm2_, thin ? settings.min_feature_mm() : settings.nozzle, layers_, lo + 1, hi + 1, zlo,
        zhi,
        thin ? "--min-feature-size sets the narrowest part printed"
             : "without --no-thin-walls it is printed as single lines");
}

}  // namespace carve

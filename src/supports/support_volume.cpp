// The support regions, layer by layer from the top, and the model's shadow for buildplate.
#include "supports/support_volume.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"
#include "skeleton/skeleton.hpp"

namespace carve {

SupportOptions support_options(const Settings& settings, double z0) {
    SupportOptions o;
    o.mode = settings.support;
    o.gap_layers = std::max(0, settings.support_gap_layers());
    o.xy_gap = to_units(settings.support_xy_gap);
    o.reach = settings.support_reach();
    o.lean = settings.dilation_per_layer();
    o.line_width = settings.line_width();
    // A trunk narrower than this sways as the nozzle passes; about 7 line widths at 0.4 mm.
    o.trunk = std::max(o.lean + 1, to_units(1.5 * settings.width_mm() / 0.4));
    o.interface_layers = std::max(0, settings.support_interface_layers);
    o.layer_height = settings.layer_height;
    o.first_layer = settings.model_layer_mm(0);  // the model's (a normal layer on a raft)
    o.z0 = z0;
    return o;
}

ModelShadow::ModelShadow(const std::vector<Vec3>& vertices,
                         const std::vector<std::array<uint32_t, 3>>& triangles, double cell_mm) {
    if (vertices.empty() || triangles.empty()) return;
    double x1 = vertices[0].x, y1 = vertices[0].y;
    x0_ = x1, y0_ = y1;
    for (const Vec3& v : vertices) {
        x0_ = std::min(x0_, v.x), y0_ = std::min(y0_, v.y);
        x1 = std::max(x1, v.x), y1 = std::max(y1, v.y);
    }
    cell_ = cell_mm;
    nx_ = static_cast<int>(std::ceil((x1 - x0_) / cell_)) + 1;
    ny_ = static_cast<int>(std::ceil((y1 - y0_) / cell_)) + 1;
    lowest_.assign(size_t(nx_) * size_t(ny_), std::numeric_limits<float>::infinity());
    auto lower = [&](int ix, int iy, double z) {
        if (ix < 0 || iy < 0 || ix >= nx_ || iy >= ny_) return;
        float& cell = lowest_[size_t(iy) * size_t(nx_) + size_t(ix)];
        cell = std::min(cell, static_cast<float>(z));
    };
    for (const auto& t : triangles) {
        const Vec3 &a = vertices[t[0]], &b = vertices[t[1]], &c = vertices[t[2]];
        // The vertices themselves: a triangle thinner than a cell may hold no cell centre.
        for (const Vec3* v : {&a, &b, &c})
            lower(static_cast<int>(std::floor((v->x - x0_) / cell_)),
                  static_cast<int>(std::floor((v->y - y0_) / cell_)), v->z);
        const double det = (b.y - c.y) * (a.x - c.x) + (c.x - b.x) * (a.y - c.y);
        if (std::abs(det) < 1e-12) continue;  // vertical: its lowest point is a vertex's cell
        const int ix0 = static_cast<int>(std::floor((std::min({a.x, b.x, c.x}) - x0_) / cell_));
        const int ix1 = static_cast<int>(std::floor((std::max({a.x, b.x, c.x}) - x0_) / cell_));
        const int iy0 = static_cast<int>(std::floor((std::min({a.y, b.y, c.y}) - y0_) / cell_));
        const int iy1 = static_cast<int>(std::floor((std::max({a.y, b.y, c.y}) - y0_) / cell_));
        for (int iy = iy0; iy <= iy1; ++iy)
            for (int ix = ix0; ix <= ix1; ++ix) {
                const double px = x0_ + (ix + 0.5) * cell_, py = y0_ + (iy + 0.5) * cell_;
                const double l1 = ((b.y - c.y) * (px - c.x) + (c.x - b.x) * (py - c.y)) / det;
                const double l2 = ((c.y - a.y) * (px - c.x) + (a.x - c.x) * (py - c.y)) / det;
                const double l3 = 1 - l1 - l2;
                if (l1 < 0 || l2 < 0 || l3 < 0) continue;
                lower(ix, iy, l1 * a.z + l2 * b.z + l3 * c.z);
            }
    }
}

Paths ModelShadow::below(double z_mm, Coord grow) const {
    // Runs of cells along each row, one rectangle each; a cell holding a lower point counts
    // whole, so the region errs on the side of the model.
    Paths cells;
    for (int iy = 0; iy < ny_; ++iy) {
        int ix = 0;
        while (ix < nx_) {
            if (!(lowest_[size_t(iy) * size_t(nx_) + size_t(ix)] < z_mm)) {
                ++ix;
                continue;
            }
            const int start = ix;
            while (ix < nx_ && lowest_[size_t(iy) * size_t(nx_) + size_t(ix)] < z_mm) ++ix;
            const Coord xa = to_units(x0_ + start * cell_), xb = to_units(x0_ + ix * cell_);
            const Coord ya = to_units(y0_ + iy * cell_), yb = to_units(y0_ + (iy + 1) * cell_);
            cells.push_back(Path{Point(xa, ya), Point(xb, ya), Point(xb, yb), Point(xa, yb)});
        }
    }
    if (cells.empty()) return {};
    Paths region = unite(cells);
    return grow > 0 ? dilate(region, grow) : region;
}

SupportPlanner::SupportPlanner(SupportOptions options, const ModelShadow* shadow)
    : options_(options), shadow_(shadow) {}

void SupportPlanner::add_outline(int index, const Paths& outline) {
    if (next_ < 0 && outlines_.empty()) next_ = index;
    outlines_.emplace_back(index, outline);
    lowest_ = index;
}

int SupportPlanner::ready(bool finished) const {
    if (next_ < 0 || outlines_.empty()) return -1;
    if (finished || lowest_ <= next_ - options_.gap_layers) return next_;
    return -1;
}

const Paths& SupportPlanner::outline(int index) const {
    for (const auto& [i, o] : outlines_)
        if (i == index) return o;
    return empty_;
}

namespace {

// How far a single line reaches out unheld beside the support below it without sagging: a line
// width and a half (the check calls 2 mm hanging).
constexpr Coord kHeld = 600;

// The region's bounding box grown by `margin`, as a rectangle: what of the model can matter.
Paths box_around(const Paths& region, Coord margin) {
    const BBox2 b = bounds(region);
    return {
        Path{Point(b.min_x - margin, b.min_y - margin), Point(b.max_x + margin, b.min_y - margin),
             Point(b.max_x + margin, b.max_y + margin), Point(b.min_x - margin, b.max_y + margin)}};
}

Paths without_specks(const Paths& region, double min_area) {
    Paths out;
    for (Paths& c : components(region))
        if (area(c) >= min_area) out.insert(out.end(), c.begin(), c.end());
    return out;
}

}  // namespace

// What of the layer g + 1 above has nothing under it within `reach`: the overhang whose support
// starts here, g empty layers below it. Slivers along a slope a little steeper than the support
// angle are left to the walls (opened away at a quarter width).
Paths SupportPlanner::fresh_overhang(int j) const {
    const SupportOptions& o = options_;
    const int g = o.gap_layers;
    const Coord w = o.line_width;
    const double min_area = 4.0 * double(w) * double(w);
    Paths fresh;
    const Paths& over = outline(j + g + 1);
    if (over.empty()) return fresh;
    const Paths& under = outline(j + g);
    fresh = under.empty() ? over : subtract(over, dilate(under, o.reach));
    if (!fresh.empty()) fresh = without_specks(open(fresh, w / 4), min_area);
    if (!fresh.empty() && o.mode == SupportMode::Buildplate && shadow_) {
        // Only where the model has nothing below this layer's middle: a column from here down
        // stays clear of it, since the support only narrows going down.
        // (As the slicer cuts it: (j + 0.5) h when the first layer is h.)
        const double z =
            o.z0 + (j == 0 ? o.first_layer / 2
                           : (o.first_layer - o.layer_height) + (j + 0.5) * o.layer_height);
        fresh = subtract(fresh, shadow_->below(z, o.xy_gap));
    }
    return fresh;
}

// Clear of the model by xy_gap beside it, and by g layers above and below: the support never
// touches the model, and where it meets the model's top (auto) it stops there. Returns where
// beside the model the support does not narrow.
Paths SupportPlanner::clear_of_model(int j, Paths& region, Paths& walls) const {
    const SupportOptions& o = options_;
    const int g = o.gap_layers;
    const Coord w = o.line_width;
    Paths hug;
    Paths model;
    Paths reach = region;
    reach.insert(reach.end(), walls.begin(), walls.end());
    const Paths near = box_around(reach, o.xy_gap + o.lean + 2 * w);
    for (int k = j - g; k <= j + g; ++k) {
        const Paths& m = outline(k);
        if (m.empty()) continue;
        const Paths clipped = intersect(m, near);
        model.insert(model.end(), clipped.begin(), clipped.end());
    }
    if (!model.empty()) {
        const Paths keep_off = dilate(unite(model), o.xy_gap);
        if (!region.empty()) region = subtract(region, keep_off);
        hug = dilate(keep_off, o.lean + w);
        if (!walls.empty()) {
            // A wall is a line: it keeps half a width more off the model.
            const Paths wall_off = dilate(keep_off, w / 2);
            walls = clip_lines(walls, subtract(near, wall_off));
        }
    }
    region = without_specks(region, double(w) * double(w));  // a quarter of fresh_overhang's
    return hug;
}

// On the bottom layer, also the overhangs of layers 1 .. g, whose support would have to start
// below the bed to keep the z gap: they are held from the bed, touching the model, as
// PrusaSlicer does on its first layer. Left alone, such an overhang is a line laid in the air a
// layer or two above the bed (on cat, nearly all of what hangs with supports); a support
// touching it costs only a rougher underside over one layer. It keeps the xy gap from the
// model's first layer, the one beside it. No shadow for --support buildplate: nothing of the
// model lies under these overhangs, only the bed.
Paths SupportPlanner::grounded_overhangs() const {
    const SupportOptions& o = options_;
    const Coord w = o.line_width;
    const double min_area = 4.0 * double(w) * double(w);
    Paths grounded, lower;
    for (int k = 1; k <= o.gap_layers; ++k) {
        const Paths& below = outline(k - 1);
        lower.insert(lower.end(), below.begin(), below.end());
        const Paths& above = outline(k);
        if (above.empty()) continue;
        // What of layer k has nothing of the model under it, down to the bed.
        Paths f = lower.empty() ? above : subtract(above, dilate(unite(lower), o.reach));
        if (!f.empty()) f = without_specks(open(f, w / 4), min_area);
        grounded.insert(grounded.end(), f.begin(), f.end());
    }
    if (!grounded.empty() && !outline(0).empty())
        grounded = subtract(grounded, dilate(outline(0), o.xy_gap));
    if (!grounded.empty()) grounded = without_specks(unite(grounded), min_area / 4);
    return grounded;
}

// The dense top of the support: the new overhangs of the last interface layers.
void SupportPlanner::add_interface(SupportLayer& out, const Paths& fresh, const Paths& region) {
    const int layers = options_.interface_layers;
    if (layers > 0) {
        Paths top = fresh.empty() || region.empty() ? Paths{} : intersect(fresh, region);
        out.new_mm2 = area_mm2(top);
        fresh_.push_front(std::move(top));
        while (int(fresh_.size()) > layers) fresh_.pop_back();
        Paths recent;
        for (const Paths& f : fresh_) recent.insert(recent.end(), f.begin(), f.end());
        if (!recent.empty() && !region.empty()) out.interface = intersect(unite(recent), region);
    } else if (!fresh.empty() && !region.empty()) {
        out.new_mm2 = area_mm2(intersect(fresh, region));
    }
}

// Going down, each part narrows by `lean` (its edge then leans at the cavities' angle and holds
// itself). What of a part is too thin for its outline (under a line width: a peninsula
// narrowing away, a sliver) is printed as its medial axis instead, and that axis goes on down as
// a single wall, so that nothing of it is left hanging when the part narrows past it. A compact
// part no wider than a trunk goes straight down as a column; a long thin one narrows on until it
// would vanish, and its axis goes on down as a wall (a ring under a dome's rim becomes one
// cylinder). Returns the region carried to the layer below; adds the axes to `walls`.
Paths SupportPlanner::narrow(const Paths& region, const Paths& hug, SupportLayer& out,
                             Paths& walls) const {
    const SupportOptions& o = options_;
    const Coord w = o.line_width;
    Paths carried;
    const SkeletonOptions axis{w, w / 2, 5};
    auto add_axis = [&](const Paths& piece, bool print_here) {
        for (Path& l : medial_axis(piece, axis)) {
            if (l.size() < 2 || length(Paths{l}, false) < double(w)) continue;
            if (print_here) out.walls.push_back(l);
            walls.push_back(std::move(l));
        }
    };
    for (Paths& c : components(region)) {
        const Paths printable = open(c, w / 2);
        // Beside the model the support keeps its width, thin parts too: under a dome it is the
        // shadow of every ring above, to which each layer adds the next ring (narrowing there,
        // or dropping a ring too thin to print, would leave each ring a thin band of its own);
        // elsewhere it narrows.
        const Paths along = hug.empty() ? Paths{} : intersect(c, hug);
        // What is too thin to print and reaches further than a line's safe overhang from the
        // rest, away from the model, is printed as its axis and goes on down as a wall (a
        // corner rounded off by the opening is held by the outline beside it).
        if (Paths lost = subtract(c, printable); area(lost) > 0.25 * double(w) * double(w)) {
            Paths held = printable.empty() ? Paths{} : dilate(printable, kHeld);
            if (!along.empty()) held = held.empty() ? along : unite(held, along);
            for (Paths& piece : components(lost))
                if (held.empty() || !subtract(piece, held).empty()) add_axis(piece, true);
        }
        if (!printable.empty() && erode(printable, o.trunk).empty()) {
            const BBox2 b = bounds(printable);
            if (std::max(b.max_x - b.min_x, b.max_y - b.min_y) <= 3 * o.trunk) {
                carried.insert(carried.end(), printable.begin(), printable.end());
                continue;
            }
        }
        Paths next = printable.empty() ? Paths{} : erode(printable, o.lean);
        if (!along.empty()) next = next.empty() ? along : unite(next, along);
        if (next.empty()) {
            if (!printable.empty()) add_axis(printable, false);
            continue;
        }
        carried.insert(carried.end(), next.begin(), next.end());
    }
    return carried;
}

SupportLayer SupportPlanner::plan(int j) {
    const SupportOptions& o = options_;
    const int g = o.gap_layers;
    const Coord w = o.line_width;
    SupportLayer out;

    Paths fresh = fresh_overhang(j);
    // Overhangs of neighbouring layers (the rings under a dome) and the support carried from
    // above meet within a lean or two: closed, they are one region printed sparse, not a stack
    // of thin columns side by side.
    Paths region = fresh.empty() ? carried_ : close(unite(carried_, fresh), 2 * o.lean);
    Paths walls = walls_;
    Paths hug;  // beside the model: where the support does not narrow
    if (!region.empty() || !walls.empty()) hug = clear_of_model(j, region, walls);
    if (j == 0 && g > 0) {
        if (const Paths grounded = grounded_overhangs(); !grounded.empty()) {
            region = region.empty() ? grounded : unite(region, grounded);
            fresh = fresh.empty() ? grounded : unite(fresh, grounded);
        }
    }
    out.region = region;
    add_interface(out, fresh, region);

    // Walls standing under nothing of the region: printed as lines (inside the region its own
    // walls hold the same place).
    if (!walls.empty()) {
        out.walls =
            region.empty() ? walls : clip_lines(walls, subtract(box_around(walls, w), region));
        // Drop stubs shorter than a line width: nothing stands on them.
        Paths kept;
        for (Path& l : out.walls)
            if (l.size() >= 2 && length(Paths{l}, false) >= double(w)) kept.push_back(std::move(l));
        out.walls = std::move(kept);
    }
    carried_ = narrow(region, hug, out, walls);
    walls_ = std::move(walls);

    next_ = j - 1;
    while (!outlines_.empty() && outlines_.front().first > next_ + g + 1) outlines_.pop_front();
    return out;
}

}  // namespace carve

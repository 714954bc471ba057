// The per-layer half of carve check's analyser: once a layer's moves are read, its footprint
// against what lies below (the previous layers within its thickness, the supports' tops within
// the gap) and against the model's slice, summed into the result. Kept apart from the G-code
// interpreter in gcode_analysis.cpp: this is where the measure is, that is where the file is read.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "base/error.hpp"
#include "check/analyser.hpp"
#include "check/footprint.hpp"

namespace carve::check {

namespace {

constexpr double kMaxLayerMm = 1.0;      // no layer is thicker: how far back recent layers go
constexpr double kDefaultLayerMm = 0.2;  // a layer's thickness when nothing tells it
// Layers held for what lies below (interleaved support layers, the support gap): a file that
// goes up and down 200,000 times kept every layer and read them all for each new one.
constexpr size_t kMaxRecent = 64;

}  // namespace

void Analyser::start_layer(double z) {
    if (have_layer_) finish_layer();
    if (result_.layers >= kMaxLayers)
        throw InputError(fmt::format(
            "line {}: more than 1 million layers; carve check measures files of fewer", line_no_));
    layer_points_ = 0;
    on_bed_ = false;
    mid_air_ = false;
    double height;
    if (!have_prev_) {
        height = z;
        first_z_ = z;
        // A first layer more than a layer's thickness above the bed is printed in mid-air.
        on_bed_ = z <= kMaxLayerMm + kZTolerance;
        if (!on_bed_) mid_air_ = true, height = kDefaultLayerMm;
    } else if (z > prev_z_ + kZTolerance) {
        height = z - prev_z_;
        // Farther above the layer below than any layer is thick: nothing holds it. Its lines
        // are as thick as the layer below's (the gap is no thickness: a gap of a billion
        // millimetres made lines as wide and took gigabytes).
        if (height > kMaxLayerMm + kZTolerance) mid_air_ = true, height = prev_height_;
    } else {
        // Going down again: a sequential print starting its next object, or odd output.
        ++result_.z_reversals;
        if (z <= first_z_ + kZTolerance) {
            height = std::max(z, kZTolerance);
            on_bed_ = true;
        } else {
            height = prev_height_;
        }
    }
    have_layer_ = true;
    layer_z_ = z;
    layer_ = LayerFigures{};
    layer_.z_mm = z;
    layer_.height_mm = height;
}

// What lies below: the layers within the thickness of this one (one layer, unless a slicer
// interleaves thinner layers, as PrusaSlicer does between its support's layers and the
// object's), and the supports' tops within the gap below that (a support holds its overhang
// across a gap of a layer or so). Most layers: the previous layer alone, read in place;
// otherwise the footprints gathered into `merged`.
const Paths& Analyser::below_layer(double reach_z, Paths& merged) {
    while (!recent_.empty() && (recent_.front().z < reach_z - opt_.support_gap_mm - kMaxLayerMm ||
                                recent_.size() > kMaxRecent))
        recent_.pop_front();
    // The layer read last lies below this one only if it is lower and within its reach: not
    // when this one is in mid-air, or lower (a sequential print's next object).
    const bool prev_below = have_prev_ && prev_z_ < layer_.z_mm - kZTolerance &&
                            prev_z_ >= reach_z - opt_.support_gap_mm;
    size_t parts = 0;
    for (const Recent& r : recent_) {
        if (r.z > layer_.z_mm - kZTolerance) continue;  // a sequential print's next object
        const Paths* add = r.z >= reach_z                         ? &r.footprint
                           : r.z >= reach_z - opt_.support_gap_mm ? &r.support
                                                                  : nullptr;
        if (!add || add->empty()) continue;
        if (add != &recent_.back().footprint) ++parts;
        merged.insert(merged.end(), add->begin(), add->end());
    }
    if (parts > 0 && prev_below)
        merged.insert(merged.end(), prev_footprint_.begin(), prev_footprint_.end());
    return parts == 0 && prev_below ? prev_footprint_ : merged;
}

// What of the layer nothing below holds, its longest bridge, what of it hangs far (support
// held by the model's top across the gap), and where: over the model's slice or beyond it.
void Analyser::measure_hanging(const Paths& footprint, const Paths& support_footprint,
                               const Paths& below, double reach_z) {
    Paths unsupported = difference(footprint, dilate_round(below, r_units_));
    layer_.unsupported_area_mm2 = region_area_mm2(unsupported);
    if (unsupported.empty()) return;
    std::vector<Path> moves;
    moves.reserve(lines_.size());
    for (const Polyline& l : lines_) moves.push_back(l.points);
    const Bridge bridge = longest_bridge(moves, unsupported);
    layer_.longest_bridge_mm = bridge.length_mm;
    if (bridge.length_mm > result_.longest_bridge_mm) {
        result_.longest_bridge_mm = bridge.length_mm;
        result_.longest_bridge_z_mm = layer_.z_mm;
        result_.longest_bridge_x_mm = bridge.x_mm;
        result_.longest_bridge_y_mm = bridge.y_mm;
    }
    Paths far = far_region(unsupported, below, far_units_);
    if (!support_footprint.empty() && !far.empty()) {
        // A support standing on the model's top leaves the same gap: support extrusion is held
        // by anything printed within the gap below it.
        Paths on_model;
        for (const Recent& r : recent_)
            if (r.z < reach_z && r.z >= reach_z - opt_.support_gap_mm && !r.footprint.empty())
                on_model.insert(on_model.end(), r.footprint.begin(), r.footprint.end());
        Paths far_support = intersection(far, support_footprint);
        if (!on_model.empty() && !far_support.empty()) {
            on_model.insert(on_model.end(), below.begin(), below.end());
            Paths rest = difference(far, support_footprint);
            far_support = far_region(far_support, on_model, far_units_);
            far = std::move(rest);
            far.insert(far.end(), far_support.begin(), far_support.end());
        }
        layer_.hanging_support_mm2 = region_area_mm2(far_support);
    }
    layer_.far_unsupported_area_mm2 = region_area_mm2(far);
    if (opt_.model_slice && have_prev_model_ && !far.empty()) {
        // Over the model's slice one layer down: something inside the object could have held
        // it. The rest hangs beyond the model itself.
        layer_.hanging_inside_mm2 = region_area_mm2(intersection(far, prev_model_));
        layer_.hanging_overhang_mm2 =
            std::max(0.0, layer_.far_unsupported_area_mm2 - layer_.hanging_inside_mm2);
    } else {
        layer_.hanging_overhang_mm2 = layer_.far_unsupported_area_mm2;
    }
}

// The layer's figures added to the file's.
void Analyser::add_layer_sums() {
    GcodeAnalysis& r = result_;
    if (r.layers == 0) r.first_z_mm = layer_.z_mm;
    r.last_z_mm = std::max(r.last_z_mm, layer_.z_mm);
    ++r.layers;
    r.path_length_mm += layer_.path_length_mm;
    r.footprint_area_mm2 += layer_.footprint_area_mm2;
    r.unsupported_area_mm2 += layer_.unsupported_area_mm2;
    r.far_unsupported_area_mm2 += layer_.far_unsupported_area_mm2;
    r.outside_area_mm2 += layer_.outside_area_mm2;
    r.max_outside_model_mm = std::max(r.max_outside_model_mm, layer_.max_outside_model_mm);
    r.hanging_inside_mm2 += layer_.hanging_inside_mm2;
    r.hanging_overhang_mm2 += layer_.hanging_overhang_mm2;
    r.hanging_support_mm2 += layer_.hanging_support_mm2;
    r.outside_support_mm2 += layer_.outside_support_mm2;
    r.travel_inside_mm += layer_.travel_inside_mm;
    r.travel_outside_mm += layer_.travel_outside_mm;
    r.wall_crossings += layer_.wall_crossings;
    if (opt_.keep_layers) r.per_layer.push_back(layer_);
}

// The layer kept as what lies below the next ones.
void Analyser::keep_as_below(Paths footprint, Paths support_footprint, double h) {
    // The last layer is read from prev_footprint_, the ones before from recent_. Its entry may
    // be gone already, dropped above as out of this layer's reach (a layer in mid-air): then
    // nothing of it is kept (back() of the empty deque wrote through a dangling reference, which
    // AddressSanitizer found as a leak in HostileCheck.LayersInMidAirHang).
    if (have_prev_ && !recent_.empty()) recent_.back().footprint = std::move(prev_footprint_);
    // Layers at or above this one lie below none of the next ones that this one does not
    // cover: a file going up and down (200,000 Z reversals) kept them all and merged dozens of
    // footprints for every layer.
    while (!recent_.empty() && recent_.back().z > layer_.z_mm - kZTolerance) recent_.pop_back();
    recent_.push_back({layer_.z_mm, {}, std::move(support_footprint)});
    prev_footprint_ = std::move(footprint);
    have_prev_ = true;
    prev_z_ = layer_.z_mm;
    prev_height_ = h;
}

void Analyser::finish_layer() {
    have_layer_ = false;
    double h = layer_.height_mm;
    if (h <= kZTolerance) h = prev_height_ > 0 ? prev_height_ : 0.2;
    if (scan_only_) {
        ++result_.layers;
        have_prev_ = true;
        prev_z_ = layer_.z_mm;
        prev_height_ = h;
        layer_travel_.clear();
        return;
    }
    // A layer holding only support (PrusaSlicer interleaves them between the object's
    // layers) is not the object's layer below: the object's lines are as thick as the step
    // from the last layer that held the object, and what lies below them reaches that far.
    const bool support_only =
        std::all_of(lines_.begin(), lines_.end(), [](const Polyline& l) { return l.support; });
    const double model_h =
        !support_only && have_model_z_ && !mid_air_ && layer_.z_mm - model_z_ > h + kZTolerance
            ? std::min(layer_.z_mm - model_z_, kMaxLayerMm)
            : h;
    Paths footprint = widen(lines_, model_h, filament_area_, opt_.bead);
    Paths support_footprint;
    double thickest = model_h;  // a ;HEIGHT: comment may say support is thicker
    for (const Polyline& l : lines_) thickest = std::max(thickest, l.height);
    if (opt_.object_layer && !support_only) report_object(footprint, model_h);
    if (!support_only) {
        have_model_z_ = true;
        model_z_ = layer_.z_mm;
    }
    if (std::any_of(lines_.begin(), lines_.end(), [](const Polyline& l) { return l.support; })) {
        std::vector<Polyline> support_lines;
        for (const Polyline& l : lines_)
            if (l.support) support_lines.push_back(l);
        support_footprint = widen(support_lines, model_h, filament_area_, opt_.bead);
    }
    layer_.footprint_area_mm2 = region_area_mm2(footprint);
    const double reach_z = layer_.z_mm - thickest - kZTolerance;
    Paths merged;
    const Paths& below = below_layer(reach_z, merged);
    if (!on_bed_) measure_hanging(footprint, support_footprint, below, reach_z);
    if (layer_.path_length_mm > 0) {
        double width = line_width(layer_.extruded_volume_mm3 / layer_.path_length_mm, h, opt_.bead);
        width_sum_ += width * layer_.path_length_mm;
        width_weight_ += layer_.path_length_mm;
    }
    if (opt_.model_slice) {
        check_model(footprint, support_footprint, h);
        // Support-only layers (PrusaSlicer's interleaved ones) are not the object's layers.
        if (!support_only) {
            printability_.layer(layer_.z_mm, model_h, footprint, prev_model_);
            layer_.uncovered_mm2 = uncovered_.layer(result_.layers, layer_.z_mm, prev_model_,
                                                    footprint, disk_width_mm());
        }
    }
    lines_.clear();
    layer_travel_.clear();
    add_layer_sums();
    keep_as_below(std::move(footprint), std::move(support_footprint), h);
}

// The uncovered check's disk: a line's width, 1.125 x the nozzle when the header names it
// (PrusaSlicer's default width), else the mean line width measured so far.
double Analyser::disk_width_mm() const {
    if (result_.nozzle_diameter_mm > 0)
        return kStrictLineWidthPerNozzle * result_.nozzle_diameter_mm;
    return width_weight_ > 0 ? width_sum_ / width_weight_ : kStrictLineWidthPerNozzle * 0.4;
}

// What of the model lies above the last layer that printed it is all left out (a wall too thin
// for the slicer, from some height up: a vase's, lettering's): sliced on at the last layer's
// height, counted on from the G-code's last layer index.
void Analyser::model_above_print() {
    if (!have_model_z_ || opt_.model_top_mm <= model_z_ + kZTolerance) return;
    const double h = std::max(prev_height_ > kZTolerance ? prev_height_ : kDefaultLayerMm, 0.01);
    int index = result_.layers;
    for (double z = model_z_ + h; z - h / 2 < opt_.model_top_mm && index < kMaxLayers;
         z += h, ++index) {
        const Paths model = opt_.model_slice(z - h / 2);
        if (uncovered_.layer(index, z, model, {}, disk_width_mm()) > 0)
            uncovered_.count_layer_above_print();
    }
}

void Analyser::report_object(const Paths& footprint, double h) {
    double e = 0;
    size_t own = 0;
    for (const Polyline& l : lines_)
        if (l.object && !l.support) e += l.e, ++own;
    if (own == 0) return;
    if (own == lines_.size()) {
        opt_.object_layer(layer_.z_mm, h, footprint, e * filament_area_);
        return;
    }
    // Support or a purge line beside the object on this layer: the object's lines alone.
    std::vector<Polyline> lines;
    lines.reserve(own);
    for (const Polyline& l : lines_)
        if (l.object && !l.support) lines.push_back(l);
    opt_.object_layer(layer_.z_mm, h, widen(lines, h, filament_area_, opt_.bead),
                      e * filament_area_);
}

void Analyser::check_model(const Paths& footprint, const Paths& support_footprint, double h) {
    result_.model_checked = true;
    Paths model = opt_.model_slice(layer_.z_mm - h / 2);
    double tolerance = opt_.model_tolerance_mm;
    if (tolerance < 0) {
        tolerance =
            layer_.path_length_mm > 0
                ? 0.5 * line_width(layer_.extruded_volume_mm3 / layer_.path_length_mm, h, opt_.bead)
                : 0.2;
    }
    tolerance_sum_ += tolerance;
    Paths grown = dilate_round(model, to_units(tolerance));
    Paths outside_tol = difference(footprint, grown);
    layer_.outside_area_mm2 = region_area_mm2(outside_tol);
    if (!support_footprint.empty())
        layer_.outside_support_mm2 = region_area_mm2(difference(support_footprint, grown));
    if (!layer_travel_.empty()) {
        const TravelFigures t = measure_travel(layer_travel_, grown);
        layer_.travel_inside_mm = t.inside_mm;
        layer_.travel_outside_mm = t.outside_mm;
        layer_.wall_crossings += t.wall_crossings;
    }
    prev_model_ = model;
    have_prev_model_ = true;
    layer_.max_outside_model_mm = max_distance_outside(footprint, model);
}

}  // namespace carve::check

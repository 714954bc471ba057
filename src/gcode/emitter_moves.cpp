// The emitter's moves: travels (combed into a layer from the layer below, z-hop), retraction
// with its wipe and recovery, extrusions at the speed of their feature with their E, arcs for
// runs on one circle, and the book-keeping of each printed move (see emitter.hpp).
#include <cmath>
#include <iterator>

#include "gcode/cooling.hpp"
#include "gcode/emitter.hpp"
#include "gcode/limits.hpp"

namespace carve {

// Emits " F..." when the feed rate changes (it is modal, shared by G0 and G1).
void Emitter::feed(double mm_per_s) {
    guard(mm_per_s > 0 && mm_per_s <= 10000, "F");
    const long long f = std::llround(mm_per_s * 60.0);
    if (f == carry_.feed) return;
    carry_.feed = f;
    fmt::format_to(std::back_inserter(buf_), " F{}", f);
}

void Emitter::e_word(long long target) {
    guard(std::isfinite(carry_.e_mm) && std::abs(carry_.e_mm) < 1e9, "E");
    put(" E");
    fixed(st_.relative_e ? target - carry_.e_units : target, 5);
}

// Retraction and its recovery are the same pure-filament move at the retraction speed.
void Emitter::move_filament(long long target) {
    put("G1");
    e_word(target);
    feed(st_.retract_speed);
    buf_.push_back('\n');
    carry_.e_units = target;
    retract_dwell();
}

// A filament-only move: the estimate times it as the firmware runs it (retract_time), the cooling
// as it did before, at the retraction speed, so that no layer's feed rate changes.
void Emitter::retract_dwell() {
    carry_.planner.dwell(retract_time(st_), st_.retract_length / retract_speed_limit(st_));
}

void Emitter::retract() {
    if (!can_retract() || carry_.retracted) return;
    if (st_.wipe && carry_.wipe_length > 0) {
        wipe();
    } else if (st_.firmware_retraction) {
        line("G10 ; retract");
        retract_dwell();
    } else {
        move_filament(carry_.e_units - retract_units_);
    }
    carry_.retracted = true;
    ++stats_.retractions;
}

// Back along the last path while retracting, so that what oozes lands on the line just
// printed (PrusaSlicer's wipe). The filament moves at most at the retraction speed: the
// nozzle slows down if the wipe is short. With firmware retraction the wipe is a plain
// move before G10, the firmware knowing its own length.
void Emitter::wipe() {
    const bool firmware = st_.firmware_retraction;
    double v = st_.travel_speed;
    if (!firmware && st_.retract_length > 0)
        v = std::min(v, carry_.wipe_length * st_.retract_speed / st_.retract_length);
    line(";WIPE_START");
    const long long e0 = carry_.e_units;
    double done = 0;
    for (const Point& q : carry_.wipe_path) {
        const double dx = to_mm(q.X - carry_.pos.X), dy = to_mm(q.Y - carry_.pos.Y);
        const double len = std::hypot(dx, dy);
        if (len <= 0) continue;
        done += len;
        put("G1 X");
        fixed(q.X, 3);
        put(" Y");
        fixed(q.Y, 3);
        if (!firmware) {
            const long long target = e0 - std::llround(double(retract_units_) *
                                                       std::min(1.0, done / carry_.wipe_length));
            e_word(target);
            carry_.e_units = target;
        }
        feed(v);
        buf_.push_back('\n');
        // The wipe extrudes (backwards) after the line: every firmware moves it at the print
        // acceleration (Marlin's P applies to any move with E, and S was the print's).
        carry_.planner.move(dx, dy, v, print_accel_);
        stats_.travel_length_mm += len;
        carry_.pos = q;
    }
    if (!firmware && carry_.e_units != e0 - retract_units_) {
        put("G1");
        e_word(e0 - retract_units_);
        feed(st_.retract_speed);
        buf_.push_back('\n');
        carry_.e_units = e0 - retract_units_;
    }
    line(";WIPE_END");
    if (firmware) {
        line("G10 ; retract");
        retract_dwell();
    } else {
        carry_.planner.stop();
    }
    carry_.wipe_path.clear();
    carry_.wipe_length = 0;
}

void Emitter::unretract() {
    if (!carry_.retracted) return;
    if (st_.firmware_retraction) {
        line("G11 ; unretract");
        retract_dwell();
    } else {
        move_filament(std::llround(carry_.e_mm * kEScale));
    }
    carry_.retracted = false;
}

void Emitter::move_z(Coord z, const char* what) {
    if (z == carry_.z) return;
    put("G1 Z");
    fixed(z + z_offset_, 3);  // --z-offset: the printer's Z, not the layer's
    if (!what)
        what = z > carry_.layer_z ? "a travel's lift (--z-hop, a profile's retract_lift)"
                                  : "a layer change";
    bounds_.moved_to(to_mm(z + z_offset_), what);
    // A move to the layer's own height always states its feed, modal or not: Moonraker takes
    // the object's height from the highest "G1 Z.. F.." when a file has no
    // ;BEFORE_LAYER_CHANGE comments (it said 67.4 mm of the 120 mm cat).
    if (z == carry_.layer_z) carry_.feed = -1;
    feed(kZSpeed);
    buf_.push_back('\n');
    const double dz = carry_.z < 0 ? to_mm(z) : std::abs(to_mm(z - carry_.z));
    // The cooling times it as before Klipper's Z limits were planned (no feed rate changes).
    const double cooling = st_.flavor == GcodeFlavor::Klipper
                               ? trapezoid_time(dz, 0, kZSpeed, 0, travel_accel_)
                               : trapezoid_time(dz, 0, std::min(kZSpeed, st_.max_feedrate_z), 0,
                                                std::min(travel_accel_, st_.max_acceleration_z));
    carry_.planner.dwell(z_move_time(st_, dz, kZSpeed, travel_accel_), cooling);
    carry_.z = z;
}

// The travel to `p` through `via` (output coordinates). A travel planned inside the part
// never retracts; any other retracts when longer than retract_before_travel.
void Emitter::travel_to(const Point& p, const Path& via, TravelKind kind) {
    if (p == carry_.pos && via.empty()) {
        if (carry_.layer_z > carry_.z) move_z(carry_.layer_z);
        return;
    }
    double d = 0;
    Point at = carry_.pos;
    for (const Point& q : via) d += std::hypot(to_mm(q.X - at.X), to_mm(q.Y - at.Y)), at = q;
    d += std::hypot(to_mm(p.X - at.X), to_mm(p.Y - at.Y));
    const bool retract_now =
        can_retract() && kind != TravelKind::Inside && d > st_.retract_min_travel;
    if (retract_now) retract();
    Coord hop = retract_now ? to_units(st_.z_hop) : 0;
    // The first travel crosses the bed from wherever the start G-code left the nozzle (the end
    // of a purge line, at the first layer's height): retracted and lifted by a layer at least,
    // as PrusaSlicer's MK3S profile does (0.8 mm, to Z 0.4), not dragged through the first
    // layer's height.
    if (carry_.first_travel) hop = std::max(hop, to_units(st_.first_layer_mm()));
    if (hop > 0)
        move_z(std::max(carry_.z, carry_.layer_z) + hop);
    else if (carry_.layer_z > carry_.z)
        move_z(carry_.layer_z);
    for (const Point& q : via) travel_move(q);
    travel_move(p);
    if (carry_.z != carry_.layer_z) move_z(carry_.layer_z);
    carry_.first_travel = false;
}

void Emitter::travel_move(const Point& p) {
    if (p == carry_.pos) return;
    use_acceleration(travel_accel_);
    put("G0 X");
    fixed(p.X, 3);
    put(" Y");
    fixed(p.Y, 3);
    feed(st_.travel_speed);
    buf_.push_back('\n');
    carry_.planner.move(to_mm(p.X - carry_.pos.X), to_mm(p.Y - carry_.pos.Y), st_.travel_speed,
                        travel_accel_);
    stats_.travel_length_mm += std::hypot(to_mm(p.X - carry_.pos.X), to_mm(p.Y - carry_.pos.Y));
    carry_.pos = p;
}

// The travel into a layer, from where the layer below ended: planned here, the only stage
// that knows both ends. The comber is built once per layer, and only if needed.
// Where the part narrows upwards the layer below ended outside this layer's comb region, on
// what is now the top of the part: the nozzle first moves in over that top, then combs. Up to
// 2.5 mm, which holds every such entry on the shared models (the widest, 2.45 mm, on skull's
// top); before, each of them retracted (fandisk 5 retractions in all, 3 of them these).
TravelPlan Emitter::plan_layer_entry(const Point& target_model) {
    if (carry_.first_travel || !layer_comb_ || layer_comb_->empty()) return {};
    const Point from(carry_.pos.X - off_x_, carry_.pos.Y - off_y_);
    for (const LayerEntry& e : last_entries_)
        if (e.from == from && e.to == target_model) return e.plan;
    if (last_entries_.size() == 2) last_entries_.erase(last_entries_.begin());
    last_entries_.push_back({from, target_model, find_layer_entry(from, target_model)});
    return last_entries_.back().plan;
}

TravelPlan Emitter::find_layer_entry(const Point& from, const Point& target_model) {
    TravelPlan plan;
    if (!comber_) comber_ = std::make_unique<Comber>(*layer_comb_);
    const TravelOptions options = travel_options(st_);
    // Where the comb region splits (a wall thinner than it), inside the outer wall's centreline,
    // as plan_layer does within a layer: on skull the travel into a layer crossed the cranium.
    auto plan_to = [&](const Point& a) {
        TravelPlan p = plan_travel(*comber_, a, target_model, options);
        if (p.leaves && layer_thin_ && !layer_thin_->empty()) {
            if (!thin_) thin_ = std::make_unique<Comber>(*layer_thin_);
            p = plan_travel(*comber_, a, target_model, options, thin_.get());
        }
        return p;
    };
    plan = plan_to(from);
    constexpr Coord kEntryReach = 2500;
    if (!plan.leaves || comber_->locate(from, options.reach)) return plan;
    const auto onto = comber_->locate(from, std::max(options.reach, kEntryReach));
    if (!onto) return plan;
    TravelPlan inside = plan_to(onto->p);
    if (inside.leaves) return plan;
    inside.via.insert(inside.via.begin(), onto->p);
    return inside;
}

bool Emitter::enter_reversed(const LayerToolpaths& layer) {
    const std::vector<size_t>& starts = layer.island_starts;
    if (carry_.first_travel || starts.size() < 3 || starts.back() > layer.extrusions.size())
        return false;
    const Point from(carry_.pos.X - off_x_, carry_.pos.Y - off_y_);
    // Staying inside first (no string, no retraction), then the shorter way.
    auto cost = [&](size_t first) {
        const Point& to = layer.extrusions[first].points.front();
        const TravelPlan plan = plan_layer_entry(to);
        double len = 0;
        Point at = from;
        for (const Point& q : plan.via) len += distance(at, q), at = q;
        return std::pair{plan.leaves, len + distance(at, to)};
    };
    return cost(starts[starts.size() - 2]) < cost(starts[0]);
}

double Emitter::speed_of(Feature f) const {
    double v = st_.perimeter_speed;
    switch (f) {
        case Feature::OuterWall:
        case Feature::Shell:
            v = st_.perimeter_speed;
            break;
        case Feature::Cover:
        case Feature::SupportInterface:  // dense lines under the overhang, as a cover's
            v = st_.cover_speed;
            break;
        case Feature::CavityWall:
        case Feature::Rib:
        case Feature::Tie:
        case Feature::Support:  // single walls, as the cavities'
            v = st_.cavity_speed;
            break;
        case Feature::Bridge:
            v = st_.bridge_speed;
            break;
        case Feature::Skirt:  // as PrusaSlicer: at the perimeters' speed
        case Feature::Brim:
            v = st_.perimeter_speed;
            break;
    }
    if (st_.max_print_speed > 0) v = std::min(v, st_.max_print_speed);
    if (print_layer() == 0) v = std::min(v, st_.first_layer_speed);
    return slowed_speed(v, speed_factor_, st_.min_print_speed);
}

void Emitter::extrude(const Extrusion& ex, const Travel& travel) {
    if (ex.points.size() < 2) return;
    auto shifted = [&](const Point& p) { return Point(p.X + off_x_, p.Y + off_y_); };
    Path via;
    TravelKind kind = travel.kind;
    if (kind == TravelKind::Unplanned) {
        TravelPlan plan = plan_layer_entry(ex.points.front());
        if (!plan.via.empty() || !plan.leaves) {
            via = std::move(plan.via);
            kind = plan.leaves ? TravelKind::Leaves : TravelKind::Inside;
        }
    } else {
        via = travel.via;
    }
    for (Point& q : via) q = shifted(q);
    travel_to(shifted(ex.points.front()), via, kind);
    if (!carry_.type_known || ex.feature != carry_.type) {
        carry_.type_known = true;
        carry_.type = ex.feature;
        fmt::format_to(std::back_inserter(buf_), ";TYPE:{}\n", feature_name(ex.feature));
    }
    // The layer's own line width and thickness: the first layer's may differ.
    const double layer_width = st_.layer_width_mm(carry_.layer), layer_height = thickness();
    const double width = layer_width * ex.flow;
    if (width != carry_.width) {
        carry_.width = width;
        fmt::format_to(std::back_inserter(buf_), ";WIDTH:{:.3f}\n", width);
    }
    set_fan(fan_byte(ex.feature == Feature::Bridge ? bridge_fan_percent(st_, carry_.layer)
                                                   : layer_fan_));
    unretract();
    use_acceleration(print_accel_);
    // --max-volumetric-speed: no faster than the cap over the line's cross-section, rounded
    // down to a whole mm/min so that the F written keeps under the cap. The cross-section is
    // the larger of the real one and the one ;WIDTH and ;HEIGHT state (3 decimals): a viewer
    // computing the flow from the file finds it under the cap too.
    double speed = speed_of(ex.feature);
    if (st_.max_volumetric_speed > 0) {
        const double stated_w = std::max(width, std::round(width * 1000) / 1000);
        const double stated_h = std::max(layer_height, std::round(layer_height * 1000) / 1000);
        const double capped = std::floor(st_.max_volumetric_speed / (stated_w * stated_h) * 60);
        speed = std::min(speed, std::max(1.0, capped) / 60);
    }
    // Filament per mm of path: the line's cross-section (width x height) over the filament's,
    // scaled by --extrusion-multiplier.
    const double e_per_mm =
        layer_width * layer_height * ex.flow / filament_area_ * st_.extrusion_multiplier;
    const size_t n = ex.points.size() + (ex.closed ? 1 : 0);
    std::vector<Point>& pts = path_points_;
    pts.clear();
    for (size_t i = 0; i < n; ++i) pts.push_back(shifted(ex.points[i % ex.points.size()]));
    const double tolerance = st_.arc_tolerance * kUnitsPerMm;
    for (size_t i = 0; i + 1 < pts.size();) {
        if (st_.arc_fitting && pts[i] == carry_.pos) {
            if (const auto arc = fit_arc(pts, i, tolerance)) {
                arc_to(pts, i, *arc, speed, e_per_mm, ex.feature);
                i = arc->last;
                continue;
            }
        }
        const Point q = pts[++i];
        if (q == carry_.pos) continue;
        const double dx = to_mm(q.X - carry_.pos.X), dy = to_mm(q.Y - carry_.pos.Y);
        const double len = std::hypot(dx, dy);
        carry_.e_mm += len * e_per_mm;
        const long long target = std::llround(carry_.e_mm * kEScale);
        guard(std::abs(q.X) < kMaxCoord && std::abs(q.Y) < kMaxCoord, "X/Y");
        put("G1 X");
        fixed(q.X, 3);
        put(" Y");
        fixed(q.Y, 3);
        e_word(target);
        feed(speed);
        buf_.push_back('\n');
        carry_.e_units = target;
        carry_.planner.move(dx, dy, speed, print_accel_, e_per_mm);
        printed(q, len, e_per_mm, ex.feature);
    }
    if (st_.wipe) remember_for_wipe(ex, shifted);
}

// Book-keeping of a printed move of `len` mm ending at q.
void Emitter::printed(const Point& q, double len, double e_per_mm, Feature feature) {
    stats_.extruded_volume_mm3 += len * e_per_mm * filament_area_;
    if (feature == Feature::Bridge) stats_.bridge_length_mm += len;
    bounds_.min_x = std::min(bounds_.min_x, to_mm(q.X));
    bounds_.max_x = std::max(bounds_.max_x, to_mm(q.X));
    bounds_.min_y = std::min(bounds_.min_y, to_mm(q.Y));
    bounds_.max_y = std::max(bounds_.max_y, to_mm(q.Y));
    bounds_.min_z = std::min(bounds_.min_z, to_mm(carry_.z));
    bounds_.max_z = std::max(bounds_.max_z, to_mm(carry_.z));
    if (object_ >= 0) {
        Bounds& o = object_bounds_[static_cast<size_t>(object_)];
        o.min_x = std::min(o.min_x, to_mm(q.X)), o.max_x = std::max(o.max_x, to_mm(q.X));
        o.min_y = std::min(o.min_y, to_mm(q.Y)), o.max_y = std::max(o.max_y, to_mm(q.Y));
        o.min_z = std::min(o.min_z, to_mm(carry_.z)), o.max_z = std::max(o.max_z, to_mm(carry_.z));
    }
    carry_.pos = q;
}

// One G2/G3 for points first+1..arc.last. The planner times the chords it replaces (the
// arc is within the tolerance of them); E follows the arc's own length.
void Emitter::arc_to(const std::vector<Point>& pts, size_t first, const Arc& arc, double speed,
                     double e_per_mm, Feature feature) {
    const Point q = pts[arc.last];
    const double len = arc.length / kUnitsPerMm;
    carry_.e_mm += len * e_per_mm;
    const long long target = std::llround(carry_.e_mm * kEScale);
    guard(std::abs(q.X) < kMaxCoord && std::abs(q.Y) < kMaxCoord, "X/Y");
    put(arc.counter_clockwise ? "G3 X" : "G2 X");
    fixed(q.X, 3);
    put(" Y");
    fixed(q.Y, 3);
    put(" I");
    fixed(std::llround(arc.cx - double(carry_.pos.X)), 3);
    put(" J");
    fixed(std::llround(arc.cy - double(carry_.pos.Y)), 3);
    e_word(target);
    feed(speed);
    buf_.push_back('\n');
    carry_.e_units = target;
    for (size_t k = first; k < arc.last; ++k)
        carry_.planner.move(to_mm(pts[k + 1].X - pts[k].X), to_mm(pts[k + 1].Y - pts[k].Y), speed,
                            print_accel_, e_per_mm);
    for (size_t k = first + 1; k < arc.last; ++k) printed(pts[k], 0, e_per_mm, feature);
    printed(q, len, e_per_mm, feature);
    ++stats_.arcs;
    stats_.lines_saved_by_arcs += static_cast<long long>(arc.last - first) - 1;
}

// The last wipe_distance of the path just printed, walking back from its end.
template <class Shift>
void Emitter::remember_for_wipe(const Extrusion& ex, Shift shifted) {
    carry_.wipe_path.clear();
    carry_.wipe_length = 0;
    const size_t m = ex.points.size();
    const size_t n = m + (ex.closed ? 1 : 0);
    Point at = carry_.pos;
    for (size_t k = n - 1; k-- > 0 && carry_.wipe_length < st_.wipe_distance;) {
        Point q = shifted(ex.points[k % m]);
        const double len = std::hypot(to_mm(q.X - at.X), to_mm(q.Y - at.Y));
        if (len <= 0) continue;
        if (carry_.wipe_length + len > st_.wipe_distance) {
            const double f = (st_.wipe_distance - carry_.wipe_length) / len;
            q = Point(at.X + std::llround(f * double(q.X - at.X)),
                      at.Y + std::llround(f * double(q.Y - at.Y)));
            carry_.wipe_length = st_.wipe_distance;
        } else {
            carry_.wipe_length += len;
        }
        carry_.wipe_path.push_back(q);
        at = q;
    }
}

// M204 S as the moves change where the firmware may read nothing else (switches_acceleration);
// the others were told M204 P and T once.
void Emitter::use_acceleration(double a) {
    if (!switches_acceleration(st_) || a == carry_.accel) return;
    carry_.accel = a;
    line(fmt::format("M204 S{}", std::llround(a)));
}

}  // namespace carve

// G-code assembly: spill layers as they come (top down), write them bottom up at the end.
//
// Layers are spilled in a compact binary form (zig-zag varint deltas) to an unlinked temporary
// file next to the output, so nothing is left behind even if the process dies. finish() runs the
// emitter once over the spilled layers, writing the body to a second unlinked file while it
// measures (time, material, bounds); then the header stating those figures, the body and the
// trailer go to a temporary name that is renamed onto the output when complete. The figures
// come from the very moves written, so the header cannot disagree with the body. (A measuring
// pass before the writing pass did the same in twice the time, all of it after the last layer,
// when nothing else runs.)
#include "gcode/gcode.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <limits>
#include <memory>
#include <mutex>
#include <numbers>
#include <regex>
#include <stdexcept>
#include <string_view>

#include "base/atomic_file.hpp"
#include "base/error.hpp"
#include "base/stage_timer.hpp"
#include "gcode/arcs.hpp"
#include "gcode/cooling.hpp"
#include "gcode/header.hpp"
#include "gcode/labels.hpp"
#include "gcode/limits.hpp"
#include "gcode/motion.hpp"
#include "gcode/placeholders.hpp"
#include "gcode/progress.hpp"
#include "gcode/spill.hpp"
#include "toolpath/comb.hpp"

namespace carve {

namespace {

constexpr double kZSpeed = 10.0;          // mm/s for layer changes and z-hops
constexpr long long kEScale = 100000;     // E is written with 5 decimals
constexpr size_t kFlushBytes = 1 << 20;   // text buffered before each fwrite
constexpr Coord kMaxCoord = 100'000'000;  // 100 m in um: no printer's bed, a guard only

[[noreturn]] void io_error(const std::string& what, const std::string& path) {
    throw OutputError("cannot write " + path + ": " + what);
}

// The last guard before a number reaches the printer: settings are validated where they are
// read, so a value failing here is carve's own bug, reported instead of written (a NaN would
// come out as E-92233720368547.75808 or F-9223372036854775808).
void guard(bool ok, const char* word) {
    if (!ok)
        throw std::runtime_error(std::string("G-code emitter: refusing a non-finite or "
                                             "out-of-range ") +
                                 word + " word");
}

// Does the expanded start G-code wait for this temperature itself ("M109 S215", "M190 R60")?
// Only a command counts, not a comment, and not a wait for 0 (that heats nothing).
bool waits_for(const std::string& gcode, std::string_view command) {
    size_t at = 0;
    while (at < gcode.size()) {
        size_t end = gcode.find('\n', at);
        if (end == std::string::npos) end = gcode.size();
        std::string_view line(gcode.data() + at, end - at);
        at = end + 1;
        line = line.substr(0, line.find(';'));
        while (!line.empty() && (line.front() == ' ' || line.front() == '\t'))
            line.remove_prefix(1);
        if (line.size() < command.size()) continue;
        bool same = true;
        for (size_t i = 0; i < command.size(); ++i)
            same = same && std::toupper(static_cast<unsigned char>(line[i])) == command[i];
        if (!same || (line.size() > command.size() &&
                      std::isdigit(static_cast<unsigned char>(line[command.size()]))))
            continue;
        // The target: S or R followed by a number above 0.
        for (size_t i = command.size(); i + 1 < line.size(); ++i) {
            const char c = static_cast<char>(std::toupper(static_cast<unsigned char>(line[i])));
            if ((c == 'S' || c == 'R') && (line[i - 1] == ' ' || line[i - 1] == '\t')) {
                const double v = std::atof(std::string(line.substr(i + 1)).c_str());
                if (v > 0) return true;
            }
        }
    }
    return false;
}

}  // namespace

std::string format_duration(double seconds) {
    long long s = std::llround(std::max(0.0, seconds));
    const long long d = s / 86400, h = s / 3600 % 24, m = s / 60 % 60, sec = s % 60;
    if (d > 0) return fmt::format("{}d {}h {}m {}s", d, h, m, sec);
    if (h > 0) return fmt::format("{}h {}m {}s", h, m, sec);
    if (m > 0) return fmt::format("{}m {}s", m, sec);
    return fmt::format("{}s", sec);
}

namespace {

struct Bounds {
    double min_x = std::numeric_limits<double>::max(), min_y = min_x, min_z = min_x;
    double max_x = std::numeric_limits<double>::lowest(), max_y = max_x, max_z = max_x;
    bool empty() const { return min_x > max_x; }
};

// Turns layers into G-code text (or, without a file, only measures what it would print).
class Emitter {
  public:
    Emitter(const Settings& st, Coord off_x, Coord off_y, std::FILE* out, std::string path,
            std::string object = "object")
        : st_(st),
          off_x_(off_x),
          off_y_(off_y),
          out_(out),
          path_(std::move(path)),
          object_(std::move(object)),
          planner_(machine_limits(st)) {
        const double r = st.filament_diameter / 2;
        filament_area_ = std::numbers::pi * r * r;
        retract_units_ = std::llround(std::max(0.0, st.retract_length) * kEScale);
    }

    void start() {
        guard(st_.first_layer_bed_temperature >= 0 && st_.first_layer_bed_temperature <= 200 &&
                  st_.first_layer_nozzle_temperature >= 0 &&
                  st_.first_layer_nozzle_temperature <= 500 && st_.bed_temperature >= 0 &&
                  st_.bed_temperature <= 200 && st_.nozzle_temperature >= 0 &&
                  st_.nozzle_temperature <= 500,
              "S (temperature)");
        const std::string start_text = expand_custom_gcode(st_.start_gcode, st_).text;
        const bool klipper_macro = st_.flavor == GcodeFlavor::Klipper && st_.start_gcode.empty();
        // Klipper's PRINT_START macro heats, given the temperatures: heating before it would
        // wait for the bed twice and leave the macro's own order (soak, mesh) without effect.
        const bool macro_heats = st_.flavor == GcodeFlavor::Klipper &&
                                 start_text.find("PRINT_START") != std::string::npos;
        for (const std::string& l : machine_limit_lines(st_)) line(l);
        set_fan(0);
        if (klipper_macro) {
            line(fmt::format("PRINT_START BED_TEMP={} EXTRUDER_TEMP={}",
                             st_.first_layer_bed_temperature, st_.first_layer_nozzle_temperature));
        } else if (!macro_heats) {
            // Like PrusaSlicer: heat unless the user's start G-code waits for it itself, judged
            // from the text the printer will get (an M109 inside a false {if} heats nothing).
            const bool user_bed = waits_for(start_text, "M190");
            const bool user_nozzle = waits_for(start_text, "M109");
            if (!user_bed) line(fmt::format("M140 S{} ; bed", st_.first_layer_bed_temperature));
            if (!user_nozzle)
                line(fmt::format("M104 S{} ; nozzle", st_.first_layer_nozzle_temperature));
            if (!user_bed)
                line(fmt::format("M190 S{} ; wait for bed", st_.first_layer_bed_temperature));
            if (!user_nozzle)
                line(fmt::format("M109 S{} ; wait for nozzle", st_.first_layer_nozzle_temperature));
        }
        raw(start_text);
        custom(st_.start_filament_gcode);
        line("G21 ; millimetres");
        line("G90 ; absolute coordinates");
        line(st_.relative_e ? "M83 ; relative extrusion" : "M82 ; absolute extrusion");
        line("G92 E0");
        mark_progress(0);
    }

    void layer(const LayerToolpaths& layer) {
        layer_ = layer.index;
        layer_z_ = to_units(layer.z);
        custom(st_.before_layer_gcode);
        put("\n;LAYER_CHANGE\n;Z:");
        fixed(layer_z_, 3);
        put("\n;HEIGHT:");
        fixed(to_units(st_.layer_height), 3);
        fmt::format_to(std::back_inserter(buf_), "\n;LAYER:{}\n", layer.index);
        custom(st_.layer_gcode);
        if (layer.index == 1) {
            if (st_.nozzle_temperature != st_.first_layer_nozzle_temperature)
                line(fmt::format("M104 S{}", st_.nozzle_temperature));
            if (st_.bed_temperature != st_.first_layer_bed_temperature)
                line(fmt::format("M140 S{}", st_.bed_temperature));
        }
        mark_progress(planner_.time());
        type_known_ = false;
        layer_comb_ = &layer.comb_region;
        print_layer_cooled(layer);
        layer_comb_ = nullptr;
        ++stats_.layers;
        flush(false);
    }

    void end() {
        if (!retracted_ && !first_travel_) retract();
        mark_progress(-1);  // 100 %: the total, known below
        custom(st_.end_filament_gcode);
        if (st_.flavor == GcodeFlavor::Klipper && st_.end_gcode.empty()) line("PRINT_END");
        raw(expand_custom_gcode(st_.end_gcode, st_,
                                {{"max_layer_z", to_mm(layer_z_)},
                                 {"layer_z", to_mm(layer_z_)},
                                 {"layer_num", std::max(0, layer_)}})
                .text);
        planner_.stop();
        stats_.estimated_print_time_s = planner_.time();
        stats_.filament_length_mm = stats_.extruded_volume_mm3 / filament_area_;
        stats_.filament_weight_g = stats_.extruded_volume_mm3 / 1000.0 * st_.filament_density;
        for (ProgressMark& m : marks_)
            if (m.elapsed_s < 0) m.elapsed_s = stats_.estimated_print_time_s;
        flush(true);
    }

    void comment_block(const std::vector<std::string>& lines) {
        for (const std::string& l : lines) line(l);
    }

    void flush_all() { flush(true); }
    const PrintStats& stats() const { return stats_; }
    const std::vector<ProgressMark>& progress_marks() const { return marks_; }
    const Bounds& bounds() const { return bounds_; }

  private:
    // --- text output.
    void put(std::string_view s) { buf_.append(s.data(), s.data() + s.size()); }
    void line(std::string_view s) {
        put(s);
        buf_.push_back('\n');
    }
    void raw(const std::string& text) {
        if (text.empty()) return;
        put(text);
        if (text.back() != '\n') buf_.push_back('\n');
    }
    // A profile's filament or layer-change G-code, expanded for the layer being written. A
    // "G92 E0" in it resets the firmware's E, as PrusaSlicer assumes.
    void custom(const std::string& text) {
        if (text.empty()) return;
        const std::string g = expand_custom_gcode(text, st_,
                                                  {{"layer_num", std::max(0, layer_)},
                                                   {"layer_z", to_mm(layer_z_)},
                                                   {"max_layer_z", to_mm(layer_z_)}})
                                  .text;
        raw(g);
        static const std::regex kResetE(R"((^|\n)\s*G92\s+E0*(\.0*)?(\s|;|$))");
        if (std::regex_search(g, kResetE)) {
            e_mm_ -= double(e_units_) / kEScale;
            e_units_ = 0;
        }
    }
    // A value in units of 10^-decimals (decimals >= 1), written with exactly that many
    // decimals. By hand: every coordinate of the file passes here, and fmt's general path (a
    // format string parsed per call) was most of the time spent writing G-code.
    void fixed(long long v, int decimals) {
        if (v < 0) {
            buf_.push_back('-');
            v = -v;
        }
        char digits[24];  // least significant first, at least decimals + 1 of them
        int n = 0;
        do {
            digits[n++] = static_cast<char>('0' + v % 10);
            v /= 10;
        } while (v > 0 || n <= decimals);
        for (int i = n - 1; i >= 0; --i) {
            if (i == decimals - 1) buf_.push_back('.');
            buf_.push_back(digits[i]);
        }
    }
    void flush(bool force) {
        if (!force && buf_.size() < kFlushBytes) return;
        if (buf_.size() > 0 && std::fwrite(buf_.data(), 1, buf_.size(), out_) != buf_.size())
            io_error(std::strerror(errno), path_);
        written_ += static_cast<long long>(buf_.size());
        buf_.clear();
    }

    // --- machine state changes.
    void set_fan(int speed) {
        speed = std::clamp(speed, 0, 255);
        if (speed == fan_) return;
        fan_ = speed;
        if (st_.flavor == GcodeFlavor::RepRap)
            line(fmt::format("M106 S{:.2f}", speed / 255.0));
        else if (speed == 0)
            line("M107");
        else
            line(fmt::format("M106 S{}", speed));
    }

    // Emits " F..." when the feed rate changes (it is modal, shared by G0 and G1).
    void feed(double mm_per_s) {
        guard(mm_per_s > 0 && mm_per_s <= 10000, "F");
        const long long f = std::llround(mm_per_s * 60.0);
        if (f == feed_) return;
        feed_ = f;
        fmt::format_to(std::back_inserter(buf_), " F{}", f);
    }

    void e_word(long long target) {
        guard(std::isfinite(e_mm_) && std::abs(e_mm_) < 1e9, "E");
        put(" E");
        fixed(st_.relative_e ? target - e_units_ : target, 5);
    }

    // Retraction and its recovery are the same pure-filament move at the retraction speed.
    void move_filament(long long target) {
        put("G1");
        e_word(target);
        feed(st_.retract_speed);
        buf_.push_back('\n');
        e_units_ = target;
        planner_.dwell(st_.retract_length / retract_speed_limit(st_));
    }

    bool can_retract() const { return st_.firmware_retraction || retract_units_ > 0; }

    void retract() {
        if (!can_retract() || retracted_) return;
        if (st_.wipe && wipe_length_ > 0) {
            wipe();
        } else if (st_.firmware_retraction) {
            line("G10 ; retract");
            planner_.dwell(st_.retract_length / retract_speed_limit(st_));
        } else {
            move_filament(e_units_ - retract_units_);
        }
        retracted_ = true;
        ++stats_.retractions;
    }

    // Back along the last path while retracting, so that what oozes lands on the line just
    // printed (PrusaSlicer's wipe). The filament moves at most at the retraction speed: the
    // nozzle slows down if the wipe is short. With firmware retraction the wipe is a plain
    // move before G10, the firmware knowing its own length.
    void wipe() {
        const bool firmware = st_.firmware_retraction;
        double v = st_.travel_speed;
        if (!firmware && st_.retract_length > 0)
            v = std::min(v, wipe_length_ * st_.retract_speed / st_.retract_length);
        line(";WIPE_START");
        const long long e0 = e_units_;
        double done = 0;
        for (const Point& q : wipe_path_) {
            const double dx = to_mm(q.X - pos_.X), dy = to_mm(q.Y - pos_.Y);
            const double len = std::hypot(dx, dy);
            if (len <= 0) continue;
            done += len;
            put("G1 X");
            fixed(q.X, 3);
            put(" Y");
            fixed(q.Y, 3);
            if (!firmware) {
                const long long target =
                    e0 - std::llround(double(retract_units_) * std::min(1.0, done / wipe_length_));
                e_word(target);
                e_units_ = target;
            }
            feed(v);
            buf_.push_back('\n');
            planner_.move(dx, dy, v, st_.travel_acceleration);
            stats_.travel_length_mm += len;
            pos_ = q;
        }
        if (!firmware && e_units_ != e0 - retract_units_) {
            put("G1");
            e_word(e0 - retract_units_);
            feed(st_.retract_speed);
            buf_.push_back('\n');
            e_units_ = e0 - retract_units_;
        }
        line(";WIPE_END");
        if (firmware) {
            line("G10 ; retract");
            planner_.dwell(st_.retract_length / retract_speed_limit(st_));
        } else {
            planner_.stop();
        }
        wipe_path_.clear();
        wipe_length_ = 0;
    }

    void unretract() {
        if (!retracted_) return;
        if (st_.firmware_retraction) {
            line("G11 ; unretract");
            planner_.dwell(st_.retract_length / retract_speed_limit(st_));
        } else {
            move_filament(std::llround(e_mm_ * kEScale));
        }
        retracted_ = false;
    }

    void move_z(Coord z) {
        if (z == z_) return;
        put("G1 Z");
        fixed(z, 3);
        feed(kZSpeed);
        buf_.push_back('\n');
        const double dz = z_ < 0 ? to_mm(z) : std::abs(to_mm(z - z_));
        const bool limited = st_.flavor != GcodeFlavor::Klipper;
        planner_.dwell(
            trapezoid_time(dz, 0, limited ? std::min(kZSpeed, st_.max_feedrate_z) : kZSpeed, 0,
                           limited ? std::min(st_.travel_acceleration, st_.max_acceleration_z)
                                   : st_.travel_acceleration));
        z_ = z;
    }

    // The travel to `p` through `via` (output coordinates). A travel planned inside the part
    // never retracts; any other retracts when longer than retract_before_travel.
    void travel_to(const Point& p, const Path& via, TravelKind kind) {
        if (p == pos_ && via.empty()) {
            if (layer_z_ > z_) move_z(layer_z_);
            return;
        }
        double d = 0;
        Point at = pos_;
        for (const Point& q : via) d += std::hypot(to_mm(q.X - at.X), to_mm(q.Y - at.Y)), at = q;
        d += std::hypot(to_mm(p.X - at.X), to_mm(p.Y - at.Y));
        const bool retract_now = !first_travel_ && can_retract() && kind != TravelKind::Inside &&
                                 d > st_.retract_min_travel;
        if (retract_now) retract();
        const Coord hop = retract_now ? to_units(st_.z_hop) : 0;
        if (hop > 0)
            move_z(std::max(z_, layer_z_) + hop);
        else if (layer_z_ > z_)
            move_z(layer_z_);
        for (const Point& q : via) travel_move(q);
        travel_move(p);
        if (z_ != layer_z_) move_z(layer_z_);
        first_travel_ = false;
    }

    void travel_move(const Point& p) {
        if (p == pos_) return;
        use_acceleration(st_.travel_acceleration);
        put("G0 X");
        fixed(p.X, 3);
        put(" Y");
        fixed(p.Y, 3);
        feed(st_.travel_speed);
        buf_.push_back('\n');
        planner_.move(to_mm(p.X - pos_.X), to_mm(p.Y - pos_.Y), st_.travel_speed,
                      st_.travel_acceleration);
        stats_.travel_length_mm += std::hypot(to_mm(p.X - pos_.X), to_mm(p.Y - pos_.Y));
        pos_ = p;
    }

    // The travel into a layer, from where the layer below ended: planned here, the only stage
    // that knows both ends. The comber is built once per layer, and only if needed.
    TravelPlan plan_layer_entry(const Point& target_model) {
        TravelPlan plan;
        if (first_travel_ || !layer_comb_ || layer_comb_->empty()) return plan;
        if (!comber_) comber_ = std::make_unique<Comber>(*layer_comb_);
        const Point from(pos_.X - off_x_, pos_.Y - off_y_);
        return plan_travel(*comber_, from, target_model, travel_options(st_));
    }

    double speed_of(Feature f) const {
        double v = st_.perimeter_speed;
        switch (f) {
            case Feature::OuterWall:
            case Feature::Shell:
                v = st_.perimeter_speed;
                break;
            case Feature::Cover:
                v = st_.cover_speed;
                break;
            case Feature::CavityWall:
                v = st_.cavity_speed;
                break;
            case Feature::Bridge:
                v = st_.bridge_speed;
                break;
        }
        if (st_.max_print_speed > 0) v = std::min(v, st_.max_print_speed);
        if (layer_ == 0) v = std::min(v, st_.first_layer_speed);
        return slowed_speed(v, speed_factor_, st_.min_print_speed);
    }

    void extrude(const Extrusion& ex, const Travel& travel) {
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
        if (!type_known_ || ex.feature != type_) {
            type_known_ = true;
            type_ = ex.feature;
            fmt::format_to(std::back_inserter(buf_), ";TYPE:{}\n", feature_name(ex.feature));
        }
        const double width = st_.width_mm() * ex.flow;
        if (width != width_) {
            width_ = width;
            fmt::format_to(std::back_inserter(buf_), ";WIDTH:{:.3f}\n", width);
        }
        set_fan(
            fan_byte(ex.feature == Feature::Bridge ? bridge_fan_percent(st_, layer_) : layer_fan_));
        unretract();
        use_acceleration(st_.acceleration);
        const double speed = speed_of(ex.feature);
        // Filament per mm of path: the line's cross-section (width x height) over the filament's.
        const double e_per_mm = st_.width_mm() * st_.layer_height * ex.flow / filament_area_;
        const size_t n = ex.points.size() + (ex.closed ? 1 : 0);
        std::vector<Point>& pts = path_points_;
        pts.clear();
        for (size_t i = 0; i < n; ++i) pts.push_back(shifted(ex.points[i % ex.points.size()]));
        const double tolerance = st_.arc_tolerance * kUnitsPerMm;
        for (size_t i = 0; i + 1 < pts.size();) {
            if (st_.arc_fitting && pts[i] == pos_) {
                if (const auto arc = fit_arc(pts, i, tolerance)) {
                    arc_to(pts, i, *arc, speed, e_per_mm, ex.feature);
                    i = arc->last;
                    continue;
                }
            }
            const Point q = pts[++i];
            if (q == pos_) continue;
            const double dx = to_mm(q.X - pos_.X), dy = to_mm(q.Y - pos_.Y);
            const double len = std::hypot(dx, dy);
            e_mm_ += len * e_per_mm;
            const long long target = std::llround(e_mm_ * kEScale);
            guard(std::abs(q.X) < kMaxCoord && std::abs(q.Y) < kMaxCoord, "X/Y");
            put("G1 X");
            fixed(q.X, 3);
            put(" Y");
            fixed(q.Y, 3);
            e_word(target);
            feed(speed);
            buf_.push_back('\n');
            e_units_ = target;
            planner_.move(dx, dy, speed, st_.acceleration);
            printed(q, len, e_per_mm, ex.feature);
        }
        if (st_.wipe) remember_for_wipe(ex, shifted);
    }

    // Book-keeping of a printed move of `len` mm ending at q.
    void printed(const Point& q, double len, double e_per_mm, Feature feature) {
        stats_.extruded_volume_mm3 += len * e_per_mm * filament_area_;
        if (feature == Feature::Bridge) stats_.bridge_length_mm += len;
        bounds_.min_x = std::min(bounds_.min_x, to_mm(q.X));
        bounds_.max_x = std::max(bounds_.max_x, to_mm(q.X));
        bounds_.min_y = std::min(bounds_.min_y, to_mm(q.Y));
        bounds_.max_y = std::max(bounds_.max_y, to_mm(q.Y));
        bounds_.min_z = std::min(bounds_.min_z, to_mm(z_));
        bounds_.max_z = std::max(bounds_.max_z, to_mm(z_));
        pos_ = q;
    }

    // One G2/G3 for points first+1..arc.last. The planner times the chords it replaces (the
    // arc is within the tolerance of them); E follows the arc's own length.
    void arc_to(const std::vector<Point>& pts, size_t first, const Arc& arc, double speed,
                double e_per_mm, Feature feature) {
        const Point q = pts[arc.last];
        const double len = arc.length / kUnitsPerMm;
        e_mm_ += len * e_per_mm;
        const long long target = std::llround(e_mm_ * kEScale);
        guard(std::abs(q.X) < kMaxCoord && std::abs(q.Y) < kMaxCoord, "X/Y");
        put(arc.counter_clockwise ? "G3 X" : "G2 X");
        fixed(q.X, 3);
        put(" Y");
        fixed(q.Y, 3);
        put(" I");
        fixed(std::llround(arc.cx - double(pos_.X)), 3);
        put(" J");
        fixed(std::llround(arc.cy - double(pos_.Y)), 3);
        e_word(target);
        feed(speed);
        buf_.push_back('\n');
        e_units_ = target;
        for (size_t k = first; k < arc.last; ++k)
            planner_.move(to_mm(pts[k + 1].X - pts[k].X), to_mm(pts[k + 1].Y - pts[k].Y), speed,
                          st_.acceleration);
        for (size_t k = first + 1; k < arc.last; ++k) printed(pts[k], 0, e_per_mm, feature);
        printed(q, len, e_per_mm, feature);
        ++stats_.arcs;
        stats_.lines_saved_by_arcs += static_cast<long long>(arc.last - first) - 1;
    }

    // The last wipe_distance of the path just printed, walking back from its end.
    template <class Shift>
    void remember_for_wipe(const Extrusion& ex, Shift shifted) {
        wipe_path_.clear();
        wipe_length_ = 0;
        const size_t m = ex.points.size();
        const size_t n = m + (ex.closed ? 1 : 0);
        Point at = pos_;
        for (size_t k = n - 1; k-- > 0 && wipe_length_ < st_.wipe_distance;) {
            Point q = shifted(ex.points[k % m]);
            const double len = std::hypot(to_mm(q.X - at.X), to_mm(q.Y - at.Y));
            if (len <= 0) continue;
            if (wipe_length_ + len > st_.wipe_distance) {
                const double f = (st_.wipe_distance - wipe_length_) / len;
                q = Point(at.X + std::llround(f * double(q.X - at.X)),
                          at.Y + std::llround(f * double(q.Y - at.Y)));
                wipe_length_ = st_.wipe_distance;
            } else {
                wipe_length_ += len;
            }
            wipe_path_.push_back(q);
            at = q;
        }
    }

    // --- cooling, progress, labels.
    static int fan_byte(int percent) {
        return static_cast<int>(std::lround(std::clamp(percent, 0, 100) * 2.55));
    }

    // Klipper takes the acceleration from M204 S as the moves change (its limits are in
    // printer.cfg); the other firmwares were told M204 P and T once.
    void use_acceleration(double a) {
        if (st_.flavor != GcodeFlavor::Klipper || a == accel_) return;
        accel_ = a;
        line(fmt::format("M204 S{}", std::llround(a)));
    }

    // An M73 goes here, `elapsed_s` into the print (-1: at the end, the total).
    void mark_progress(double elapsed_s) {
        if (!st_.m73) return;
        marks_.push_back({written_ + static_cast<long long>(buf_.size()), elapsed_s});
    }

    // Everything a layer's paths change, to write the layer again slower.
    struct Snapshot {
        size_t text = 0;
        Point pos;
        Coord z = 0;
        double e_mm = 0;
        long long e_units = 0, feed = 0;
        bool retracted = false, first_travel = false, type_known = false, labelled = false;
        int fan = 0;
        Feature type = Feature::OuterWall;
        double width = 0, accel = 0, wipe_length = 0;
        MotionPlanner planner;
        PrintStats stats;
        Bounds bounds;
        Path wipe_path;
    };
    Snapshot save() const {
        return {buf_.size(),   pos_,        z_,        e_mm_,   e_units_,  feed_,  retracted_,
                first_travel_, type_known_, labelled_, fan_,    type_,     width_, accel_,
                wipe_length_,  planner_,    stats_,    bounds_, wipe_path_};
    }
    void restore(const Snapshot& k) {
        buf_.resize(k.text);
        pos_ = k.pos, z_ = k.z, e_mm_ = k.e_mm, e_units_ = k.e_units, feed_ = k.feed;
        retracted_ = k.retracted, first_travel_ = k.first_travel, type_known_ = k.type_known;
        labelled_ = k.labelled, fan_ = k.fan, type_ = k.type, width_ = k.width, accel_ = k.accel;
        wipe_length_ = k.wipe_length, planner_ = k.planner, stats_ = k.stats, bounds_ = k.bounds;
        wipe_path_ = k.wipe_path;
        comber_.reset();
    }

    // The layer's paths as the cooling wants them: written at full speed and timed; written
    // again slower while it is shorter than the minimum layer time, or with another fan.
    void print_layer_cooled(const LayerToolpaths& layer) {
        const Snapshot before = save();
        const double t0 = planner_.time();
        speed_factor_ = 1;
        layer_fan_ = layer_fan_percent(st_, layer.index, std::numeric_limits<double>::infinity());
        print_paths(layer);
        const double full = planner_.time() - t0;
        const int fan = layer_fan_percent(st_, layer.index, full);
        const bool slow = needs_slowdown(st_, full);
        if (!slow && fan == layer_fan_) return;
        const double target = st_.slowdown_below_layer_time;
        const double fastest = std::max({speed_of(Feature::OuterWall), speed_of(Feature::Cover),
                                         speed_of(Feature::CavityWall), speed_of(Feature::Bridge)});
        double factor = slow ? std::max(0.01, full / target) : 1.0;
        for (int pass = 0; pass < 8; ++pass) {
            restore(before);
            speed_factor_ = factor;
            layer_fan_ = fan;
            print_paths(layer);
            const double tried = planner_.time() - t0;
            // Done when long enough, or when every extrusion is down to the minimum speed.
            if (!slow || tried >= target * 0.999 ||
                slowed_speed(fastest, factor, st_.min_print_speed) <= st_.min_print_speed)
                break;
            factor = next_speed_factor(full, factor, tried, target);
        }
        speed_factor_ = 1;
    }

    void print_paths(const LayerToolpaths& layer) {
        comber_.reset();
        set_fan(fan_byte(layer_fan_));
        bool any = false;
        for (const Extrusion& ex : layer.extrusions) any = any || ex.points.size() >= 2;
        if (any) {
            for (const std::string& l : object_start(st_, object_, 0, !labelled_)) line(l);
            labelled_ = true;
        }
        static const Travel unplanned;
        for (size_t i = 0; i < layer.extrusions.size(); ++i)
            extrude(layer.extrusions[i], i < layer.travels.size() ? layer.travels[i] : unplanned);
        if (any)
            for (const std::string& l : object_end(st_, object_)) line(l);
    }

    const Settings& st_;
    Coord off_x_, off_y_;
    std::FILE* out_;
    std::string path_;
    std::string object_;               // the object's label
    std::vector<ProgressMark> marks_;  // where the M73 lines go
    long long written_ = 0;            // bytes of text flushed to out_
    double speed_factor_ = 1;          // cooling's slowdown of the layer being written
    int layer_fan_ = 0;                // percent, for the layer's ordinary extrusions
    double accel_ = -1;                // Klipper's M204 S in force
    bool labelled_ = false;            // M486 A named the object
    fmt::memory_buffer buf_;
    double filament_area_ = 1;
    long long retract_units_ = 0;

    Point pos_{0, 0};  // output coordinates, um; the start G-code is assumed to home
    Coord z_ = -1;     // unknown until the first Z move
    Coord layer_z_ = 0;
    int layer_ = 0;
    double e_mm_ = 0;        // filament fed for extrusion so far (retractions excluded)
    long long e_units_ = 0;  // the firmware's E position, in 10^-5 mm
    bool retracted_ = false;
    bool first_travel_ = true;
    long long feed_ = -1;
    int fan_ = -1;
    bool type_known_ = false;
    Feature type_ = Feature::OuterWall;
    double width_ = -1;
    MotionPlanner planner_;
    std::vector<Point> path_points_;  // the path being printed, shifted, reused
    PrintStats stats_;
    Bounds bounds_;
    const Paths* layer_comb_ = nullptr;  // the comb region of the layer being written
    std::unique_ptr<Comber> comber_;     // built from it on first use
    Path wipe_path_;                     // output coordinates, from the nozzle backwards
    double wipe_length_ = 0;             // mm
};

}  // namespace

namespace {

// A read-write temporary file next to `path` (same disk, and a bad directory fails early),
// unlinked at once so that it disappears with the process whatever happens. Its name is
// carve's short temporary pattern, not `path` plus a suffix: a target name near the file
// system's limit still works.
std::FILE* unlinked_file(const std::string& path, const char*) {
    return unlinked_temporary(path, path);
}

}  // namespace

struct GcodeWriter::Impl {
    std::string output_path;
    std::string written;  // where the complete file is (written_path())
    Settings settings;
    Coord off_x = 0, off_y = 0;
    int layer_count = 0;
    std::FILE* spill = nullptr;
    long long spill_end = 0;
    std::vector<long long> offsets, sizes;
    OutputGroup* group = nullptr;         // commit held back until the run's other outputs are done
    std::string object = "object";        // the object's label
    std::vector<std::string> thumbnails;  // the header's thumbnail blocks
    bool finished = false;
    std::mutex mutex;

    LayerToolpaths load(int index) {
        if (offsets[index] < 0) {
            LayerToolpaths empty;
            empty.index = index;
            empty.z = (index + 1) * settings.layer_height;
            return empty;
        }
        std::string blob(static_cast<size_t>(sizes[index]), '\0');
        if (fseeko(spill, offsets[index], SEEK_SET) != 0 ||
            std::fread(blob.data(), 1, blob.size(), spill) != blob.size())
            throw std::runtime_error("carve: cannot read back the layer spill file");
        return decode_layer(blob);
    }

    void run(Emitter& emitter) {
        emitter.start();
        for (int i = 0; i < layer_count; ++i) emitter.layer(load(i));
        emitter.end();
    }
};

GcodeWriter::GcodeWriter(std::string output_path, const Settings& settings, double offset_x_mm,
                         double offset_y_mm, int layer_count)
    : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.output_path = std::move(output_path);
    m.settings = settings;
    m.off_x = to_units(offset_x_mm);
    m.off_y = to_units(offset_y_mm);
    m.layer_count = std::max(0, layer_count);
    m.offsets.assign(m.layer_count, -1);
    m.sizes.assign(m.layer_count, 0);
    // The spill lives next to the output (same disk, and a bad directory fails early), unlinked
    // at once so that it disappears with the process whatever happens.
    m.spill = unlinked_file(m.output_path, ".spill-XXXXXX");
}

GcodeWriter::~GcodeWriter() {
    if (!impl_) return;
    if (impl_->spill) std::fclose(impl_->spill);
}

const std::string& GcodeWriter::written_path() const {
    return impl_->written;
}

void GcodeWriter::commit_with(OutputGroup& group) {
    impl_->group = &group;
}

void GcodeWriter::set_object_name(const std::string& name) {
    impl_->object = name.empty() ? "object" : name;
}

void GcodeWriter::set_thumbnails(std::vector<std::string> lines) {
    impl_->thumbnails = std::move(lines);
}

void GcodeWriter::add_layer(const LayerToolpaths& layer) {
    StageTimer timer(Stage::kGcode);
    const std::string blob = encode_layer(layer);
    std::lock_guard lock(impl_->mutex);
    Impl& m = *impl_;
    if (m.finished) throw std::logic_error("GcodeWriter::add_layer after finish()");
    if (layer.index < 0 || layer.index >= m.layer_count)
        throw std::out_of_range("GcodeWriter::add_layer: layer index out of range");
    if (fseeko(m.spill, m.spill_end, SEEK_SET) != 0 ||
        std::fwrite(blob.data(), 1, blob.size(), m.spill) != blob.size())
        io_error(std::strerror(errno), m.output_path + " (temporary layer file)");
    m.offsets[layer.index] = m.spill_end;
    m.sizes[layer.index] = static_cast<long long>(blob.size());
    m.spill_end += static_cast<long long>(blob.size());
}

PrintStats GcodeWriter::finish(const std::vector<std::string>& header_comments) {
    std::lock_guard lock(impl_->mutex);
    Impl& m = *impl_;
    if (m.finished) throw std::logic_error("GcodeWriter::finish called twice");
    if (std::fflush(m.spill) != 0) io_error(std::strerror(errno), m.output_path);

    // The body, measured as it is written.
    std::FILE* body = unlinked_file(m.output_path, ".body-XXXXXX");
    std::FILE* out = nullptr;
    try {
        std::setvbuf(body, nullptr, _IOFBF, 1 << 16);
        Emitter writer(m.settings, m.off_x, m.off_y, body, m.output_path, m.object);
        m.run(writer);
        writer.flush_all();
        if (std::fflush(body) != 0 || std::ferror(body) || std::fseek(body, 0, SEEK_SET) != 0)
            io_error(std::strerror(errno), m.output_path);
        const PrintStats s = writer.stats();
        const Bounds& b = writer.bounds();

        auto file = std::make_unique<AtomicFile>(m.output_path);
        out = file->stream();
        // PrusaSlicer's order: who made the file first (hosts look there), the thumbnails, then
        // Cura's summary lines and carve's own; the figures and the configuration close the
        // file, where Moonraker's PrusaSlicer parser reads them.
        std::vector<std::string> head{generated_by_line(), ";"};
        head.insert(head.end(), m.thumbnails.begin(), m.thumbnails.end());
        for (const std::string& c : header_comments)
            head.push_back(c.rfind(';', 0) == 0 ? c : "; " + c);
        head.push_back(fmt::format(";FLAVOR:{}", flavor_name(m.settings.flavor)));
        head.push_back(fmt::format(";TIME:{}", std::llround(s.estimated_print_time_s)));
        head.push_back(fmt::format(";Filament used: {:.5f}m", s.filament_length_mm / 1000.0));
        head.push_back(fmt::format(";Layer height: {}", m.settings.layer_height));
        if (!b.empty()) {
            head.push_back(fmt::format(";MINX:{:.3f}", b.min_x));
            head.push_back(fmt::format(";MINY:{:.3f}", b.min_y));
            head.push_back(fmt::format(";MINZ:{:.3f}", b.min_z));
            head.push_back(fmt::format(";MAXX:{:.3f}", b.max_x));
            head.push_back(fmt::format(";MAXY:{:.3f}", b.max_y));
            head.push_back(fmt::format(";MAXZ:{:.3f}", b.max_z));
        }
        head.push_back(fmt::format(";LAYER_COUNT:{}", m.layer_count));
        head.push_back(fmt::format("; estimated printing time (normal mode) = {}",
                                   format_duration(s.estimated_print_time_s)));
        if (!b.empty())
            for (const std::string& l :
                 object_definition(m.settings, m.object, b.min_x, b.min_y, b.max_x, b.max_y))
                head.push_back(l);
        head.push_back("");

        Emitter text(m.settings, m.off_x, m.off_y, out, m.output_path);
        text.comment_block(head);
        text.flush_all();
        copy_with_progress(body, out, writer.progress_marks(), s.estimated_print_time_s,
                           m.output_path);
        std::fclose(body);
        body = nullptr;
        std::vector<std::string> tail{""};
        for (const std::string& l : footer_figures(s, m.layer_count)) tail.push_back(l);
        tail.push_back("");
        for (const std::string& l : config_block(m.settings)) tail.push_back(l);
        text.comment_block(tail);
        text.flush_all();
        const PrintStats result = s;
        out = nullptr;
        file->close();
        if (m.group) {
            m.written = file->temporary();
            m.group->hold(std::move(file));
        } else {
            file->commit();
            m.written = m.output_path;
        }
        m.finished = true;
        std::fclose(m.spill);
        m.spill = nullptr;
        return result;
    } catch (...) {
        if (body) std::fclose(body);
        throw;  // the AtomicFile removes its temporary
    }
}

}  // namespace carve

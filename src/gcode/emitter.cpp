// The emitter's programme of the file: the start (machine limits, heating, the start G-code),
// each layer (its header comments, cooling's timing and second pass), the end; and the state it
// carries between moves: text buffered and flushed, fan, M73 marks (see emitter.hpp).
#include "gcode/emitter.hpp"

#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <numbers>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <utility>

#include "base/error.hpp"
#include "base/numbers.hpp"
#include "config/config_keys.hpp"
#include "gcode/cooling.hpp"
#include "gcode/labels.hpp"
#include "gcode/limits.hpp"
#include "gcode/placeholders.hpp"

namespace carve {

namespace {

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

void io_error(const std::string& what, const std::string& path) {
    throw OutputError("cannot write " + path + ": " + what);
}

Emitter::Emitter(const Settings& st, Coord off_x, Coord off_y, std::FILE* out, std::string path,
                 std::string object)
    : st_(st),
      off_x_(off_x),
      off_y_(off_y),
      out_(out),
      path_(std::move(path)),
      objects_{ObjectLabel{std::move(object)}},
      object_bounds_(1) {
    print_accel_ = commanded_acceleration(st, st.acceleration);
    travel_accel_ = commanded_acceleration(st, st.travel_acceleration);
    const double r = st.filament_diameter / 2;
    filament_area_ = std::numbers::pi * r * r;
    retract_units_ = std::llround(std::max(0.0, st.retract_length) * kEScale);
    z_offset_ = to_units(st.z_offset);
    carry_.layer = st.first_print_layer();
    carry_.objects_labelled.assign(1, 0);
    carry_.planner = estimate_planner(st);
}

void Emitter::start() {
    guard(st_.first_layer_bed_temperature >= 0 && st_.first_layer_bed_temperature <= 200 &&
              st_.first_layer_nozzle_temperature >= 0 &&
              st_.first_layer_nozzle_temperature <= 500 && st_.bed_temperature >= 0 &&
              st_.bed_temperature <= 200 && st_.nozzle_temperature >= 0 &&
              st_.nozzle_temperature <= 500,
          "S (temperature)");
    const std::string start_text = expand_custom_gcode(st_.start_gcode, st_).text;
    const bool klipper_macro = st_.flavor == GcodeFlavor::Klipper && st_.start_gcode.empty();
    for (const std::string& l : machine_limit_lines(st_, kZSpeed)) line(l);
    set_fan(0);
    // Like PrusaSlicer: heat and wait unless the start G-code waits for it itself, judged from
    // the text the printer will get (an M109 inside a false {if} heats nothing). A Klipper
    // macro's parameters count for nothing: the stock PRINT_START of Klipper's own configs
    // (config/kit-voron2-250mm.cfg) reads none. A macro that does read them finds both at
    // temperature; one that purges without heating too.
    const bool user_bed = waits_for(start_text, "M190");
    const bool user_nozzle = waits_for(start_text, "M109");
    if (!user_bed) line(fmt::format("M140 S{} ; bed", st_.first_layer_bed_temperature));
    if (!user_nozzle) line(fmt::format("M104 S{} ; nozzle", st_.first_layer_nozzle_temperature));
    if (!user_bed) line(fmt::format("M190 S{} ; wait for bed", st_.first_layer_bed_temperature));
    if (!user_nozzle)
        line(fmt::format("M109 S{} ; wait for nozzle", st_.first_layer_nozzle_temperature));
    // Viewers colour what follows as custom G-code, not as the first feature's.
    line(";TYPE:Custom");
    if (klipper_macro)
        line(fmt::format("PRINT_START BED_TEMP={} EXTRUDER_TEMP={}",
                         st_.first_layer_bed_temperature, st_.first_layer_nozzle_temperature));
    // Its Z moves are not held to the printer's height: they come before the print, from
    // where the printer homed (the default's G1 Z5 is a lift off the bed any printer makes).
    raw(start_text);
    // What a Klipper macro does is out of sight: the stock PRINT_START of kit-voron2-250mm.cfg
    // turns the hot end off ("M104 S0") while the bed heats, and klippy then stopped at the
    // first extrusion, "Extrude below minimum temp". So wait for the nozzle again after the
    // start G-code, where PrusaSlicer writes its M109.
    if (st_.flavor == GcodeFlavor::Klipper && !user_nozzle)
        line(fmt::format("M109 S{} ; wait for nozzle (a start macro may have turned it off)",
                         st_.first_layer_nozzle_temperature));
    custom(st_.start_filament_gcode);
    line("G21 ; millimetres");
    line("G90 ; absolute coordinates");
    line(st_.relative_e ? "M83 ; relative extrusion" : "M82 ; absolute extrusion");
    line("G92 E0");
    mark_progress(0, 0);
    close_section();
}

void Emitter::layer(const LayerToolpaths& layer) {
    carry_.layer = layer.index;
    carry_.layer_z = to_units(layer.z);
    // PrusaSlicer's profiles write ";BEFORE_LAYER_CHANGE" and the layer's height on the next
    // lines; Moonraker reads the object's height from them before anything else.
    if (st_.before_layer_gcode.find(";BEFORE_LAYER_CHANGE") == std::string::npos) {
        put("\n;BEFORE_LAYER_CHANGE\n;");
        fixed(carry_.layer_z, 3);
        buf_.push_back('\n');
    } else {
        buf_.push_back('\n');
    }
    custom(st_.before_layer_gcode);
    put(";LAYER_CHANGE\n;Z:");
    fixed(carry_.layer_z, 3);
    // The layer's height as PrusaSlicer states it: the model's first layer on a raft is a layer
    // height, the gap under it apart (`carve check` places the model at Z less it), though its
    // flow fills the gap too.
    put("\n;HEIGHT:");
    fixed(to_units(carry_.layer >= 0 ? st_.model_layer_mm(carry_.layer) : thickness()), 3);
    fmt::format_to(std::back_inserter(buf_), "\n;LAYER:{}\n", print_layer());
    custom(st_.layer_gcode);
    if (print_layer() == 1) {
        if (st_.nozzle_temperature != st_.first_layer_nozzle_temperature)
            line(fmt::format("M104 S{}", st_.nozzle_temperature));
        if (st_.bed_temperature != st_.first_layer_bed_temperature)
            line(fmt::format("M140 S{}", st_.bed_temperature));
    }
    // --pause-at: before the first layer whose top reaches the height (PrusaSlicer's colour
    // change at a layer), a test of this layer's index alone, so that every chunk agrees. The
    // heights are the model's: above a raft, from the model's bottom.
    const std::vector<double> none;  // a raft's layers: the heights are the model's
    for (double z : layer.index >= 0 ? st_.pause_at : none) {
        const double base = st_.model_base_mm();
        const double below = layer.index > 0 ? st_.layer_top_mm(layer.index - 1) - base : -1e9;
        if (z > below + 1e-9 && z <= st_.layer_top_mm(layer.index) - base + 1e-9) {
            line(fmt::format(";PAUSE_AT {}", plain_number(z)));
            pause();
            break;
        }
    }
    mark_progress(carry_.planner.time(), carry_.planner.time_stealth());
    carry_.type_known = false;
    layer_comb_ = &layer.comb_region;
    layer_thin_ = &layer.thin_region;
    // Built on first use and kept for the layer: the choice of its order and every cooling pass
    // plan on the same regions.
    comber_.reset();
    thin_.reset();
    last_entries_.clear();
    bool reverse = enter_reversed(layer);
    if (std::exchange(flip_, false) && layer.island_starts.size() >= 3 &&
        layer.island_starts.back() <= layer.extrusions.size())
        reverse = !reverse;
    if (reverse) {
        const LayerToolpaths reversed = with_islands_reversed(layer);
        print_layer_cooled(reversed);
    } else {
        print_layer_cooled(layer);
    }
    layer_comb_ = nullptr;
    layer_thin_ = nullptr;
    ++stats_.layers;
    // The next layer starts with a Z move, at rest: its time does not depend on this one's.
    carry_.planner.stop();
    reset_e();
    close_section();
    flush(false);
}

// Parks as the firmwares' own pause macros do (Klipper's sample PAUSE, Marlin's M600 with
// its park): retracted and lifted clear of the part before the command, so that the nozzle does
// not sit hot on the part's edge, oozing; then back down and unretracted as it was. Before
// anything is printed there is nothing to leave: the command alone.
void Emitter::pause() {
    const std::string command = !st_.pause_command.empty()           ? st_.pause_command
                                : st_.flavor == GcodeFlavor::Klipper ? "PAUSE"
                                                                     : "M600";
    if (carry_.first_travel || carry_.z < 0) {
        line(command);
        return;
    }
    const bool was_retracted = carry_.retracted;
    retract();
    const Coord at = carry_.z;
    const Coord top = to_units(st_.max_print_height) - z_offset_;
    const Coord lifted = std::max(at, std::min(at + to_units(kPauseLift), top));
    move_z(lifted, "the lift before a pause (--pause-at)");
    line(command);
    move_z(at, "the lift before a pause (--pause-at)");
    if (!was_retracted) unretract();
}

void Emitter::end() {
    if (!carry_.retracted && !carry_.first_travel) retract();
    mark_progress(-1, -1);  // 100 %: the total, known below
    custom(st_.end_filament_gcode);
    line(";TYPE:Custom");
    if (st_.flavor == GcodeFlavor::Klipper && st_.end_gcode.empty()) line("PRINT_END");
    try {
        const std::string end_text =
            expand_custom_gcode(st_.end_gcode, st_,
                                {{"max_layer_z", to_mm(carry_.layer_z)},
                                 {"layer_z", to_mm(carry_.layer_z)},
                                 {"layer_num", std::max(0, print_layer())}})
                .text;
        raw(end_text);
        scan_custom_z(end_text, "the end G-code's lift (end_gcode)");
    } catch (const InputError& e) {
        throw InputError(fmt::format("end_gcode: {}", e.what()));
    }
    carry_.planner.stop();
    close_section();
    run_stats_.estimated_print_time_s = time_base_;
    run_stats_.estimated_stealth_time_s = stealth_base_;
    run_stats_.filament_length_mm = run_stats_.extruded_volume_mm3 / filament_area_;
    run_stats_.filament_weight_g = run_stats_.extruded_volume_mm3 / 1000.0 * st_.filament_density;
    for (ProgressMark& m : marks_)
        if (m.elapsed_s < 0)
            m.elapsed_s = run_stats_.estimated_print_time_s,
            m.stealth_elapsed_s = run_stats_.estimated_stealth_time_s;
    flush(true);
}

void Emitter::close_section() {
    const double time = carry_.planner.take_done();
    sections_.push_back({stats_, time, carry_.planner.take_done_stealth()});
    add_stats(run_stats_, stats_);
    time_base_ += sections_.back().time_s;
    stealth_base_ += sections_.back().stealth_time_s;
    stats_ = {};
}

void Emitter::add_stats(PrintStats& to, const PrintStats& s) {
    to.extruded_volume_mm3 += s.extruded_volume_mm3;
    to.filament_length_mm += s.filament_length_mm;
    to.filament_weight_g += s.filament_weight_g;
    to.estimated_print_time_s += s.estimated_print_time_s;
    to.estimated_stealth_time_s += s.estimated_stealth_time_s;
    to.travel_length_mm += s.travel_length_mm;
    to.retractions += s.retractions;
    to.layers += s.layers;
    to.bridge_length_mm += s.bridge_length_mm;
    to.arcs += s.arcs;
    to.lines_saved_by_arcs += s.lines_saved_by_arcs;
}

// The firmware's E back to 0 after a layer, and carve's count of the filament fed with it (but
// for what is retracted): the next layer's E words are the same whatever came before. Bounded
// E values are also what PrusaSlicer's Marlin profiles keep with G92 E0 in their layer G-code
// (a float's precision in a long print).
void Emitter::reset_e() {
    const long long fed = std::llround(carry_.e_mm * kEScale);
    if (!st_.relative_e && carry_.e_units != 0) line("G92 E0");
    carry_.e_mm = double(fed - carry_.e_units) / kEScale;
    carry_.e_units = 0;
}

void Emitter::warm_up() {
    out_ = nullptr;
    carry_.first_travel = false;
    carry_.objects_labelled.assign(objects_.size(), 1);
}

void Emitter::begin_chunk(std::FILE* out) {
    out_ = out;
    buf_.clear();
    written_ = 0;
    marks_.clear();
    sections_.clear();
    run_stats_ = {};
    stats_ = {};
    time_base_ = 0;
    stealth_base_ = 0;
    bounds_ = {};
    object_bounds_.assign(objects_.size(), Bounds{});
    custom_bytes_ = 0;
}

void Emitter::adopt_totals(double time_s, double stealth_time_s, const PrintStats& stats) {
    time_base_ = time_s;
    stealth_base_ = stealth_time_s;
    run_stats_ = stats;
}

void Emitter::check_custom_bytes(size_t bytes) {
    if (bytes > kMaxCustomBytes)
        throw InputError(fmt::format(
            "the profile's custom G-code adds more than {} MB to the file (it is expanded on "
            "every layer); shorten it",
            kMaxCustomBytes >> 20));
}

void Emitter::scan_custom_z(const std::string& text, const char* what) {
    // From where carve's own moves left the nozzle (the bed before the first one).
    double z = carry_.z < 0 ? 0.0 : to_mm(carry_.z + z_offset_);
    bool relative = false;
    std::istringstream lines(text);
    for (std::string l; std::getline(lines, l);) {
        l.resize(std::min(l.find(';'), l.size()));
        std::istringstream words(l);
        std::string command, word;
        if (!(words >> command)) continue;
        for (char& c : command) c = char(std::toupper(static_cast<unsigned char>(c)));
        if (command == "G90") relative = false;
        if (command == "G91") relative = true;
        const bool move =
            command == "G0" || command == "G1" || command == "G00" || command == "G01";
        if (!move && command != "G92") continue;
        while (words >> word) {
            if (word.size() < 2 || (word[0] != 'Z' && word[0] != 'z')) continue;
            const std::optional<double> v = parse_decimal(word.substr(1));
            if (!v) continue;
            // G92 sets the position without moving.
            z = command == "G92" ? *v : relative ? z + *v : *v;
            if (move) bounds_.moved_to(z, what);
        }
    }
}

void Emitter::raw(const std::string& text) {
    if (text.empty()) return;
    put(text);
    if (text.back() != '\n') buf_.push_back('\n');
}

namespace {

// Whether a line of `g` is "G92 E0" (E0, E0.0, E00 ...), alone or followed by other words or a
// comment. Scanned by hand: std::regex recurses once per character and overflows the stack on a
// long run of blanks.
bool resets_e(std::string_view g) {
    auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
    for (size_t start = 0; start < g.size();) {
        size_t end = g.find('\n', start);
        if (end == std::string_view::npos) end = g.size();
        std::string_view line = g.substr(start, end - start);
        start = end + 1;
        size_t i = 0;
        while (i < line.size() && blank(line[i])) ++i;
        if (line.substr(i, 3) != "G92") continue;
        i += 3;
        const size_t gap = i;
        while (i < line.size() && blank(line[i])) ++i;
        if (i == gap || i >= line.size() || line[i] != 'E') continue;
        ++i;
        while (i < line.size() && line[i] == '0') ++i;
        if (i < line.size() && line[i] == '.') {
            ++i;
            while (i < line.size() && line[i] == '0') ++i;
        }
        if (i == line.size() || blank(line[i]) || line[i] == ';') return true;
    }
    return false;
}

}  // namespace

// A profile's filament or layer-change G-code, expanded for the layer being written. A
// "G92 E0" in it resets the firmware's E, as PrusaSlicer assumes.
void Emitter::custom(const std::string& text) {
    if (text.empty()) return;
    std::string g;
    try {
        g = expand_custom_gcode(text, st_,
                                {{"layer_num", std::max(0, print_layer())},
                                 {"layer_z", to_mm(carry_.layer_z)},
                                 {"max_layer_z", to_mm(carry_.layer_z)}})
                .text;
    } catch (const InputError& e) {
        // Named by its key: a figure beyond range is found only on the layer that computes it.
        std::string key = "custom G-code";
        for (const CustomGcodeKey& c : custom_gcode_keys())
            if (&(st_.*(c.text)) == &text) key = c.ini_key;
        throw InputError(fmt::format("{} (layer {}): {}", key, print_layer() + 1, e.what()));
    }
    // Bounded in total too: layer_gcode is expanded on every layer.
    custom_bytes_ += g.size();
    check_custom_bytes(custom_bytes_);
    raw(g);
    const char* key = "the profile's custom G-code";
    for (const CustomGcodeKey& c : custom_gcode_keys())
        if (&(st_.*(c.text)) == &text) key = c.ini_key;
    scan_custom_z(g, key);
    if (resets_e(g)) {
        carry_.e_mm -= double(carry_.e_units) / kEScale;
        carry_.e_units = 0;
    }
}

void Emitter::flush(bool force) {
    if (!force && buf_.size() < kFlushBytes) return;
    if (out_ && buf_.size() > 0 && std::fwrite(buf_.data(), 1, buf_.size(), out_) != buf_.size())
        io_error(std::strerror(errno), path_);
    written_ += static_cast<long long>(buf_.size());
    buf_.clear();
}

void Emitter::set_fan(int speed) {
    speed = std::clamp(speed, 0, 255);
    if (speed == carry_.fan) return;
    carry_.fan = speed;
    if (st_.flavor == GcodeFlavor::RepRap)
        line(fmt::format("M106 S{:.2f}", speed / 255.0));
    else if (speed == 0)
        line("M107");
    else
        line(fmt::format("M106 S{}", speed));
}

// An M73 goes here, `local_s` into the open section (-1: at the end, the total).
void Emitter::mark_progress(double local_s, double stealth_local_s) {
    if (!st_.m73) return;
    marks_.push_back({written_ + static_cast<long long>(buf_.size()),
                      local_s < 0 ? local_s : time_base_ + local_s, sections_.size(), local_s,
                      stealth_local_s < 0 ? stealth_local_s : stealth_base_ + stealth_local_s,
                      stealth_local_s});
}

Emitter::Snapshot Emitter::save() const {
    return {buf_.size(), carry_, object_bounds_, stats_, bounds_};
}

void Emitter::restore(const Snapshot& k) {
    buf_.resize(k.text);
    carry_ = k.carry;
    object_bounds_ = k.object_bounds, stats_ = k.stats, bounds_ = k.bounds;
}

// The layer's paths as the cooling wants them: written at full speed and timed; written
// again slower while it is shorter than the minimum layer time, or with another fan.
void Emitter::print_layer_cooled(const LayerToolpaths& layer) {
    const Snapshot before = save();
    const double t0 = carry_.planner.time_cooling();
    speed_factor_ = 1;
    layer_fan_ = layer_fan_percent(st_, layer.index, std::numeric_limits<double>::infinity());
    print_paths(layer);
    const double full = carry_.planner.time_cooling() - t0;
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
        const double tried = carry_.planner.time_cooling() - t0;
        // Done when long enough, or when every extrusion is down to the minimum speed.
        if (!slow || tried >= target * 0.999 ||
            slowed_speed(fastest, factor, st_.min_print_speed) <= st_.min_print_speed)
            break;
        factor = next_speed_factor(full, factor, tried, target);
    }
    speed_factor_ = 1;
}

void Emitter::set_objects(std::vector<ObjectLabel> objects) {
    objects_ = std::move(objects);
    carry_.objects_labelled.assign(objects_.size(), 0);
    object_bounds_.assign(objects_.size(), Bounds{});
}

// The object whose box holds p (model coordinates), else the one whose box is nearest.
int Emitter::object_of(const Point& p) const {
    if (objects_.size() == 1) return 0;
    const double x = to_mm(p.X), y = to_mm(p.Y);
    int best = 0;
    double best_d = std::numeric_limits<double>::max();
    for (size_t k = 0; k < objects_.size(); ++k) {
        const ObjectLabel& o = objects_[k];
        const double dx = std::max({o.min_x - x, 0.0, x - o.max_x});
        const double dy = std::max({o.min_y - y, 0.0, y - o.max_y});
        const double d = dx * dx + dy * dy;
        if (d < best_d) best_d = d, best = static_cast<int>(k);
    }
    return best;
}

void Emitter::print_paths(const LayerToolpaths& layer) {
    set_fan(fan_byte(layer_fan_));
    // Each object's run of extrusions between its own start and end lines: a host that cancels
    // one skips them, the travel into the object included. Skirt, brim and raft belong to no
    // object, as in PrusaSlicer's files: inside one's block they made its outline (Klipper's
    // EXCLUDE_OBJECT_DEFINE) take in the others, and cancelling it dropped the rest of them.
    object_ = -1;
    static const Travel unplanned;
    for (size_t i = 0; i < layer.extrusions.size(); ++i) {
        const Extrusion& ex = layer.extrusions[i];
        if (ex.points.size() >= 2) {
            const bool shared =
                layer.index < 0 || ex.feature == Feature::Skirt || ex.feature == Feature::Brim;
            const int k = shared ? -1 : object_of(ex.points.front());
            if (k != object_) {
                if (object_ >= 0)
                    for (const std::string& l : object_end(st_, objects_[object_].name)) line(l);
                if (k >= 0) {
                    for (const std::string& l :
                         object_start(st_, objects_[k].name, k, !carry_.objects_labelled[k]))
                        line(l);
                    carry_.objects_labelled[k] = 1;
                }
                object_ = k;
            }
        }
        extrude(ex, i < layer.travels.size() ? layer.travels[i] : unplanned);
    }
    if (object_ >= 0)
        for (const std::string& l : object_end(st_, objects_[object_].name)) line(l);
    object_ = -1;
}

}  // namespace carve

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
#include <cerrno>
#include <cmath>
#include <cstring>
#include <iterator>
#include <limits>
#include <mutex>
#include <numbers>
#include <stdexcept>
#include <string_view>

#include "base/error.hpp"
#include "gcode/placeholders.hpp"
#include "base/stage_timer.hpp"
#include "gcode/motion.hpp"
#include "gcode/spill.hpp"

namespace carve {

namespace {

constexpr double kZSpeed = 10.0;         // mm/s for layer changes and z-hops
constexpr long long kEScale = 100000;    // E is written with 5 decimals
constexpr size_t kFlushBytes = 1 << 20;  // text buffered before each fwrite

[[noreturn]] void io_error(const std::string& what, const std::string& path) {
    throw InputError("cannot write " + path + ": " + what);
}

std::string format_duration(double seconds) {
    long long s = std::llround(std::max(0.0, seconds));
    const long long d = s / 86400, h = s / 3600 % 24, m = s / 60 % 60, sec = s % 60;
    if (d > 0) return fmt::format("{}d {}h {}m {}s", d, h, m, sec);
    if (h > 0) return fmt::format("{}h {}m {}s", h, m, sec);
    if (m > 0) return fmt::format("{}m {}s", m, sec);
    return fmt::format("{}s", sec);
}

std::string_view flavor_name(GcodeFlavor f) {
    switch (f) {
        case GcodeFlavor::Marlin:
            return "Marlin";
        case GcodeFlavor::RepRap:
            return "RepRap";
        case GcodeFlavor::Klipper:
            return "Klipper";
    }
    return "Marlin";
}

// Every setting that shapes the output, as "; key = value" lines (PrusaSlicer's style).
std::vector<std::pair<std::string, std::string>> setting_lines(const Settings& s) {
    auto num = [](double v) { return fmt::format("{}", v); };
    auto one_line = [](std::string text) {
        for (char& c : text)
            if (c == '\n') c = '|';
        return text;
    };
    return {
        {"layer_height", num(s.layer_height)},
        {"nozzle_diameter", num(s.nozzle)},
        {"extrusion_width", num(s.nozzle)},
        {"max_overhang", num(s.max_overhang)},
        {"cavities", s.cavities_auto ? "auto" : std::to_string(s.cavities)},
        {"covers", std::to_string(s.covers)},
        {"shells", std::to_string(s.shells)},
        {"walls", s.walls == WallMode::Single ? "single" : "double"},
        {"restriction_factor", num(s.restriction_factor)},
        {"opening_factor", num(s.opening_factor)},
        {"wall_extension", num(s.wall_extension)},
        {"bridge_angle_step", num(s.bridge_angle_step)},
        {"prune_bridges", s.prune_bridges ? "1" : "0"},
        {"gcode_flavor", std::string(flavor_name(s.flavor))},
        {"printer_name", s.printer_name},
        {"filament_diameter", num(s.filament_diameter)},
        {"filament_density", num(s.filament_density)},
        {"bed_size", fmt::format("{}x{}", s.bed_x, s.bed_y)},
        {"use_relative_e_distances", s.relative_e ? "1" : "0"},
        {"first_layer_temperature", std::to_string(s.first_layer_nozzle_temperature)},
        {"temperature", std::to_string(s.nozzle_temperature)},
        {"first_layer_bed_temperature", std::to_string(s.first_layer_bed_temperature)},
        {"bed_temperature", std::to_string(s.bed_temperature)},
        {"perimeter_speed", num(s.perimeter_speed)},
        {"cavity_speed", num(s.cavity_speed)},
        {"cover_speed", num(s.cover_speed)},
        {"bridge_speed", num(s.bridge_speed)},
        {"travel_speed", num(s.travel_speed)},
        {"first_layer_speed", num(s.first_layer_speed)},
        {"max_print_speed", num(s.max_print_speed)},
        {"acceleration", num(s.acceleration)},
        {"travel_acceleration", num(s.travel_acceleration)},
        {"junction_deviation", num(kJunctionDeviationMm)},
        {"retract_length", num(s.retract_length)},
        {"retract_speed", num(s.retract_speed)},
        {"retract_before_travel", num(s.retract_min_travel)},
        {"retract_lift", num(s.z_hop)},
        {"bridge_flow_ratio", num(s.bridge_flow)},
        {"fan_speed", std::to_string(s.fan_speed)},
        {"bridge_fan_speed", std::to_string(s.bridge_fan_speed)},
        {"start_gcode", one_line(s.start_gcode)},
        {"end_gcode", one_line(s.end_gcode)},
    };
}

struct Bounds {
    double min_x = std::numeric_limits<double>::max(), min_y = min_x, min_z = min_x;
    double max_x = std::numeric_limits<double>::lowest(), max_y = max_x, max_z = max_x;
    bool empty() const { return min_x > max_x; }
};

// Turns layers into G-code text (or, without a file, only measures what it would print).
class Emitter {
  public:
    Emitter(const Settings& st, Coord off_x, Coord off_y, std::FILE* out, std::string path)
        : st_(st), off_x_(off_x), off_y_(off_y), out_(out), path_(std::move(path)) {
        const double r = st.filament_diameter / 2;
        filament_area_ = std::numbers::pi * r * r;
        retract_units_ = std::llround(std::max(0.0, st.retract_length) * kEScale);
    }

    void start() {
        const bool klipper_macro = st_.flavor == GcodeFlavor::Klipper && st_.start_gcode.empty();
        set_fan(0);
        if (klipper_macro) {
            line(fmt::format("PRINT_START BED_TEMP={} EXTRUDER_TEMP={}",
                             st_.first_layer_bed_temperature, st_.first_layer_nozzle_temperature));
        } else {
            // Like PrusaSlicer: heat unless the user's start G-code does it itself.
            const bool user_bed = st_.start_gcode.find("M190") != std::string::npos;
            const bool user_nozzle = st_.start_gcode.find("M109") != std::string::npos;
            if (!user_bed) line(fmt::format("M140 S{} ; bed", st_.first_layer_bed_temperature));
            if (!user_nozzle)
                line(fmt::format("M104 S{} ; nozzle", st_.first_layer_nozzle_temperature));
            if (!user_bed)
                line(fmt::format("M190 S{} ; wait for bed", st_.first_layer_bed_temperature));
            if (!user_nozzle)
                line(fmt::format("M109 S{} ; wait for nozzle", st_.first_layer_nozzle_temperature));
        }
        raw(expand_custom_gcode(st_.start_gcode, st_).text);
        line("G21 ; millimetres");
        line("G90 ; absolute coordinates");
        line(st_.relative_e ? "M83 ; relative extrusion" : "M82 ; absolute extrusion");
        line("G92 E0");
    }

    void layer(const LayerToolpaths& layer) {
        layer_ = layer.index;
        layer_z_ = to_units(layer.z);
        put("\n;LAYER_CHANGE\n;Z:");
        fixed(layer_z_, 3);
        put("\n;HEIGHT:");
        fixed(to_units(st_.layer_height), 3);
        fmt::format_to(std::back_inserter(buf_), "\n;LAYER:{}\n", layer.index);
        if (layer.index == 1) {
            if (st_.nozzle_temperature != st_.first_layer_nozzle_temperature)
                line(fmt::format("M104 S{}", st_.nozzle_temperature));
            if (st_.bed_temperature != st_.first_layer_bed_temperature)
                line(fmt::format("M140 S{}", st_.bed_temperature));
        }
        if (layer.index > 0) set_fan(st_.fan_speed);
        type_known_ = false;
        for (const Extrusion& e : layer.extrusions) extrude(e);
        ++stats_.layers;
        flush(false);
    }

    void end() {
        if (!retracted_ && !first_travel_) retract();
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
        flush(true);
    }

    void comment_block(const std::vector<std::string>& lines) {
        for (const std::string& l : lines) line(l);
    }

    void flush_all() { flush(true); }
    const PrintStats& stats() const { return stats_; }
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
        const long long f = std::llround(mm_per_s * 60.0);
        if (f == feed_) return;
        feed_ = f;
        fmt::format_to(std::back_inserter(buf_), " F{}", f);
    }

    void e_word(long long target) {
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
        planner_.dwell(st_.retract_length / st_.retract_speed);
    }

    void retract() {
        if (retract_units_ == 0 || retracted_) return;
        move_filament(e_units_ - retract_units_);
        retracted_ = true;
        ++stats_.retractions;
    }

    void unretract() {
        if (!retracted_) return;
        move_filament(std::llround(e_mm_ * kEScale));
        retracted_ = false;
    }

    void move_z(Coord z) {
        if (z == z_) return;
        put("G1 Z");
        fixed(z, 3);
        feed(kZSpeed);
        buf_.push_back('\n');
        const double dz = z_ < 0 ? to_mm(z) : std::abs(to_mm(z - z_));
        planner_.dwell(trapezoid_time(dz, 0, kZSpeed, 0, st_.travel_acceleration));
        z_ = z;
    }

    void travel_to(const Point& p) {
        const double d = std::hypot(to_mm(p.X - pos_.X), to_mm(p.Y - pos_.Y));
        if (p == pos_) {
            if (layer_z_ > z_) move_z(layer_z_);
            return;
        }
        const bool retract_now = !first_travel_ && retract_units_ > 0 && d > st_.retract_min_travel;
        if (retract_now) retract();
        const Coord hop = retract_now ? to_units(st_.z_hop) : 0;
        if (hop > 0)
            move_z(std::max(z_, layer_z_) + hop);
        else if (layer_z_ > z_)
            move_z(layer_z_);
        put("G0 X");
        fixed(p.X, 3);
        put(" Y");
        fixed(p.Y, 3);
        feed(st_.travel_speed);
        buf_.push_back('\n');
        planner_.move(to_mm(p.X - pos_.X), to_mm(p.Y - pos_.Y), st_.travel_speed,
                      st_.travel_acceleration);
        stats_.travel_length_mm += d;
        pos_ = p;
        if (z_ != layer_z_) move_z(layer_z_);
        first_travel_ = false;
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
        return v;
    }

    void extrude(const Extrusion& ex) {
        if (ex.points.size() < 2) return;
        auto shifted = [&](const Point& p) { return Point(p.X + off_x_, p.Y + off_y_); };
        travel_to(shifted(ex.points.front()));
        if (!type_known_ || ex.feature != type_) {
            type_known_ = true;
            type_ = ex.feature;
            fmt::format_to(std::back_inserter(buf_), ";TYPE:{}\n", feature_name(ex.feature));
        }
        const double width = st_.nozzle * ex.flow;
        if (width != width_) {
            width_ = width;
            fmt::format_to(std::back_inserter(buf_), ";WIDTH:{:.3f}\n", width);
        }
        if (layer_ > 0)
            set_fan(ex.feature == Feature::Bridge ? st_.bridge_fan_speed : st_.fan_speed);
        unretract();
        const double speed = speed_of(ex.feature);
        // Filament per mm of path: the line's cross-section (width x height) over the filament's.
        const double e_per_mm = st_.nozzle * st_.layer_height * ex.flow / filament_area_;
        const size_t n = ex.points.size() + (ex.closed ? 1 : 0);
        for (size_t i = 1; i < n; ++i) {
            const Point q = shifted(ex.points[i % ex.points.size()]);
            if (q == pos_) continue;
            const double dx = to_mm(q.X - pos_.X), dy = to_mm(q.Y - pos_.Y);
            const double len = std::hypot(dx, dy);
            e_mm_ += len * e_per_mm;
            const long long target = std::llround(e_mm_ * kEScale);
            put("G1 X");
            fixed(q.X, 3);
            put(" Y");
            fixed(q.Y, 3);
            e_word(target);
            feed(speed);
            buf_.push_back('\n');
            e_units_ = target;
            planner_.move(dx, dy, speed, st_.acceleration);
            stats_.extruded_volume_mm3 += len * e_per_mm * filament_area_;
            if (ex.feature == Feature::Bridge) stats_.bridge_length_mm += len;
            bounds_.min_x = std::min(bounds_.min_x, to_mm(q.X));
            bounds_.max_x = std::max(bounds_.max_x, to_mm(q.X));
            bounds_.min_y = std::min(bounds_.min_y, to_mm(q.Y));
            bounds_.max_y = std::max(bounds_.max_y, to_mm(q.Y));
            bounds_.min_z = std::min(bounds_.min_z, to_mm(z_));
            bounds_.max_z = std::max(bounds_.max_z, to_mm(z_));
            pos_ = q;
        }
    }

    const Settings& st_;
    Coord off_x_, off_y_;
    std::FILE* out_;
    std::string path_;
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
    PrintStats stats_;
    Bounds bounds_;
};

}  // namespace

namespace {

// A read-write temporary file next to `path` (same disk, and a bad directory fails early),
// unlinked at once so that it disappears with the process whatever happens.
std::FILE* unlinked_file(const std::string& path, const char* suffix) {
    std::string name = path + suffix;
    const int fd = mkstemp(name.data());
    if (fd < 0) io_error(std::strerror(errno), path);
    ::unlink(name.c_str());
    std::FILE* f = fdopen(fd, "w+b");
    if (!f) {
        ::close(fd);
        io_error(std::strerror(errno), path);
    }
    return f;
}

}  // namespace

struct GcodeWriter::Impl {
    std::string output_path;
    Settings settings;
    Coord off_x = 0, off_y = 0;
    int layer_count = 0;
    std::FILE* spill = nullptr;
    long long spill_end = 0;
    std::vector<long long> offsets, sizes;
    std::string temp_output;  // non-empty while a partial output exists
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
    if (!impl_->temp_output.empty()) ::unlink(impl_->temp_output.c_str());
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
        Emitter writer(m.settings, m.off_x, m.off_y, body, m.output_path);
        m.run(writer);
        writer.flush_all();
        if (std::fflush(body) != 0 || std::ferror(body) || std::fseek(body, 0, SEEK_SET) != 0)
            io_error(std::strerror(errno), m.output_path);
        const PrintStats s = writer.stats();
        const Bounds& b = writer.bounds();

        std::string name = m.output_path + ".tmp-XXXXXX";
        const int fd = mkstemp(name.data());
        if (fd < 0) io_error(std::strerror(errno), m.output_path);
        m.temp_output = name;
        ::fchmod(fd, 0644);  // mkstemp's 0600 would be a surprise on a shared printer host
        out = fdopen(fd, "wb");
        if (!out) {
            ::close(fd);
            io_error(std::strerror(errno), m.output_path);
        }
        std::setvbuf(out, nullptr, _IOFBF, 1 << 16);
        const double volume_cm3 = s.extruded_volume_mm3 / 1000.0;
        std::vector<std::string> head;
        head.push_back("; generated by carve");
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
        head.push_back(fmt::format("; filament used [mm] = {:.2f}", s.filament_length_mm));
        head.push_back(fmt::format("; filament used [cm3] = {:.2f}", volume_cm3));
        head.push_back(fmt::format("; filament used [g] = {:.2f}", s.filament_weight_g));
        head.push_back(fmt::format("; extruded volume [mm3] = {:.2f}", s.extruded_volume_mm3));
        head.push_back(fmt::format("; travel [mm] = {:.1f}", s.travel_length_mm));
        head.push_back(fmt::format("; retractions = {}", s.retractions));
        head.push_back(fmt::format("; bridges [mm] = {:.1f}", s.bridge_length_mm));
        head.push_back(";");
        for (const auto& [key, value] : setting_lines(m.settings))
            head.push_back(fmt::format("; {} = {}", key, value));
        head.push_back("");

        Emitter text(m.settings, m.off_x, m.off_y, out, m.output_path);
        text.comment_block(head);
        text.flush_all();
        std::vector<char> chunk(1 << 20);
        for (size_t n; (n = std::fread(chunk.data(), 1, chunk.size(), body)) > 0;)
            if (std::fwrite(chunk.data(), 1, n, out) != n)
                io_error(std::strerror(errno), m.output_path);
        if (std::ferror(body)) io_error(std::strerror(errno), m.output_path);
        std::fclose(body);
        body = nullptr;
        text.comment_block({"", "; end of print",
                            fmt::format("; estimated printing time (normal mode) = {}",
                                        format_duration(s.estimated_print_time_s)),
                            fmt::format("; filament used [mm] = {:.2f}", s.filament_length_mm),
                            fmt::format("; filament used [g] = {:.2f}", s.filament_weight_g)});
        text.flush_all();
        const PrintStats result = s;
        if (std::fflush(out) != 0 || std::ferror(out))
            io_error(std::strerror(errno), m.output_path);
        if (::fsync(fileno(out)) != 0 && errno != EINVAL)
            io_error(std::strerror(errno), m.output_path);
        const int closed = std::fclose(out);
        out = nullptr;
        if (closed != 0) io_error(std::strerror(errno), m.output_path);
        if (std::rename(m.temp_output.c_str(), m.output_path.c_str()) != 0)
            io_error(std::strerror(errno), m.output_path);
        m.temp_output.clear();
        m.finished = true;
        std::fclose(m.spill);
        m.spill = nullptr;
        return result;
    } catch (...) {
        if (body) std::fclose(body);
        if (out) std::fclose(out);
        if (!m.temp_output.empty()) ::unlink(m.temp_output.c_str());
        m.temp_output.clear();
        throw;
    }
}

}  // namespace carve

// Built-in printers and the PrusaSlicer .ini reader.
#include "config/profiles.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <sstream>

#include "base/error.hpp"
#include "base/numbers.hpp"
#include "config/setting_table.hpp"

namespace carve {

namespace {

struct Preset {
    const char* name;
    std::function<void(Settings&)> apply;
};

const std::vector<Preset>& presets() {
    static const std::vector<Preset> list = {
        {"generic", [](Settings&) {}},
        {"mk3s",
         [](Settings& s) {
             // As PrusaSlicer's own MK3S profile: firmware 3.13's checks, the intro line, and
             // the machine limits it writes (Prusa firmware corners by classic jerk).
             s.printer_name = "Prusa i3 MK3S-like";
             s.bed_x = 250, s.bed_y = 210;
             s.flavor = GcodeFlavor::Marlin;
             s.acceleration = 1000, s.travel_acceleration = 1250, s.retract_acceleration = 1250;
             s.max_acceleration_x = s.max_acceleration_y = 1000;
             s.max_acceleration_z = 200, s.max_acceleration_e = 5000;
             s.max_feedrate_x = s.max_feedrate_y = 200;
             s.max_feedrate_z = 12, s.max_feedrate_e = 120;
             s.max_jerk_x = s.max_jerk_y = 8, s.max_jerk_z = 0.4, s.max_jerk_e = 4.5;
             s.junction_deviation = 0;
             s.m73 = 1;
             s.retract_length = 0.8, s.retract_speed = 35;
             s.start_gcode =
                 "M862.3 P \"MK3S\" ; printer model check\n"
                 "M862.1 P[nozzle_diameter] ; nozzle diameter check\n"
                 "M115 U3.13.0 ; tell printer latest fw version\n"
                 "G90 ; use absolute coordinates\n"
                 "M83 ; extruder relative mode\n"
                 "M104 S[first_layer_temperature] ; set extruder temp\n"
                 "M140 S[first_layer_bed_temperature] ; set bed temp\n"
                 "M190 S[first_layer_bed_temperature] ; wait for bed temp\n"
                 "M109 S[first_layer_temperature] ; wait for extruder temp\n"
                 "G28 W ; home all without mesh bed level\n"
                 "G80 ; mesh bed levelling\n"
                 "G1 Z0.2 F720\n"
                 "G1 Y-3 F1000 ; go outside print area\n"
                 "G92 E0\n"
                 "G1 X60 E9 F1000 ; intro line\n"
                 "G1 X100 E12.5 F1000 ; intro line\n"
                 "G92 E0\n";
             // carve has retracted already, in either extrusion mode.
             s.end_gcode =
                 "G91\nG1 Z1 F720 ; lift the nozzle off the print\nG90\n"
                 "M104 S0 ; turn off temperature\n"
                 "M140 S0 ; turn off heatbed\n"
                 "M107 ; turn off fan\n"
                 "G1 X0 Y200 F3000 ; home X axis\n"
                 "M84 ; disable motors\n";
         }},
        {"ender3",
         [](Settings& s) {
             s.printer_name = "Creality Ender-3-like";
             s.bed_x = 220, s.bed_y = 220;
             s.flavor = GcodeFlavor::Marlin;
             s.acceleration = 500, s.travel_acceleration = 1000, s.retract_acceleration = 1000;
             s.max_acceleration_x = s.max_acceleration_y = 1000;
             s.max_acceleration_z = 100, s.max_acceleration_e = 5000;
             s.max_feedrate_x = s.max_feedrate_y = 500;
             s.max_feedrate_z = 10, s.max_feedrate_e = 60;
             s.max_jerk_x = s.max_jerk_y = 8, s.max_jerk_z = 0.4, s.max_jerk_e = 5;
             s.junction_deviation = 0;  // Creality's Marlin builds corner by classic jerk
             s.m73 = 1;
             s.retract_length = 5.0, s.retract_speed = 40;  // Bowden extruder
             s.travel_speed = 120;
             // Carve heats first (the text waits for nothing), then the purge line along the
             // left edge, in absolute extrusion.
             s.start_gcode =
                 "G90 ; use absolute coordinates\n"
                 "M82 ; absolute extrusion for the purge line\n"
                 "G28 ; home all axes\n"
                 "G92 E0\n"
                 "G1 Z2.0 F3000\n"
                 "G1 X0.1 Y20 Z0.3 F5000 ; to the start of the purge line\n"
                 "G1 X0.1 Y200 Z0.3 F1500 E15 ; first purge line\n"
                 "G1 X0.4 Y200 Z0.3 F5000\n"
                 "G1 X0.4 Y20 Z0.3 F1500 E30 ; second purge line\n"
                 "G92 E0\n"
                 "G1 Z2.0 F3000\n";
         }},
        {"klipper",
         [](Settings& s) {
             // The heating is PRINT_START's, with one spelling: carve writes no M104/M109 before
             // a start G-code that calls it. printer.cfg holds the limits, so none are written;
             // M204 S follows the moves.
             s.printer_name = "Klipper generic";
             s.bed_x = 300, s.bed_y = 300;
             s.flavor = GcodeFlavor::Klipper;
             s.acceleration = 3000, s.travel_acceleration = 5000;
             s.travel_speed = 250, s.max_print_speed = 200;
             s.retract_length = 0.8;
             s.start_gcode =
                 "PRINT_START BED_TEMP=[first_layer_bed_temperature] "
                 "EXTRUDER_TEMP=[first_layer_temperature]\n";
             s.end_gcode = "PRINT_END\n";
         }},
    };
    return list;
}

std::string trim(std::string s) {
    const char* ws = " \t\r\n";
    s.erase(0, s.find_first_not_of(ws));
    s.erase(s.find_last_not_of(ws) + 1);
    return s;
}

// A plain decimal number: std::stod would also read "0x0" (a bed_shape point) as hexadecimal.
std::optional<double> decimal(const std::string& v) {
    return parse_decimal(v);
}

double number(const std::string& key, const std::string& value) {
    // PrusaSlicer stores per-extruder values as comma lists; the first extruder is ours.
    const std::string v = trim(value.substr(0, value.find(',')));
    if (const std::optional<double> d = decimal(v)) return *d;
    throw InputError(fmt::format("profile key '{}': '{}' is not a number", key, value));
}

// A whole number from 0 to 50 (layers, perimeters).
int count(const std::string& key, const std::string& value) {
    const double d = number(key, value);
    if (d < 0 || d > 50 || d != std::floor(d))
        throw InputError(
            fmt::format("profile key '{}': '{}' is not a whole number from 0 to 50", key, value));
    return static_cast<int>(d);
}

std::string unescape(const std::string& v) {
    std::string out;
    for (size_t i = 0; i < v.size(); ++i) {
        if (v[i] == '\\' && i + 1 < v.size()) {
            char c = v[++i];
            out += c == 'n' ? '\n' : c == 't' ? '\t' : c;
        } else {
            out += v[i];
        }
    }
    if (!out.empty() && out.back() != '\n') out += '\n';
    return out;
}

}  // namespace

std::string printer_preset_names() {
    std::string out;
    for (const Preset& p : presets()) out += (out.empty() ? "" : ", ") + std::string(p.name);
    return out;
}

void apply_printer_preset(const std::string& name, Settings& settings) {
    for (const Preset& p : presets())
        if (name == p.name) {
            settings.printer_name = name;
            p.apply(settings);
            return;
        }
    throw InputError(
        fmt::format("unknown printer '{}'; choose one of: {}", name, printer_preset_names()));
}

std::vector<std::string> load_prusa_profile(const std::string& path, Settings& s) {
    std::ifstream in(path);
    if (!in) throw InputError(fmt::format("{}: cannot open the profile", path));
    // A real profile is tens of kilobytes (a bundle of every vendor printer a few MB); more is
    // not a profile, and every key is held in memory for the placeholders.
    constexpr std::streamoff kMaxProfileBytes = 16 << 20;
    in.seekg(0, std::ios::end);
    if (in.tellg() > kMaxProfileBytes)
        throw InputError(fmt::format("{}: larger than 16 MB, not a printer profile", path));
    in.seekg(0, std::ios::beg);
    return read_prusa_profile(in, path, s);
}

std::vector<std::string> read_prusa_profile(std::istream& in, const std::string& path,
                                            Settings& s) {
    using Setter = std::function<void(const std::string&, const std::string&)>;
    int top_bottom[2] = {0, 0};
    const std::map<std::string, Setter> keys = {
        {"bed_shape",
         [&](const std::string& k, const std::string& v) {
             // "0x0,250x0,250x210,0x210": the bed is the bounding box of the points.
             double min_x = 1e9, min_y = 1e9, max_x = -1e9, max_y = -1e9;
             std::stringstream ss(v);
             std::string pt;
             int n = 0;
             while (std::getline(ss, pt, ',')) {
                 const std::string p = trim(pt);
                 const size_t cross = p.find('x');
                 const std::optional<double> x = decimal(p.substr(0, cross));
                 const std::optional<double> y =
                     cross == std::string::npos ? std::nullopt : decimal(p.substr(cross + 1));
                 if (!x || !y)
                     throw InputError(fmt::format("profile key '{}': bad point '{}'", k, pt));
                 min_x = std::min(min_x, *x), max_x = std::max(max_x, *x);
                 min_y = std::min(min_y, *y), max_y = std::max(max_y, *y);
                 ++n;
             }
             if (n < 3 || max_x <= min_x || max_y <= min_y)
                 throw InputError(fmt::format("profile key '{}': '{}' is not a bed outline", k, v));
             s.bed_x = max_x - min_x, s.bed_y = max_y - min_y;
         }},
        {"start_gcode", [&](auto&, auto& v) { s.start_gcode = unescape(v); }},
        {"thumbnails",
         [&](auto& k, auto& v) {
             s.thumbnails = parse_thumbnail_sizes(v, fmt::format("{}: profile key '{}'", path, k));
         }},
        {"end_gcode", [&](auto&, auto& v) { s.end_gcode = unescape(v); }},
        // Solid layers and perimeters are carve's covers and shells: a profile's own choice
        // holds unless --preset or --covers/--shells say otherwise.
        {"top_solid_layers",
         [&](auto& k, auto& v) {
             s.covers = std::max(top_bottom[0] = count(k, v), top_bottom[1]);
         }},
        {"bottom_solid_layers",
         [&](auto& k, auto& v) {
             s.covers = std::max(top_bottom[0], top_bottom[1] = count(k, v));
         }},
        {"perimeters",
         [&](auto& k, auto& v) {
             // The outer wall and up to 20 shells (the range of --shells).
             const int n = count(k, v);
             if (n > 21)
                 throw InputError(fmt::format(
                     "profile key '{}': '{}' is out of range; expected from 0 to 21", k, v));
             s.shells = std::max(0, n - 1);
         }},
        {"use_relative_e_distances",
         [&](auto& k, auto& v) {
             const std::string b = trim(v);
             if (b != "0" && b != "1")
                 throw InputError(fmt::format("profile key '{}': '{}' is not 0 or 1", k, v));
             s.relative_e = b == "1";
         }},
        {"gcode_flavor",
         [&](auto& k, auto& v) {
             const std::string f = trim(v);
             if (f == "klipper")
                 s.flavor = GcodeFlavor::Klipper;
             else if (f == "reprap" || f == "reprapfirmware")
                 s.flavor = GcodeFlavor::RepRap;
             else if (f.rfind("marlin", 0) == 0)
                 s.flavor = GcodeFlavor::Marlin;
             else
                 throw InputError(fmt::format("profile key '{}': unsupported flavour '{}'", k, f));
         }},
    };

    std::vector<std::string> notes;
    int ignored = 0;
    std::string line;
    int line_no = 0;
    while (std::getline(in, line)) {
        ++line_no;
        line = trim(line);
        if (line.empty() || line[0] == '#' || line[0] == ';' || line[0] == '[') continue;
        const size_t eq = line.find('=');
        if (eq == std::string::npos)
            throw InputError(fmt::format("{}:{}: expected 'key = value'", path, line_no));
        const std::string key = trim(line.substr(0, eq));
        const std::string value = trim(line.substr(eq + 1));
        // Kept raw for the placeholders of the profile's custom G-code ([printer_model], ...).
        s.profile_values[key] = value;
        // Numeric keys come from the settings table, with its ranges. PrusaSlicer stores
        // per-extruder values as comma lists; the first extruder is ours.
        if (const SettingSpec* spec = find_setting_by_ini_key(key)) {
            const std::string v = trim(value.substr(0, value.find(',')));
            if (spec->profile_skips_percent && v.find('%') != std::string::npos) continue;
            spec->set(s, v, fmt::format("{}:{}: profile key '{}'", path, line_no, key));
            continue;
        }
        auto it = keys.find(key);
        if (it == keys.end()) {
            ++ignored;
            continue;
        }
        it->second(key, value);
    }
    if (ignored > 0)
        notes.push_back(fmt::format("{}: ignored {} keys that carve does not use", path, ignored));
    return notes;
}

}  // namespace carve

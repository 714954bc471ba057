// Built-in printers and the PrusaSlicer .ini reader.
#include "config/profiles.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string_view>

#include "base/error.hpp"
#include "base/numbers.hpp"
#include "config/bundle.hpp"
#include "config/config_keys.hpp"
#include "config/setting_table.hpp"

namespace carve {

namespace {

struct Preset {
    const char* name;
    std::function<void(Settings&)> apply;
};

const std::vector<Preset>& presets() {
    static const std::vector<Preset> list = {
        // The defaults: a bed of 250 x 210 and 210 mm of height, an MK3's.
        {"generic", [](Settings&) {}},
        {"mk3s",
         [](Settings& s) {
             // As PrusaSlicer's own MK3S profile: firmware 3.13's checks, the intro line, and
             // the machine limits it writes (Prusa firmware corners by classic jerk).
             s.printer_name = "Prusa i3 MK3S-like";
             s.bed_x = 250, s.bed_y = 210, s.max_print_height = 210;
             s.flavor = GcodeFlavor::Marlin;
             s.acceleration = 1000, s.travel_acceleration = 1250, s.retract_acceleration = 1250;
             s.max_acceleration_x = s.max_acceleration_y = 1000;
             s.max_acceleration_z = 200, s.max_acceleration_e = 5000;
             s.max_feedrate_x = s.max_feedrate_y = 200;
             s.max_feedrate_z = 12, s.max_feedrate_e = 120;
             s.max_jerk_x = s.max_jerk_y = 8, s.max_jerk_z = 0.4, s.max_jerk_e = 4.5;
             s.junction_deviation = 0;
             s.m73 = 1;
             s.silent_mode = 1;
             // PrusaSlicer's MK3 profile's stealth limits (machine_max_acceleration_x = 1000,960,
             // machine_max_feedrate_x = 200,100; the other axes the same in both modes).
             s.stealth_max_acceleration = 960, s.stealth_max_feedrate = 100;
             s.printer_model = "MK3S";
             s.thumbnails = {{16, 16}, {220, 124}};  // PrusaSlicer's MK3S profile's
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
             // carve has retracted already, in either extrusion mode. The lift is
             // PrusaSlicer's: 49 mm above the part, within the printer's height (the offset
             // inside the min(), so that it stays within it too).
             s.end_gcode =
                 "{if max_layer_z < max_print_height}G1 Z{min(z_offset+max_layer_z+49, "
                 "max_print_height)} F720 ; move the print head up{endif}\n"
                 "M104 S0 ; turn off temperature\n"
                 "M140 S0 ; turn off heatbed\n"
                 "M107 ; turn off fan\n"
                 "G1 X0 Y200 F3000 ; home X axis\n"
                 "M84 ; disable motors\n";
         }},
        {"ender3",
         [](Settings& s) {
             s.printer_name = "Creality Ender-3-like";
             s.bed_x = 220, s.bed_y = 220, s.max_print_height = 250;
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
             // Klipper's own config/kit-voron2-250mm.cfg (Klipper 84104bbb): a 250 x 250 bed,
             // 250 mm of Z, max_velocity 350, max_accel 3000, max_z_velocity 50, max_z_accel 350.
             // Klipper takes M204 S as it comes, above max_accel too, so carve holds its
             // accelerations to machine_max_acceleration_x/y (that max_accel) and states them in
             // the configuration block. PRINT_START gets the temperatures, but carve heats and
             // waits before it too: the stock macros read no parameters. Thumbnails as Mainsail
             // and Fluidd show them (their documentation's sizes).
             s.printer_name = "Voron 2 250 (Klipper config/kit-voron2-250mm.cfg)";
             s.bed_x = 250, s.bed_y = 250, s.max_print_height = 250;
             s.thumbnails = {{32, 32}, {400, 300}};
             s.flavor = GcodeFlavor::Klipper;
             s.max_acceleration_x = s.max_acceleration_y = 3000;
             s.max_acceleration_z = 350;
             s.max_feedrate_x = s.max_feedrate_y = 350;
             s.max_feedrate_z = 50;
             s.acceleration = 3000, s.travel_acceleration = 3000;
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

// A plain decimal number: std::stod would also read "0x0" (a bed_shape point) as hexadecimal.
std::optional<double> decimal(const std::string& v) {
    return parse_decimal(v);
}

double number(const std::string& key, const std::string& value) {
    // PrusaSlicer stores per-extruder values as comma lists; the first extruder is ours.
    const std::string v = trim_whitespace(value.substr(0, value.find(',')));
    if (const std::optional<double> d = decimal(v)) return *d;
    throw InputError(fmt::format("profile key '{}': '{}' is not a number", key, value));
}

// The first of a per-extruder list ("PLA;PETG" or "PLA,PETG"), unquoted, for the configuration
// block: one line, no control characters.
std::string one_line(const std::string& value) {
    std::string out;
    for (char c : value)
        if (static_cast<unsigned char>(c) >= 0x20 && c != 0x7f) out += c;
    return trim_whitespace(out.substr(0, std::min<size_t>(out.size(), 200)));
}
std::string first_item(const std::string& value) {
    std::string v = one_line(value);
    v = trim_whitespace(v.substr(0, v.find_first_of(",;")));
    if (v.size() >= 2 && v.front() == '"' && v.back() == '"') v = v.substr(1, v.size() - 2);
    return v;
}

// A whole number from 0 to 50 (layers, perimeters).
int count(const std::string& key, const std::string& value) {
    const double d = number(key, value);
    if (d < 0 || d > 50 || d != std::floor(d))
        throw InputError(
            fmt::format("profile key '{}': '{}' is not a whole number from 0 to 50", key, value));
    return static_cast<int>(d);
}

// Keys of PrusaSlicer 2.5 that change what is printed. Those carve does not read are named in
// the loading note when the selected presets set them to something other than off or zero;
// the rest of a profile (names, notes, compatibility rules, multi-material) does not change
// carve's print.
const char* const kPrintKeys[] = {"bridge_fan_speed",
                                  "cooling",
                                  "disable_fan_first_layers",
                                  "fan_always_on",
                                  "fan_below_layer_time",
                                  "full_fan_speed_layer",
                                  "max_fan_speed",
                                  "min_fan_speed",
                                  "min_print_speed",
                                  "slowdown_below_layer_time",
                                  "machine_limits_usage",
                                  "machine_max_acceleration_e",
                                  "machine_max_acceleration_x",
                                  "machine_max_acceleration_y",
                                  "machine_max_acceleration_z",
                                  "machine_max_acceleration_retracting",
                                  "machine_max_feedrate_e",
                                  "machine_max_feedrate_x",
                                  "machine_max_feedrate_y",
                                  "machine_max_feedrate_z",
                                  "machine_max_jerk_e",
                                  "machine_max_jerk_x",
                                  "machine_max_jerk_y",
                                  "machine_max_jerk_z",
                                  "machine_min_extruding_rate",
                                  "machine_min_travel_rate",
                                  "default_acceleration",
                                  "perimeter_acceleration",
                                  "infill_acceleration",
                                  "bridge_acceleration",
                                  "first_layer_acceleration",
                                  "infill_speed",
                                  "top_solid_infill_speed",
                                  "gap_fill_speed",
                                  "small_perimeter_speed",
                                  "travel_speed_z",
                                  "deretract_speed",
                                  "bridge_flow_ratio",
                                  "infill_extrusion_width",
                                  "solid_infill_extrusion_width",
                                  "top_infill_extrusion_width",
                                  "retract_restart_extra",
                                  "retract_layer_change",
                                  "retract_before_wipe",
                                  "support_material",
                                  "external_perimeters_first",
                                  "spiral_vase",
                                  "fill_density",
                                  "ironing",
                                  "thumbnails"};

// Off: every per-extruder item is zero, empty or nil (PrusaSlicer's "use the printer's").
bool set_to_something(const std::string& value) {
    std::stringstream ss(first_quoted(value));
    std::string item;
    while (std::getline(ss, item, ',')) {
        item = trim_whitespace(item);
        if (item != "0" && item != "0%" && item != "" && item != "nil" && item != "\"\"")
            return true;
    }
    return false;
}

// A profile that states the X/Y limits states the stealth mode's with them, or has none (its
// limits are then the normal ones): PrusaSlicer's "1000,960" is normal,stealth. X and Y are one
// limit for carve's stealth estimate, the lower.
void apply_stealth_limits(const std::map<std::string, IniValue>& values, Settings& s) {
    auto one = [&](const std::string& kind, const char* option) {
        std::optional<double> lowest;
        bool stated = false;
        for (const char* axis : {"_x", "_y"}) {
            const auto it = values.find("machine_max_" + kind + axis);
            if (it == values.end()) continue;
            stated = true;
            const std::string& value = it->second.value;
            const size_t comma = value.find(',');
            if (comma == std::string::npos) continue;
            const double v = number(it->first, value.substr(comma + 1));
            lowest = std::min(lowest.value_or(v), v);
        }
        if (!stated) return;
        for (const SettingSpec& spec : setting_table())
            if (std::string_view(spec.option) == option)
                spec.set(s, plain_number(lowest.value_or(0)),
                         fmt::format("profile key 'machine_max_{}_x/y' (stealth)", kind));
    };
    one("acceleration", "stealth-max-acceleration");
    one("feedrate", "stealth-max-feedrate");
}

// An extrusion width: mm, or a percentage of `nozzle` (the nozzle, PrusaSlicer 2.4 on; for
// first_layer_extrusion_width the first layer's height, its ratio_over); 0 = automatic.
double width_value(const std::string& key, const std::string& value, double nozzle) {
    std::string v = trim_whitespace(value.substr(0, value.find(',')));
    const bool percent = !v.empty() && v.back() == '%';
    if (percent) v.pop_back();
    const double d = number(key, v);
    const double mm = percent ? d * nozzle / 100 : d;
    if (!(mm == 0 || (mm >= 0.05 && mm <= 3.0)))
        throw InputError(fmt::format(
            "profile key '{}': '{}' is out of range; expected 0 (automatic) or from 0.05 to 3 mm",
            key, value));
    return mm;
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

std::vector<std::string> load_prusa_profile(const std::string& path, Settings& s,
                                            const ProfileOptions& options) {
    std::ifstream in(path);
    if (!in) throw InputError(fmt::format("{}: cannot open the profile", path));
    // A real profile is tens of kilobytes (a bundle of every vendor printer a few MB); more is
    // not a profile, and every key is held in memory for the placeholders.
    // Read by blocks rather than measured by seeking: a pipe (--load /dev/stdin) cannot seek,
    // and a failed seek left the stream failed, so its profile was silently empty.
    constexpr size_t kMaxProfileBytes = 16 << 20;
    std::string text;
    char block[1 << 16];
    while (in.read(block, sizeof block) || in.gcount() > 0) {
        text.append(block, size_t(in.gcount()));
        if (text.size() > kMaxProfileBytes)
            throw InputError(fmt::format("{}: larger than 16 MB, not a printer profile", path));
    }
    if (in.bad()) throw InputError(fmt::format("{}: cannot read the profile", path));
    std::istringstream whole(std::move(text));
    return read_prusa_profile(whole, path, s, options);
}

namespace {

// The keys of the line widths, read once the nozzle is known.
const std::set<std::string>& width_keys() {
    static const std::set<std::string> keys = {"extrusion_width",
                                               "perimeter_extrusion_width",
                                               "external_perimeter_extrusion_width",
                                               "first_layer_extrusion_width",
                                               "min_bead_width",
                                               "min_feature_size"};
    return keys;
}

// One profile read into settings, in read_prusa_profile()'s phases: what is read before it is
// applied, and where each key came from for the messages.
class ProfileReading {
  public:
    ProfileReading(ResolvedProfile& profile, const std::string& path, Settings& s)
        : profile_(profile), values_(profile.values), path_(path), s_(s) {}

    // A filament may override the printer's retraction (filament_retract_length, ...; "nil" =
    // the printer's own).
    void take_filament_overrides() {
        for (const char* k : {"retract_length", "retract_lift", "retract_speed",
                              "retract_before_travel", "wipe", "retract_layer_change",
                              "retract_restart_extra", "retract_before_wipe", "deretract_speed"}) {
            auto f = values_.find(std::string("filament_") + k);
            if (f != values_.end() &&
                trim_whitespace(f->second.value.substr(0, f->second.value.find(','))) != "nil")
                values_[k] = f->second;
        }
    }

    // What PrusaSlicer's own export says of the presets it was made from: the placeholders of
    // the vendors' G-code test them ({if print_settings_id=~/.*QUALITY @MK3.*/}).
    void add_bundle_ids() {
        if (!profile_.bundle) return;
        auto id = [&](const char* key, const std::string& name, bool quoted) {
            if (!name.empty())
                values_[key] = IniValue{quoted ? "\"" + name + "\"" : name, 0, "", ""};
        };
        id("printer_settings_id", profile_.printer, false);
        id("filament_settings_id", profile_.filament, true);
        id("print_settings_id", profile_.print, false);
    }

    // Every key but the widths: the table's, the custom G-code, and the few read here.
    void read_keys() {
        Settings& s = s_;
        const std::set<std::string>& widths = width_keys();
        using Setter = std::function<void(const std::string&, const std::string&)>;
        const std::map<std::string, Setter> keys = {
            // Solid layers and perimeters would be carve's covers and shells; read (and checked)
            // here, applied below only with --profile-shells.
            {"top_solid_layers", [&](auto& k, auto& v) { solid_[0] = count(k, v); }},
            // What the configuration block tells hosts: the first extruder's, as the profile spells
            // it (a bundle's filament_settings_id is quoted, as PrusaSlicer's export has it).
            {"filament_type", [&](auto&, auto& v) { s.filament_type = first_item(v); }},
            {"filament_colour", [&](auto&, auto& v) { s.filament_colour = first_item(v); }},
            {"filament_settings_id", [&](auto&, auto& v) { s.filament_settings_id = one_line(v); }},
            {"printer_model", [&](auto&, auto& v) { s.printer_model = one_line(v); }},
            {"bottom_solid_layers", [&](auto& k, auto& v) { solid_[1] = count(k, v); }},
            // The filament's cap on the flow, beside the print's max_volumetric_speed: the lower
            // of the two that are set holds, as in PrusaSlicer.
            {"filament_max_volumetric_speed",
             [&](auto& k, auto& v) {
                 filament_cap_ = number(k, v);
                 if (!(filament_cap_ >= 0 && filament_cap_ <= 1000))
                     throw InputError(fmt::format(
                         "profile key '{}': '{}' is out of range; expected from 0 to 1000 mm^3/s",
                         k, v));
             }},
            {"perimeters",
             [&](auto& k, auto& v) {
                 // The outer wall and up to 20 shells (the range of --shells).
                 perimeters_ = count(k, v);
                 if (perimeters_ > 21)
                     throw InputError(fmt::format(
                         "profile key '{}': '{}' is out of range; expected from 0 to 21", k, v));
             }},
        };
        for (const auto& [key, v] : values_) {
            const std::string& value = v.value;
            // Kept raw for the placeholders of the profile's custom G-code ([printer_model], ...).
            s.profile_values[key] = value;
            try {
                // The table's keys, with its ranges and PrusaSlicer's spellings. PrusaSlicer stores
                // per-extruder values as comma lists; the first extruder is ours.
                if (const SettingSpec* spec = find_setting_by_ini_key(key)) {
                    // A word or a list (bed_shape, thumbnails) is the whole value.
                    const bool whole = spec->text() || spec->prusa;
                    const std::string first =
                        trim_whitespace(whole ? value : value.substr(0, value.find(',')));
                    if (spec->profile_skips_percent && first.find('%') != std::string::npos) {
                        ignored_.push_back(fmt::format("{} ({})", key, first));
                        continue;
                    }
                    spec->set_prusa(s, first, where(key, v));
                    continue;
                }
                if (const auto it = std::find_if(
                        custom_gcode_keys().begin(), custom_gcode_keys().end(),
                        [&k = key](const CustomGcodeKey& c) { return k == c.ini_key; });
                    it != custom_gcode_keys().end()) {
                    s.*(it->text) =
                        unescape_profile_text(it->string_list ? first_quoted(value) : value);
                    continue;
                }
                if (auto it = keys.find(key); it != keys.end()) {
                    it->second(key, value);
                    continue;
                }
            } catch (const InputError& e) {
                throw relabel(key, v, e);
            }
            if (widths.count(key)) continue;  // below, once the nozzle is known
            if (std::find(std::begin(kPrintKeys), std::end(kPrintKeys), key) !=
                    std::end(kPrintKeys) &&
                set_to_something(value))
                ignored_.push_back(key);
        }
    }

    // One line width for every wall, the first layer's and the thin walls' widths, the flow
    // cap, and the corners.
    void apply_widths() {
        Settings& s = s_;
        const std::set<std::string>& widths = width_keys();
        // One line width for every wall: carve's geometry (the cavity walls' spacing, the covers'
        // lines) is built on it. The inner perimeters' width is the bulk of a carved print.
        std::map<std::string, double> width;
        for (const std::string& key : widths)
            if (auto it = values_.find(key); it != values_.end()) {
                try {
                    width[key] = width_value(
                        key, it->second.value,
                        key == "first_layer_extrusion_width" ? s.first_layer_mm() : s.nozzle);
                } catch (const InputError& e) {
                    throw relabel(key, it->second, e);
                }
            }
        for (const char* key :
             {"perimeter_extrusion_width", "extrusion_width", "external_perimeter_extrusion_width"})
            if (width.count(key) && width[key] > 0) {
                s.extrusion_width = width[key];
                break;
            }
        // The first layer's own width (0: the line width, as PrusaSlicer's automatic one).
        if (const auto first = width.find("first_layer_extrusion_width"); first != width.end())
            s.first_layer_extrusion_width = first->second;
        // Arachne's thin-wall widths, which PrusaSlicer gives as a share of the nozzle.
        if (const auto it = width.find("min_bead_width"); it != width.end())
            s.min_bead_width = it->second;
        if (const auto it = width.find("min_feature_size"); it != width.end())
            s.min_feature_size = it->second;
        if (filament_cap_ > 0)
            s.max_volumetric_speed = s.max_volumetric_speed > 0
                                         ? std::min(s.max_volumetric_speed, filament_cap_)
                                         : filament_cap_;
        if (const auto ext = width.find("external_perimeter_extrusion_width");
            ext != width.end() && ext->second > 0 && std::abs(ext->second - s.width_mm()) > 1e-9)
            ignored_.push_back(
                fmt::format("external_perimeter_extrusion_width ({} mm; carve prints "
                            "every wall {} mm wide)",
                            ext->second, s.width_mm()));

        // PrusaSlicer 2.5 writes classic jerk (M205 X Y Z E) for every Marlin flavour: a printer
        // profile without a junction deviation of its own corners by its jerk, not by carve's
        // default M205 J (which the MK3S firmware ignores).
        if (!values_.count("machine_max_junction_deviation") &&
            (values_.count("machine_max_jerk_x") || values_.count("gcode_flavor")))
            s.junction_deviation = 0;
    }

    // What the run is told: the structure carve keeps, and the keys it ignores.
    std::vector<std::string> notes(const ProfileOptions& options) {
        Settings& s = s_;
        std::vector<std::string> notes;
        std::string structure;
        for (auto [key, n] :
             {std::pair{"top_solid_layers", solid_[0]}, std::pair{"bottom_solid_layers", solid_[1]},
              std::pair{"perimeters", perimeters_}})
            if (n >= 0)
                structure += fmt::format("{}{} = {}", structure.empty() ? "" : ", ", key, n);
        if (options.profile_shells) {
            if (solid_[0] >= 0 || solid_[1] >= 0) s.covers = std::max(solid_[0], solid_[1]);
            if (perimeters_ >= 0) s.shells = std::max(0, perimeters_ - 1);
        } else if (!structure.empty()) {
            notes.push_back(
                fmt::format("{}: carve keeps its own covers and shells (--covers {}, --shells {}); "
                            "the profile's {} apply with --profile-shells",
                            path_, s.covers, s.shells, structure));
        }
        if (!ignored_.empty()) {
            std::sort(ignored_.begin(), ignored_.end());
            std::string list;
            for (const std::string& k : ignored_) list += (list.empty() ? "" : ", ") + k;
            notes.push_back(fmt::format(
                "{}{}: keys that change the print and carve ignores: {}", path_,
                profile_.bundle ? fmt::format(" ([printer:{}], [filament:{}], [print:{}])",
                                              profile_.printer, profile_.filament, profile_.print)
                                : "",
                list));
        }
        return notes;
    }

  private:
    // "path:line: profile key 'k'", and where a bundle's key came from.
    std::string where(const std::string& key, const IniValue& v) const {
        std::string at = v.line > 0 ? fmt::format("{}:{}", path_, v.line) : path_;
        if (v.section.empty()) return fmt::format("{}: profile key '{}'", at, key);
        if (v.section == v.owner)
            return fmt::format("{}: [{}] profile key '{}'", at, v.section, key);
        return fmt::format("{}: [{}] (inherited by [{}]) profile key '{}'", at, v.section, v.owner,
                           key);
    }
    // The setters name the key; the message gains the file, line and section.
    InputError relabel(const std::string& key, const IniValue& v, const InputError& e) const {
        const std::string what = e.what();
        const std::string here = where(key, v);
        if (what.rfind(here, 0) == 0) return InputError(what);  // the setter named it already
        const std::string prefix = fmt::format("profile key '{}': ", key);
        return InputError(here + ": " +
                          (what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what));
    }

    ResolvedProfile& profile_;
    std::map<std::string, IniValue>& values_;
    const std::string& path_;
    Settings& s_;
    int solid_[2] = {-1, -1}, perimeters_ = -1;
    double filament_cap_ = 0;           // filament_max_volumetric_speed, mm^3/s; 0 = none
    std::vector<std::string> ignored_;  // keys that change the print, not applied
};

}  // namespace

std::vector<std::string> read_prusa_profile(std::istream& in, const std::string& path, Settings& s,
                                            const ProfileOptions& options) {
    ResolvedProfile profile = read_ini_profile(in, path, options.choice);
    ProfileReading reading(profile, path, s);
    reading.take_filament_overrides();
    reading.add_bundle_ids();
    reading.read_keys();
    apply_stealth_limits(profile.values, s);
    reading.apply_widths();
    return reading.notes(options);
}

}  // namespace carve

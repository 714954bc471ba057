// The table of settings (see setting_table.hpp). Ranges are physical bounds, wide
// enough for every real printer and narrow enough that nothing downstream overflows: a nozzle
// or layer of 0.001 mm or 1e20 mm reaches the micrometre integers as 0 or INT64_MIN.
#include "config/setting_table.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include "base/error.hpp"
#include "base/numbers.hpp"
#include "config/bundle.hpp"

namespace carve {

namespace {

using S = Settings;

// One of a few words, in the order of the enum's values.
template <class E>
TextField words(E S::*member, std::vector<std::string> names) {
    TextField t;
    t.get = [member, names](const Settings& s) { return names.at(static_cast<size_t>(s.*member)); };
    t.set = [member, names](Settings& s, const std::string& text, const std::string& source) {
        const auto it = std::find(names.begin(), names.end(), text);
        if (it == names.end())
            throw InputError(
                fmt::format("{}: '{}' is not one of {}", source, text, fmt::join(names, ", ")));
        s.*member = static_cast<E>(it - names.begin());
    };
    t.choices = std::move(names);
    return t;
}

TextField cavities_field() {
    TextField t;
    t.get = [](const Settings& s) {
        return s.cavities_auto ? std::string("auto") : std::to_string(s.cavities);
    };
    t.set = [](Settings& s, const std::string& text, const std::string& source) {
        if (text == "auto") {
            s.cavities_auto = true;
            return;
        }
        if (!range_problem(text, 0, 64, true, "").empty())
            throw InputError(fmt::format("{}: expected a number from 0 to 64 or 'auto', got '{}'",
                                         source, text));
        s.cavities = static_cast<int>(*parse_decimal(text));
        s.cavities_auto = false;
    };
    return t;
}

// "250x210": two decimal numbers (sscanf's %lf read "0x100" as hexadecimal 256).
TextField bed_field() {
    TextField t;
    t.get = [](const Settings& s) { return plain_number(s.bed_x) + "x" + plain_number(s.bed_y); };
    t.set = [](Settings& s, const std::string& text, const std::string& source) {
        const size_t cross = text.find_first_of("xX");
        std::optional<double> x, y;
        if (cross != std::string::npos) {
            x = parse_decimal(std::string_view(text).substr(0, cross));
            y = parse_decimal(std::string_view(text).substr(cross + 1));
        }
        if (!x || !y || !(*x > 0) || !(*y > 0) || *x > 10000 || *y > 10000)
            throw InputError(fmt::format(
                "{}: expected WIDTHxDEPTH in mm, each above 0 and at most 10000, such as "
                "250x210, got '{}'",
                source, text));
        s.bed_x = *x, s.bed_y = *y;
    };
    t.type_name = "WxH";
    return t;
}

// PrusaSlicer's gcode_flavor: its names for the three firmwares carve writes for. Profiles say
// "marlin", "marlin2" or "marlinlegacy" and "reprap" or "reprapfirmware"; carve writes marlin2
// (it writes M204 P/T and Marlin 2's limits) and reprapfirmware.
TextField flavor_prusa() {
    TextField t;
    t.get = [](const Settings& s) {
        switch (s.flavor) {
            case GcodeFlavor::RepRap:
                return std::string("reprapfirmware");
            case GcodeFlavor::Klipper:
                return std::string("klipper");
            case GcodeFlavor::Marlin:
                break;
        }
        return std::string("marlin2");
    };
    t.set = [](Settings& s, const std::string& text, const std::string& source) {
        if (text == "klipper")
            s.flavor = GcodeFlavor::Klipper;
        else if (text == "reprap" || text == "reprapfirmware")
            s.flavor = GcodeFlavor::RepRap;
        else if (text.rfind("marlin", 0) == 0)
            s.flavor = GcodeFlavor::Marlin;
        else
            throw InputError(fmt::format("{}: unsupported flavour '{}'", source, text));
    };
    t.choices = {"marlin2", "reprapfirmware", "klipper"};
    return t;
}

// PrusaSlicer's bed_shape: the outline's points "0x0,250x0,250x210,0x210"; the bed is their
// bounding box.
TextField bed_shape_field() {
    TextField t;
    t.get = [](const Settings& s) {
        return fmt::format("0x0,{0}x0,{0}x{1},0x{1}", plain_number(s.bed_x), plain_number(s.bed_y));
    };
    t.set = [](Settings& s, const std::string& text, const std::string& source) {
        double min_x = 1e9, min_y = 1e9, max_x = -1e9, max_y = -1e9;
        std::stringstream ss(text);
        std::string pt;
        int n = 0;
        while (std::getline(ss, pt, ',')) {
            const std::string p = trim_whitespace(pt);
            // A plain decimal number each: strtod would read "0x0" as hexadecimal.
            const size_t cross = p.find('x');
            const std::optional<double> x = parse_decimal(p.substr(0, cross));
            const std::optional<double> y =
                cross == std::string::npos ? std::nullopt : parse_decimal(p.substr(cross + 1));
            if (!x || !y) throw InputError(fmt::format("{}: bad point '{}'", source, pt));
            min_x = std::min(min_x, *x), max_x = std::max(max_x, *x);
            min_y = std::min(min_y, *y), max_y = std::max(max_y, *y);
            ++n;
        }
        if (n < 3 || max_x <= min_x || max_y <= min_y)
            throw InputError(fmt::format("{}: '{}' is not a bed outline", source, text));
        s.bed_x = max_x - min_x, s.bed_y = max_y - min_y;
    };
    t.type_name = "POINTS";
    return t;
}

TextField thumbnails_field() {
    TextField t;
    t.get = [](const Settings& s) {
        std::string out;
        for (const auto& [w, h] : s.thumbnails)
            out += fmt::format("{}{}x{}", out.empty() ? "" : ",", w, h);
        return out;
    };
    t.set = [](Settings& s, const std::string& text, const std::string& source) {
        s.thumbnails = parse_thumbnail_sizes(text, source);
    };
    t.type_name = "SIZES";
    return t;
}

// A setting that changes only `scheme`'s carving.
SettingSpec only(CarvingScheme scheme, SettingSpec spec) {
    spec.scheme = scheme;
    return spec;
}

constexpr CarvingScheme kWhole = CarvingScheme::Whole;
constexpr CarvingScheme kReport = CarvingScheme::Report;

// Heights "10,25.5": mm of the model, each from 0 to 10000, at most 100 of them.
TextField pause_at_field() {
    TextField t;
    t.get = [](const Settings& s) {
        std::string out;
        for (double z : s.pause_at) {
            if (!out.empty()) out += ',';
            out += plain_number(z);
        }
        return out;
    };
    t.set = [](Settings& s, const std::string& text, const std::string& source) {
        std::vector<double> zs;
        std::stringstream ss(text);
        for (std::string item; std::getline(ss, item, ',');) {
            const std::optional<double> z = parse_decimal(trim_whitespace(item));
            if (!z || !(*z >= 0 && *z <= 10000))
                throw InputError(fmt::format(
                    "{}: '{}' is not a height in mm from 0 to 10000 (Z[,Z..])", source, item));
            zs.push_back(*z);
        }
        if (zs.size() > 100)
            throw InputError(fmt::format("{}: {} heights; at most 100", source, zs.size()));
        std::sort(zs.begin(), zs.end());
        s.pause_at = std::move(zs);
    };
    t.type_name = "Z[,Z..]";
    return t;
}

// A G-code command or macro name for --pause-command: one line of printable text, no comment.
TextField pause_command_field() {
    TextField t;
    t.get = [](const Settings& s) { return s.pause_command; };
    t.set = [](Settings& s, const std::string& text, const std::string& source) {
        const std::string v = trim_whitespace(text);
        const bool printable = std::all_of(v.begin(), v.end(), [](char c) {
            return static_cast<unsigned char>(c) >= 0x20 && c != 0x7f && c != ';';
        });
        if (!printable || v.size() > 100)
            throw InputError(fmt::format(
                "{}: '{}' is not a command; expected one line of at most 100 characters without "
                "';', such as M601 or PAUSE",
                source, text));
        s.pause_command = v;
    };
    t.type_name = "COMMAND";
    return t;
}

// --cut: heights "100,250.5" (as --pause-at) or "auto".
TextField cut_field() {
    TextField t = pause_at_field();
    const auto get_heights = t.get;
    const auto set_heights = t.set;
    t.get = [get_heights](const Settings& s) {
        if (s.cut_auto) return std::string("auto");
        Settings heights;
        heights.pause_at = s.cut_at;
        return get_heights(heights);
    };
    t.set = [set_heights](Settings& s, const std::string& text, const std::string& source) {
        s.cut_auto = text == "auto";
        if (s.cut_auto) {
            s.cut_at.clear();
            return;
        }
        Settings heights;
        set_heights(heights, text, source);
        s.cut_at = std::move(heights.pause_at);
    };
    t.type_name = "Z[,Z..]|auto";
    return t;
}

// --cut-plane: groups of six numbers X,Y,Z,NX,NY,NZ (a point and a normal), comma-joined.
TextField cut_plane_field() {
    TextField t;
    t.get = [](const Settings& s) {
        std::string out;
        for (double v : s.cut_planes) {
            if (!out.empty()) out += ',';
            out += plain_number(v);
        }
        return out;
    };
    t.set = [](Settings& s, const std::string& text, const std::string& source) {
        std::vector<double> values;
        std::stringstream ss(text);
        for (std::string item; std::getline(ss, item, ',');) {
            const std::optional<double> v = parse_decimal(trim_whitespace(item));
            if (!v || !(std::abs(*v) <= 10000))
                throw InputError(fmt::format(
                    "{}: '{}' is not a number from -10000 to 10000 (X,Y,Z,NX,NY,NZ[,..])", source,
                    item));
            values.push_back(*v);
        }
        if (values.size() % 6 != 0 || values.size() > 6 * 20)
            throw InputError(fmt::format(
                "{}: '{}' is not up to 20 planes of six numbers each, a point and a normal "
                "(X,Y,Z,NX,NY,NZ[,..])",
                source, text));
        for (size_t k = 0; k < values.size(); k += 6)
            if (std::hypot(values[k + 3], values[k + 4], values[k + 5]) < 1e-9)
                throw InputError(
                    fmt::format("{}: plane {} has no normal (0,0,0)", source, k / 6 + 1));
        s.cut_planes = std::move(values);
    };
    t.type_name = "X,Y,Z,NX,NY,NZ[,..]";
    return t;
}

// PrusaSlicer's files state the first layer's height as printed: carve's 0 ("the layer
// height") is written as that height (the configuration block, which hosts and viewers read),
// and a file's height is read as given.
TextField first_layer_prusa() {
    TextField t;
    t.get = [](const Settings& s) { return plain_number(s.first_layer_mm()); };
    t.set = [](Settings& s, const std::string& text, const std::string& source) {
        const std::string problem = range_problem(text, 0.0, 2.0, false, "mm");
        if (!problem.empty()) throw InputError(source + ": " + problem);
        s.first_layer_height = *parse_decimal(text);
    };
    return t;
}

std::vector<SettingSpec> make_table() {
    return {
        {"layer-height", "layer_height", "mm", 0.01, 2.0, &S::layer_height,
         "Layer height h, mm [0.2]"},
        {"nozzle", "nozzle_diameter", "mm", 0.05, 3.0, &S::nozzle,
         "Nozzle diameter = line width w, mm [0.4]"},
        {"max-overhang", "", "degrees", 5.0, 75.0, &S::max_overhang,
         "Largest overhang from vertical the printer bridges, degrees; the per-layer dilation "
         "is r = h * tan(angle) [45]"},
        {"carving", "", "", 0, 0, words(&S::carving, {"whole", "report"}),
         "How the interior is carved: whole (each part of it one cavity, its ceilings bridged "
         "and held by ribs; the least material) or report (Hornus & Lefebvre's iterative "
         "carving: nested cavities torn open along the medial axis, single-filament walls) "
         "[whole]",
         false, "", "carving_scheme"},
        {"cavities", "", "", 0, 0, cavities_field(),
         "Carving iterations k, or 'auto' (stop when the remainder erodes away at the line "
         "width); 0 = a plain hollow shell [6]"},
        {"walls", "", "", 0, 0, words(&S::walls, {"single", "double"}),
         "Cavity walls: single (one filament, report 4.3) or double (4.1) [single]"},
        {"support", "", "", 0, 0, words(&S::support, {"none", "auto", "buildplate"}),
         "Supports under the model's own overhangs: none, auto (down to the bed or onto the "
         "model) or buildplate (only where nothing of the model lies below) [none]"},
        {"support-angle", "", "degrees", 0.0, 85.0, &S::support_angle,
         "Overhang from vertical beyond which the model's own surface needs support; with "
         "--support none carve measures that overhang and warns when it will hang, degrees [0 = "
         "--max-overhang]"},
        {"support-z-gap", "support_material_contact_distance", "mm", 0.0, 2.0, &S::support_z_gap,
         "Gap between a support's top and the overhang it holds, rounded to whole layers, mm "
         "[0.2]"},
        {"support-xy-gap", "", "mm", 0.0, 10.0, &S::support_xy_gap,
         "Gap between a support and the model's side, mm [0.25]"},
        {"support-interface-layers", "support_material_interface_layers", "layers", 0, 10,
         &S::support_interface_layers,
         "Dense layers at the top of every support, under the overhang, layers [2]"},
        {"covers", "", "layers", 0, 50, &S::covers, "Solid layers at tops and bottoms, layers [2]"},
        {"shells", "", "lines", 0, 20, &S::shells,
         "Extra perimeters inside the outer wall, lines [0]"},
        {"strong", "", "ratio", 0.0, 1.0, &S::strength,
         "How strong to print, a ratio of --preset strong's interior, from carve's default (0) "
         "to it (1): on a squat model round(2 x S) shells and --ties 5.5 / S, on a slender "
         "one (height over the side of its mean section 5 or more) round(4 x S) shells; "
         "--shells and --ties given win [0]"},
        {"ties", "", "mm", 0.0, 100.0, &S::tie_spacing,
         "Walls tied across the cavities: a square grid of single-filament walls at +-45 "
         "degrees this far apart, stacked layer on layer from wall to wall, mm; --strong sets "
         "it [0 = none]"},
        {"extrusion-width", "", "mm", 0.0, 3.0, &S::extrusion_width,
         "Line width w of every wall and cover, mm; a profile's perimeter_extrusion_width or "
         "extrusion_width sets it [0 = the nozzle diameter]"},
        {"flavor", "gcode_flavor", "", 0, 0, words(&S::flavor, {"marlin", "reprap", "klipper"}),
         "G-code flavour: marlin, reprap or klipper [marlin]", false, "", "", flavor_prusa()},
        {"relative-e", "use_relative_e_distances", "0/1", 0, 1, &S::relative_e,
         "Relative extrusion distances (M83) [off: absolute, M82]"},
        {"bed", "bed_shape", "mm", 0, 0, bed_field(),
         "Bed size WxH, mm; the model is centred on it [250x210]", false, "", "",
         bed_shape_field()},
        {"max-print-height", "max_print_height", "mm", 1.0, 10000.0, &S::max_print_height,
         "Highest the printer prints, mm; a taller model is refused [210]"},
        {"bed-check", "", "0/1", 0, 1, &S::bed_check,
         "Allow a model larger than the bed or taller than --max-print-height [off]", false,
         "!--no-bed-check"},
        {"filament-diameter", "filament_diameter", "mm", 0.5, 5.0, &S::filament_diameter,
         "Filament diameter, mm [1.75]"},
        {"temperature", "temperature", "C", 0, 450, &S::nozzle_temperature,
         "Nozzle temperature after the first layer, C [210]"},
        {"bed-temperature", "bed_temperature", "C", 0, 150, &S::bed_temperature,
         "Bed temperature after the first layer, C [60]"},
        {"first-layer-temperature", "first_layer_temperature", "C", 0, 450,
         &S::first_layer_nozzle_temperature, "Nozzle temperature on the first layer, C [215]"},
        {"first-layer-bed-temperature", "first_layer_bed_temperature", "C", 0, 150,
         &S::first_layer_bed_temperature, "Bed temperature on the first layer, C [60]"},
        {"filament-density", "filament_density", "g/cm^3", 0.1, 20.0, &S::filament_density,
         "Filament density for the weight estimate, g/cm^3 [1.24]"},
        {"travel-speed", "travel_speed", "mm/s", 1.0, 1000.0, &S::travel_speed,
         "Travel speed, mm/s [150]"},
        {"perimeter-speed", "external_perimeter_speed", "mm/s", 1.0, 1000.0, &S::perimeter_speed,
         "Outer wall speed, mm/s [40]", true},
        {"cavity-speed", "perimeter_speed", "mm/s", 1.0, 1000.0, &S::cavity_speed,
         "Cavity wall speed, mm/s [60]"},
        {"cover-speed", "solid_infill_speed", "mm/s", 1.0, 1000.0, &S::cover_speed,
         "Cover (solid) speed, mm/s [50]", true},
        {"bridge-speed", "bridge_speed", "mm/s", 1.0, 1000.0, &S::bridge_speed,
         "Bridge speed, mm/s [25]"},
        {"first-layer-speed", "first_layer_speed", "mm/s", 1.0, 1000.0, &S::first_layer_speed,
         "First layer speed, mm/s [20]", true},
        {"acceleration", "machine_max_acceleration_extruding", "mm/s^2", 10.0, 100000.0,
         &S::acceleration, "Print acceleration, mm/s^2 [1000]"},
        {"travel-acceleration", "machine_max_acceleration_travel", "mm/s^2", 10.0, 100000.0,
         &S::travel_acceleration, "Travel acceleration, mm/s^2 [1500]"},
        {"max-print-speed", "max_print_speed", "mm/s", 1.0, 1000.0, &S::max_print_speed,
         "Cap on every printing speed, mm/s [100]"},
        {"retract-length", "retract_length", "mm", 0.0, 20.0, &S::retract_length,
         "Retraction, mm [0.8]"},
        {"retract-speed", "retract_speed", "mm/s", 1.0, 500.0, &S::retract_speed,
         "Retraction speed, mm/s [35]"},
        {"z-hop", "retract_lift", "mm", 0.0, 10.0, &S::z_hop,
         "Lift on travel with retraction, mm [0]"},
        only(kReport, {"tear-limit", "", "mm", 0.0, 1000.0, &S::tear_limit,
                       "With --carving report: how far a cavity may tear open along its seed "
                       "per slice beyond the dilated cavity, mm; smaller leaves less unsupported "
                       "but uses more material (the report proposes r/2 = 0.1) [0 = no limit]"}),
        only(kReport, {"wall-extension", "", "mm", 0.0, 10.0, &S::wall_extension,
                       "With --carving report: an open single-filament cavity wall is extended "
                       "this far along the walls printed before it at each end, to stick to "
                       "them (report 4.3), mm [1]"}),
        only(kWhole, {"whole-width", "", "mm", 0.0, 1000.0, &S::whole_width,
                      "With --carving whole: a part of the volume to carve narrower than this is "
                      "carved whole and its ceiling printed as bridges, mm; also a part up to "
                      "--whole-width-max wide whose ceiling (what lies under the model's "
                      "surface) is narrower than this; the ribs hold ceilings of any width; 0, "
                      "which would tear every part, is refused: that is --carving report [1000]"}),
        only(kWhole, {"whole-width-max", "", "mm", 0.0, 1000.0, &S::whole_width_max,
                      "With --carving whole: how wide a part whose ceiling is narrower than "
                      "--whole-width may be and still be carved whole, mm [1000]"}),
        {"scale", "", "ratio", 0.01, 100.0, &S::scale,
         "Scale the model uniformly by this factor, ratio [1]"},
        {"orient", "", "", 0, 0, words(&S::orient, {"given", "auto"}),
         "How the model lies on the bed: given (as loaded) or auto (the axis-aligned turns and "
         "the largest faces of its convex hull laid down, each carved at coarse layers with "
         "supports; the least material wins, then the shorter print, then less overhang) "
         "[given]"},
        // Skirt and brim (toolpath/skirt.hpp), PrusaSlicer's keys and defaults (its printer
        // profiles' brim_separation).
        {"skirts", "skirts", "loops", 0, 100, &S::skirts,
         "Loops of skirt around the first layers, priming the nozzle; 0 = none, loops [1]"},
        {"skirt-distance", "skirt_distance", "mm", 0.0, 500.0, &S::skirt_distance,
         "Gap between the skirt and the part (or its brim), mm [6]"},
        {"skirt-height", "skirt_height", "layers", 0, 10000, &S::skirt_height,
         "Layers the skirt rises, layers [1]"},
        {"brim-width", "brim_width", "mm", 0.0, 200.0, &S::brim_width,
         "Width of the brim around the outside of each part on the first layer (the brims of "
         "two copies join only where they touch); 0 = none, mm [0]"},
        {"brim-separation", "brim_separation", "mm", 0.0, 10.0, &S::brim_separation,
         "Gap between the part and its brim, so that it breaks off cleanly, mm [0.1]"},
        // The raft (toolpath/raft.hpp), PrusaSlicer's keys and defaults.
        {"raft-layers", "raft_layers", "layers", 0, 100, &S::raft_layers,
         "Layers of raft printed under the model, wider than its first layer, for a part that "
         "holds the bed poorly; the raft's first layer takes the first-layer settings, the "
         "model starts --raft-contact-distance above its top; 0 = none, layers [0]"},
        {"raft-contact-distance", "raft_contact_distance", "mm", 0.0, 2.0,
         &S::raft_contact_distance,
         "Gap between the raft's top and the model's first layer, so that the raft peels off "
         "(at most the layer height: the model's first layer fills it with its flow), mm [0.1]"},
        {"raft-expansion", "raft_expansion", "mm", 0.0, 100.0, &S::raft_expansion,
         "How far the raft reaches beyond the model's first layer, mm [1.5]"},
        {"raft-first-layer-expansion", "raft_first_layer_expansion", "mm", 0.0, 100.0,
         &S::raft_first_layer_expansion,
         "How far the raft's first layer reaches beyond the raft's other layers, mm [3]"},
        // The first layer and the flow (issue #36), PrusaSlicer's keys and meanings.
        {"first-layer-height", "first_layer_height", "mm", 0.0, 2.0, &S::first_layer_height,
         "Height of the first layer (no higher than the nozzle), mm; later layers stand on it "
         "at --layer-height [0 = the layer height]",
         true, "", "", first_layer_prusa()},
        {"first-layer-extrusion-width", "", "mm", 0.0, 3.0, &S::first_layer_extrusion_width,
         "Line width on the first layer (its E follows it; the paths keep their places), under "
         "3 nozzle widths as PrusaSlicer requires; a profile's first_layer_extrusion_width sets "
         "it, mm [0 = the line width]"},
        // 0.5 to 2 (issue #52): calibration moves it by a few percent; at half the flow the
        // lines no longer touch their neighbours or the layer below, at twice it each line
        // holds two lines' plastic, which the nozzle ploughs through on the next pass.
        {"extrusion-multiplier", "extrusion_multiplier", "ratio", 0.5, 2.0,
         &S::extrusion_multiplier,
         "Scales the filament fed by every extrusion (0.5 to 2: beyond, lines either no longer "
         "touch or overflow the line), ratio [1]"},
        {"max-volumetric-speed", "max_volumetric_speed", "mm^3/s", 0.0, 1000.0,
         &S::max_volumetric_speed,
         "Cap on every extrusion's flow: a line is printed no faster than this over its width "
         "x height, and a cap that would hold the widest line under 5 mm/s is refused; a "
         "profile's filament_max_volumetric_speed caps it too, mm^3/s [0 = none]"},
        {"elephant-foot-compensation", "elefant_foot_compensation", "mm", 0.0, 5.0,
         &S::elephant_foot_compensation,
         "The first layer's slice is shrunk by this, against the squashed first layer's bulge, "
         "mm [0]"},
        {"thin-walls", "", "0/1", 0, 1, &S::thin_walls,
         "Print the parts of a slice narrower than two lines (fins, rims, lettering) as one line "
         "along their middle, as wide as the part; --no-thin-walls: only what the outer wall "
         "holds [on]",
         false, "!--no-thin-walls,--thin-walls"},
        {"min-bead-width", "", "mm", 0.0, 3.0, &S::min_bead_width,
         "Narrowest line a thin part is printed with: a part narrower than this (and not than "
         "--min-feature-size) is widened to it; a profile's min_bead_width sets it, mm [0 = 85 % "
         "of the nozzle]"},
        {"min-feature-size", "", "mm", 0.0, 3.0, &S::min_feature_size,
         "A part of a slice narrower than this is not printed (carve slice reports what that "
         "leaves out); a profile's min_feature_size sets it, mm [0 = 25 % of the nozzle]"},
        {"xy-size-compensation", "xy_size_compensation", "mm", -5.0, 5.0, &S::xy_size_compensation,
         "Every slice grows by this (shrinks if negative), holes shrinking with it, mm [0]"},
        {"z-offset", "z_offset", "mm", -10.0, 10.0, &S::z_offset,
         "Added to every Z written to the G-code (the printer's bed height); the first layer "
         "it leaves is at least a quarter of the layer height (or of the nozzle, if thinner) "
         "and the highest Z within --max-print-height, mm [0]"},
        {"copies", "", "copies", 1, 400, &S::copies,
         "Print this many copies of the model side by side, each its own object (labelled for "
         "cancelling), copies [1]"},
        {"copy-gap", "", "mm", 0.0, 100.0, &S::copy_gap,
         "With --copies: the gap between two copies, mm [6]"},
        {"threads", "", "threads", 0, 512, &S::threads,
         "Threads the per-layer work runs on, from 1 (everything on one thread) up; the G-code "
         "is the same for every count, threads [0 = every core]"},
        {"prune-bridges", "", "0/1", 0, 1, &S::prune_bridges,
         "Keep bridges that the layer below already supports [off]", false, "!--keep-all-bridges"},
        {"max-bridge-length", "", "mm", 1.0, 500.0, &S::max_bridge_length,
         "Longest span a bridge may have, mm; a longer one is split into pieces bridged apart, "
         "and what no shorter line reaches is left out [10]"},
        {"rib-reach", "", "mm", 0.0, 100.0, &S::rib_reach,
         "What the layer above prints deeper than this inside a cavity gets a rib under it, a "
         "column grown down through the cavity leaning at most the overhang angle, mm; 0 = no "
         "ribs [1.6]"},
        {"rib-spacing", "", "mm", 0.5, 100.0, &S::rib_spacing,
         "Spacing of the lattice the ribs are seeded on, mm [2.6]"},
        {"rib-piece", "", "mm", 0.0, 100.0, &S::rib_piece,
         "Length of the line a rib prints on each layer (at least two line widths), mm [0.8]"},
        {"vault-width", "", "mm", 0.0, 1000.0, &S::vault_width,
         "What would hang over a part at least this wide gets vault lines instead of ribs where "
         "they print less: parallel walls across the cavity, wall to wall, merging in pairs "
         "going down, mm; 0 = ribs alone [2.6]"},
        {"max-vertices-per-layer", "", "vertices", 0, 1e9, &S::max_vertices_per_layer,
         "Give up when one slice has more contour vertices than this; 0 = no limit, vertices "
         "[5000000]"},
        {"max-vertices", "", "vertices", 0, 1e10, &S::max_vertices_total,
         "Give up when the slices hold more contour vertices than this in all; 0 = no limit, "
         "vertices [100000000]"},
        {"combing", "", "", 0, 0, words(&S::combing, {"off", "inside", "all"}),
         "Travel inside the part without retracting: off (straight travels), inside (not over "
         "covers) or all (anywhere in the island) [all]"},
        {"avoid-crossing-perimeters", "avoid_crossing_perimeters", "0/1", 0, 1,
         &S::avoid_crossing_perimeters,
         "A travel that must leave its island goes inside it to where the next island is "
         "closest, crosses the gap and goes on inside that one, instead of straight [on]",
         false, "!--no-avoid-crossing-perimeters,--avoid-crossing-perimeters"},
        {"seam", "seam_position", "", 0, 0,
         words(&S::seam, {"aligned", "nearest", "rear", "random"}),
         "Where outer wall loops start: aligned (one line, in concave corners where there are "
         "any), nearest, rear or random [aligned]"},
        {"wipe", "wipe", "0/1", 0, 1, &S::wipe,
         "Move back along the last path while retracting [off]"},
        {"retract-before-travel", "retract_before_travel", "mm", 0.0, 1000.0,
         &S::retract_min_travel,
         "Only a travel longer than this retracts (one that stays inside the part with combing "
         "never does), mm [2]"},
        {"firmware-retraction", "use_firmware_retraction", "0/1", 0, 1, &S::firmware_retraction,
         "Retract with G10/G11, length and speed set in the firmware [off]"},
        {"wipe-distance", "", "mm", 0.0, 50.0, &S::wipe_distance,
         "With --wipe: how far back, mm [1]"},
        // Cooling (PrusaSlicer's keys and meanings).
        {"cooling", "cooling", "0/1", 0, 1, &S::cooling,
         "Automatic cooling: slow down short layers and raise the fan for them, 0/1 [1]"},
        {"min-layer-time", "slowdown_below_layer_time", "seconds", 0.0, 3600.0,
         &S::slowdown_below_layer_time,
         "A layer that would print faster is slowed down to take this long, seconds [5]"},
        {"min-print-speed", "min_print_speed", "mm/s", 1.0, 1000.0, &S::min_print_speed,
         "Slowing down for the minimum layer time stops at this speed, mm/s [10]"},
        {"fan-always-on", "fan_always_on", "0/1", 0, 1, &S::fan_always_on,
         "Keep the fan at least at the minimum speed on every layer, 0/1 [1]"},
        {"min-fan-speed", "min_fan_speed", "%", 0, 100, &S::min_fan_speed,
         "Fan speed for layers that take long enough, % [100]"},
        {"max-fan-speed", "max_fan_speed", "%", 0, 100, &S::max_fan_speed,
         "Fan speed for the shortest layers, % [100]"},
        {"bridge-fan-speed", "bridge_fan_speed", "%", 0, 100, &S::bridge_fan_speed,
         "Fan speed while printing bridges, % [100]"},
        {"fan-below-layer-time", "fan_below_layer_time", "seconds", 0.0, 3600.0,
         &S::fan_below_layer_time,
         "The fan rises from the minimum towards the maximum speed on layers shorter than "
         "this, seconds [60]"},
        {"disable-fan-first-layers", "disable_fan_first_layers", "layers", 0, 1000,
         &S::disable_fan_first_layers, "The fan stays off on this many first layers, layers [1]"},
        // Machine limits: profile keys only (PrusaSlicer's printer settings).
        {"", "machine_max_acceleration_x", "mm/s^2", 1.0, 100000.0, &S::max_acceleration_x,
         "Machine limit M201 X, mm/s^2 [3000]"},
        {"", "machine_max_acceleration_y", "mm/s^2", 1.0, 100000.0, &S::max_acceleration_y,
         "Machine limit M201 Y, mm/s^2 [3000]"},
        {"", "machine_max_acceleration_z", "mm/s^2", 1.0, 100000.0, &S::max_acceleration_z,
         "Machine limit M201 Z, mm/s^2 [200]"},
        {"", "machine_max_acceleration_e", "mm/s^2", 1.0, 100000.0, &S::max_acceleration_e,
         "Machine limit M201 E, mm/s^2 [5000]"},
        {"", "machine_max_acceleration_retracting", "mm/s^2", 1.0, 100000.0,
         &S::retract_acceleration, "Retraction acceleration M204 R, mm/s^2 [1500]"},
        {"", "machine_max_feedrate_x", "mm/s", 1.0, 10000.0, &S::max_feedrate_x,
         "Machine limit M203 X, mm/s [500]"},
        {"", "machine_max_feedrate_y", "mm/s", 1.0, 10000.0, &S::max_feedrate_y,
         "Machine limit M203 Y, mm/s [500]"},
        {"", "machine_max_feedrate_z", "mm/s", 0.1, 10000.0, &S::max_feedrate_z,
         "Machine limit M203 Z, mm/s [12]"},
        {"", "machine_max_feedrate_e", "mm/s", 0.1, 10000.0, &S::max_feedrate_e,
         "Machine limit M203 E, mm/s [120]"},
        {"", "machine_max_jerk_x", "mm/s", 0.0, 1000.0, &S::max_jerk_x,
         "Machine limit M205 X (classic jerk), mm/s [8]"},
        {"", "machine_max_jerk_y", "mm/s", 0.0, 1000.0, &S::max_jerk_y,
         "Machine limit M205 Y (classic jerk), mm/s [8]"},
        {"", "machine_max_jerk_z", "mm/s", 0.0, 1000.0, &S::max_jerk_z,
         "Machine limit M205 Z (classic jerk), mm/s [0.4]"},
        {"", "machine_max_jerk_e", "mm/s", 0.0, 1000.0, &S::max_jerk_e,
         "Machine limit M205 E (classic jerk), mm/s [4.5]"},
        {"", "machine_max_junction_deviation", "mm", 0.0, 1.0, &S::junction_deviation,
         "Junction deviation M205 J (Marlin 2); 0 = classic jerk, mm [0.013]"},
        // PrusaSlicer's spelling in the configuration block, but not read from a profile: a
        // profile turning arcs on could not be overruled, the option having no negation.
        {"arc-fitting", "", "0/1", 0, 1, &S::arc_fitting,
         "Write G2/G3 arcs where a path follows a circle within --arc-tolerance; the firmware "
         "must accept arcs (Klipper: [gcode_arcs]) [off]",
         false, "", "", words(&S::arc_fitting, {"disabled", "emit_center"})},
        {"arc-tolerance", "", "mm", 0.001, 0.2, &S::arc_tolerance,
         "With --arc-fitting, how far an arc may leave the path it replaces, mm [0.02]"},
        // The stats have always called it by its profile key.
        {"m73", "remaining_times", "0/1", 0, 1, &S::m73,
         "Write M73 progress and remaining time for printer screens and hosts; --no-m73: none, "
         "whatever the printer [off; on with --printer mk3s or ender3]",
         false, "!--no-m73,--m73", "remaining_times"},
        {"silent-mode", "silent_mode", "0/1", 0, 1, &S::silent_mode,
         "The printer has a stealth mode: M73 also writes Q/S, the figures its screen shows "
         "there, timed with --stealth-max-acceleration and --stealth-max-feedrate [off; on "
         "with --printer mk3s]",
         false, "!--no-silent-mode,--silent-mode"},
        {"stealth-max-acceleration", "", "mm/s^2", 0.0, 100000.0, &S::stealth_max_acceleration,
         "With --silent-mode: the stealth mode's X and Y acceleration limit that M73 Q/S are "
         "timed with (a profile's second machine_max_acceleration_x/y), mm/s^2 [0 = the "
         "normal limits; 960 with --printer mk3s]"},
        {"stealth-max-feedrate", "", "mm/s", 0.0, 10000.0, &S::stealth_max_feedrate,
         "With --silent-mode: the stealth mode's X and Y speed limit (a profile's second "
         "machine_max_feedrate_x/y), mm/s [0 = the normal limits; 100 with --printer mk3s]"},
        {"pause-at", "", "mm", 0, 0, pause_at_field(),
         "Pause before the first layer at or above each height, mm of the model: M600 "
         "(filament change) on Marlin and RepRap, PAUSE on Klipper, retracted and lifted 5 mm "
         "before it and back after it [none]"},
        {"pause-command", "", "", 0, 0, pause_command_field(),
         "The command --pause-at writes: a G-code or a macro's name (M601, M0, PAUSE, "
         "M600; Klipper's PAUSE needs its pause_resume section and a PAUSE macro) [none: "
         "M600 on Marlin and RepRap, PAUSE on Klipper]"},
        {"cut", "", "mm", 0, 0, cut_field(),
         "Cut the model across z at these heights above its bottom, mm, or 'auto' (the fewest "
         "cuts that fit every piece on the bed, where the cut faces are smallest); the pieces "
         "print on plates, one G-code each [none]"},
        {"cut-plane", "", "mm", 0, 0, cut_plane_field(),
         "Cut the model by planes in any direction: a point (mm from the least x, y and z corner "
         "of the model's box) and a normal each, X,Y,Z,NX,NY,NZ, groups comma-joined; each "
         "piece lies on its largest cut face [none]"},
        {"cut-connectors", "", "", 0, 0, words(&S::cut_connectors, {"none", "dowel", "pin"}),
         "What joins the pieces of --cut: dowel (holes in both faces), pin (a pin on the piece "
         "below, a hole in the one above) or none [dowel]"},
        {"dowel-diameter", "", "mm", 1.0, 50.0, &S::dowel_diameter,
         "With --cut: the diameter of a dowel or pin, mm [5]"},
        {"dowel-depth", "", "mm", 1.0, 100.0, &S::dowel_depth,
         "With --cut: the depth of each connector hole, mm [6]"},
        {"connector-clearance", "", "mm", 0.0, 2.0, &S::connector_clearance,
         "With --cut: added to the radius of a hole around a dowel or pin, mm [0.15]"},
        {"thumbnails", "thumbnails", "", 0, 0, thumbnails_field(),
         "PNG previews of the model in the header, PrusaSlicer's format, sizes WxH,WxH (e.g. "
         "16x16,220x124) [none; 16x16,220x124 with --printer mk3s, 32x32,400x300 with --printer "
         "klipper]"},
    };
}

}  // namespace

double SettingSpec::get(const Settings& s) const {
    return std::visit(
        [&](const auto& member) -> double {
            if constexpr (std::is_same_v<std::decay_t<decltype(member)>, TextField>)
                throw std::logic_error(std::string("text setting read as a number: ") + option);
            else
                return static_cast<double>(s.*member);
        },
        field);
}

std::string SettingSpec::text_value(const Settings& s) const {
    if (text()) return text_field().get(s);
    if (flag()) return get(s) != 0 ? "on" : "off";
    return plain_number(get(s));
}

std::variant<double, long long, bool, std::string> SettingSpec::value(const Settings& s) const {
    if (text()) {
        std::string t = text_field().get(s);
        if (const auto d = parse_decimal(t); d && *d == std::floor(*d) && std::abs(*d) < 1e15)
            return static_cast<long long>(*d);
        return t;
    }
    if (flag()) return get(s) != 0;
    return std::visit(
        [&](const auto& member) -> std::variant<double, long long, bool, std::string> {
            using M = std::decay_t<decltype(member)>;
            if constexpr (std::is_same_v<M, double Settings::*>)
                return s.*member;
            else if constexpr (std::is_same_v<M, TextField>)
                return std::string();  // handled above
            else
                return static_cast<long long>(s.*member);
        },
        field);
}

std::string SettingSpec::name() const {
    std::string out = *key ? key : *option ? option : ini_key;
    for (char& c : out)
        if (c == '-') c = '_';
    return out;
}

std::string SettingSpec::config_key() const {
    return *ini_key ? std::string(ini_key) : name();
}

std::string SettingSpec::prusa_text(const Settings& s) const {
    if (prusa) return prusa->get(s);
    if (text()) return text_field().get(s);
    return plain_number(get(s));
}

void SettingSpec::set_prusa(Settings& s, const std::string& text, const std::string& source) const {
    if (prusa)
        prusa->set(s, text, source);
    else
        set(s, text, source);
}

std::string SettingSpec::cli_switch_names() const {
    return *switch_names ? std::string(switch_names) : std::string("--") + option;
}

std::string SettingSpec::label() const {
    if (!*option) return name();
    // A switch that only has a negation (--keep-all-bridges) has no --option to name it by.
    const std::string own = std::string("--") + option;
    if (is_switch()) {
        const std::string names = cli_switch_names();
        bool named = false;
        for (size_t at = 0; at <= names.size();) {
            const size_t comma = std::min(names.find(',', at), names.size());
            named = named || std::string_view(names).substr(at, comma - at) == own;
            at = comma + 1;
        }
        if (!named) return name();
    }
    return own;
}

void SettingSpec::set(Settings& s, const std::string& text, const std::string& source) const {
    if (const TextField* t = std::get_if<TextField>(&field)) {
        t->set(s, text, source);
        return;
    }
    const std::string problem = range_problem(text, min, max, integer(), unit);
    if (!problem.empty()) throw InputError(source + ": " + problem);
    const double d = *parse_decimal(text);
    std::visit(
        [&](const auto& member) {
            using M = std::decay_t<decltype(member)>;
            if constexpr (std::is_same_v<M, bool Settings::*>)
                s.*member = d != 0;
            else if constexpr (!std::is_same_v<M, TextField>)
                s.*member = static_cast<std::remove_reference_t<decltype(s.*member)>>(d);
        },
        field);
}

const std::vector<SettingSpec>& setting_table() {
    static const std::vector<SettingSpec> table = make_table();
    return table;
}

const SettingSpec* find_setting_by_ini_key(const std::string& key) {
    for (const SettingSpec& spec : setting_table())
        if (!key.empty() && key == spec.ini_key) return &spec;
    return nullptr;
}

std::vector<std::pair<int, int>> parse_thumbnail_sizes(const std::string& text,
                                                       const std::string& source) {
    std::vector<std::pair<int, int>> sizes;
    size_t at = 0;
    while (at <= text.size()) {
        size_t end = text.find(',', at);
        if (end == std::string::npos) end = text.size();
        std::string item = text.substr(at, end - at);
        at = end + 1;
        item.erase(0, item.find_first_not_of(" \t"));
        item.erase(item.find_last_not_of(" \t") + 1);
        if (item.empty()) {
            if (end == text.size()) break;
            continue;
        }
        std::string format = "PNG";
        if (const size_t slash = item.find('/'); slash != std::string::npos) {
            format = item.substr(slash + 1);
            item.resize(slash);
        }
        const size_t cross = item.find('x');
        const std::optional<double> w =
            cross == std::string::npos ? std::nullopt : parse_decimal(item.substr(0, cross));
        const std::optional<double> h =
            cross == std::string::npos ? std::nullopt : parse_decimal(item.substr(cross + 1));
        auto side = [](const std::optional<double>& v) {
            return v && *v >= 1 && *v <= 1024 && *v == std::floor(*v);
        };
        if (!side(w) || !side(h))
            throw InputError(
                fmt::format("{}: '{}' is not a thumbnail size WxH (whole pixels from 1 to 1024)",
                            source, item));
        if (format != "PNG" && format != "png")
            throw InputError(fmt::format(
                "{}: thumbnail format '{}' is not supported; carve writes PNG", source, format));
        sizes.emplace_back(static_cast<int>(*w), static_cast<int>(*h));
        if (end == text.size()) break;
    }
    if (sizes.size() > 8)
        throw InputError(fmt::format("{}: {} thumbnail sizes; at most 8", source, sizes.size()));
    return sizes;
}

std::string scheme_name(CarvingScheme scheme) {
    return scheme == CarvingScheme::Report ? "report" : "whole";
}

void check_scheme(const SettingSpec& spec, const Settings& s) {
    if (!spec.scheme || *spec.scheme == s.carving) return;
    throw UsageError(fmt::format(
        "{} changes only --carving {}; this run carves with --carving {}{}, where it would do "
        "nothing",
        spec.label(), scheme_name(*spec.scheme), scheme_name(s.carving),
        s.carving == CarvingScheme::Whole ? " (the default)" : ""));
}

namespace {

// The first layer and the flow, as PrusaSlicer refuses them (and a first layer the nozzle
// would print into the bed).
void check_first_layer(const Settings& s) {
    if (s.first_layer_height > 0 && s.first_layer_height < 0.01)
        throw InputError(fmt::format(
            "--first-layer-height {} mm is too thin; expected 0 (the layer height) or from 0.01 "
            "to the {} mm nozzle",
            plain_number(s.first_layer_height), plain_number(s.nozzle)));
    // PrusaSlicer: "First layer height can't be greater than nozzle diameter".
    if (s.first_layer_mm() > s.nozzle + 1e-9)
        throw InputError(
            fmt::format("--first-layer-height {} mm is higher than the {} mm nozzle can print",
                        plain_number(s.first_layer_mm()), plain_number(s.nozzle)));
    if (s.first_layer_extrusion_width > 0 && s.first_layer_extrusion_width < 0.05)
        throw InputError(fmt::format(
            "--first-layer-extrusion-width {} mm is too thin; expected 0 (the line width) or "
            "from 0.05 to 3 mm",
            plain_number(s.first_layer_extrusion_width)));
    if (s.first_layer_mm() > s.layer_width_mm(s.first_print_layer()) + 1e-9)
        throw InputError(fmt::format(
            "--first-layer-height {} mm is thicker than the first layer's {} mm line width",
            plain_number(s.first_layer_mm()),
            plain_number(s.layer_width_mm(s.first_print_layer()))));
    // PrusaSlicer's Print::validate: "Too large extrusion width" from 3 nozzle widths. Such a
    // line is wider than the nozzle's flat tip by far: nothing presses its edges onto the bed,
    // and it is printed at a third of the speed of its E (a profile's 1500 % of a 0.2 mm first
    // layer asked for 3 mm lines from a 0.4 mm nozzle, issue #52).
    if (s.first_layer_extrusion_width >= 3 * s.nozzle - 1e-9)
        throw InputError(fmt::format(
            "--first-layer-extrusion-width {} mm (a profile's first_layer_extrusion_width) is "
            "too wide for the {} mm nozzle; expected 0 (the line width) or under 3 nozzle "
            "widths, {} mm",
            plain_number(s.first_layer_extrusion_width), plain_number(s.nozzle),
            plain_number(3 * s.nozzle)));
    if (s.max_volumetric_speed > 0 && s.max_volumetric_speed < 0.1)
        throw InputError(fmt::format(
            "--max-volumetric-speed {} mm^3/s is too low to print; expected 0 (no cap) or from "
            "0.1 to 1000 mm^3/s",
            plain_number(s.max_volumetric_speed)));
    // A first layer that the offset makes thinner than a quarter of a layer (or of the nozzle,
    // if thinner) is the nozzle scraping the bed: --z-offset -0.19 at 0.2 mm layers printed
    // 0.01 mm (issue #52). Raising it is never refused here; the printer's height is checked
    // with the model (run_setup.cpp) and on every Z written (gcode.cpp).
    const double printed = s.first_layer_mm() + s.z_offset;
    const double quarter = 0.25 * std::min(s.layer_height, s.nozzle);
    if (printed < 0.01 || (s.z_offset < 0 && printed < quarter - 1e-9))
        throw InputError(fmt::format(
            "--z-offset {} mm (a profile's z_offset) would print the {} mm first layer {} mm "
            "thick, into the bed: at least a quarter of the {} mm {} ({} mm) is needed, an "
            "offset from {} mm",
            plain_number(s.z_offset), plain_number(s.first_layer_mm()),
            plain_number(std::round(printed * 1e6) / 1e6),
            plain_number(std::min(s.layer_height, s.nozzle)),
            s.nozzle < s.layer_height ? "nozzle" : "layer height", plain_number(quarter),
            plain_number(std::round((std::max(quarter, 0.01) - s.first_layer_mm()) * 1e6) / 1e6)));
}

// The raft's gap and the volumetric cap, against the lines they shape (issue #52).
void check_flow(const Settings& s) {
    // PrusaSlicer's raft_contact_distance is a release gap of 0.1 to 0.2 mm. carve's model
    // first layer on a raft fills it with its flow (Settings::layer_thickness_mm), so a gap
    // over the layer height asked for a line taller than wide: 2 mm made a 2.2 mm line from a
    // 0.4 mm nozzle.
    if (s.raft_layers > 0 && s.raft_contact_distance > s.layer_height + 1e-9)
        throw InputError(fmt::format(
            "--raft-contact-distance {} mm (a profile's raft_contact_distance) is more than the "
            "{} mm layer height: the model's first layer on the raft fills the gap with its "
            "flow, a {} mm tall line; expected from 0 to {} mm",
            plain_number(s.raft_contact_distance), plain_number(s.layer_height),
            plain_number(s.layer_height + s.raft_contact_distance), plain_number(s.layer_height)));
    if (s.max_volumetric_speed <= 0) return;
    // The slowest feed the cap leaves is that of the widest line: the first layer's, the
    // model's first layer on a raft, or any other. Below 5 mm/s (half the slowest PrusaSlicer's
    // and Cura's cooling slow a layer to, 10 mm/s) a line is more ooze and heat soak than
    // extrusion, and a print takes days: 0.1 mm^3/s on a 3 mm nozzle's 2 mm layers fed
    // 0.017 mm/s.
    constexpr double kMinFeed = 5;  // mm/s
    double w = s.layer_width_mm(s.first_print_layer()), h = s.first_layer_mm();
    const char* which = "the first layer's";
    auto consider = [&](double width, double height, const char* name) {
        if (width * height > w * h) w = width, h = height, which = name;
    };
    consider(s.width_mm(), s.layer_height, "the");
    if (s.raft_layers > 0)
        consider(s.width_mm(), s.layer_thickness_mm(0), "the model's first layer's (on the raft)");
    const double feed = s.max_volumetric_speed / (w * h);
    if (feed < kMinFeed - 1e-9)
        throw InputError(fmt::format(
            "--max-volumetric-speed {} mm^3/s (a profile's max_volumetric_speed or "
            "filament_max_volumetric_speed) would print {} {} x {} mm lines at {:.3g} mm/s, "
            "under the {} mm/s a line is usefully printed at; expected 0 (no cap) or at least "
            "{} mm^3/s for these lines",
            plain_number(s.max_volumetric_speed), which, plain_number(w), plain_number(h), feed,
            plain_number(kMinFeed), plain_number(std::ceil(kMinFeed * w * h * 1000) / 1000)));
}

}  // namespace

void validate_settings(const Settings& s) {
    // A setting of the other scheme moved from its default: refused as the CLI refuses it.
    static const Settings defaults;
    for (const SettingSpec& spec : setting_table())
        if (spec.scheme && !spec.text() && spec.get(s) != spec.get(defaults)) check_scheme(spec, s);
    if (s.carving == CarvingScheme::Whole && s.whole_width == 0)
        throw UsageError(
            "--whole-width 0 would tear every part along its medial axis: that is the report's "
            "method, --carving report");
    for (const SettingSpec& spec : setting_table()) {
        if (spec.text()) continue;  // its parser checked it, and the bed is checked below
        const double v = spec.get(s);
        if (!(std::isfinite(v) && v >= spec.min && v <= spec.max))
            throw InputError(fmt::format(
                "{}: {} is out of range; expected from {} to {} {}",
                *spec.option ? std::string("--") + spec.option
                             : std::string("profile key '") + spec.ini_key + "'",
                plain_number(v), plain_number(spec.min), plain_number(spec.max), spec.unit));
    }
    auto bed = [](double v) { return std::isfinite(v) && v > 0 && v <= 10000; };
    if (!bed(s.bed_x) || !bed(s.bed_y))
        throw InputError(fmt::format("bed size {} x {} mm is out of range (0 to 10000 mm)",
                                     plain_number(s.bed_x), plain_number(s.bed_y)));
    if (s.extrusion_width > 0 && s.extrusion_width < 0.05)
        throw InputError(fmt::format(
            "--extrusion-width {} mm is too thin; expected 0 (the nozzle) or from 0.05 to 3 mm",
            plain_number(s.extrusion_width)));
    if (s.layer_height > s.width_mm())
        throw InputError(fmt::format("--layer-height {} mm is thicker than the {} mm line width",
                                     s.layer_height, s.width_mm()));
    check_first_layer(s);
    check_flow(s);
}

}  // namespace carve

// The setting table's text fields (setting_rows.hpp): the settings given as a word or a few
// numbers in one. Their lists of numbers ("10,25.5", "250x210") are read by one reader each.
#include <cmath>
#include <optional>
#include <sstream>
#include <string_view>

#include "base/numbers.hpp"
#include "config/bundle.hpp"
#include "config/setting_rows.hpp"

namespace carve {

namespace {

// "250x210": two plain decimal numbers either side of one of `crosses` (sscanf's %lf and strtod
// read "0x100" as hexadecimal 256), or nothing.
std::optional<std::pair<double, double>> decimal_pair(std::string_view text, const char* crosses) {
    const size_t cross = text.find_first_of(crosses);
    if (cross == std::string_view::npos) return std::nullopt;
    const std::optional<double> a = parse_decimal(text.substr(0, cross));
    const std::optional<double> b = parse_decimal(text.substr(cross + 1));
    if (!a || !b) return std::nullopt;
    return std::pair(*a, *b);
}

// "10,25.5": comma-separated decimal numbers from `min` to 10000, each refused as not `what`.
std::vector<double> decimal_list(const std::string& text, const std::string& source, double min,
                                 const char* what) {
    std::vector<double> values;
    std::stringstream ss(text);
    for (std::string item; std::getline(ss, item, ',');) {
        const std::optional<double> v = parse_decimal(trim_whitespace(item));
        if (!v || !(*v >= min && *v <= 10000))
            throw InputError(fmt::format("{}: '{}' is not {}", source, item, what));
        values.push_back(*v);
    }
    return values;
}

std::string join_numbers(const std::vector<double>& values) {
    std::string out;
    for (double v : values) {
        if (!out.empty()) out += ',';
        out += plain_number(v);
    }
    return out;
}

}  // namespace

namespace setting_rows {

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
        const auto xy = decimal_pair(text, "xX");
        if (!xy || !(xy->first > 0) || !(xy->second > 0) || xy->first > 10000 || xy->second > 10000)
            throw InputError(fmt::format(
                "{}: expected WIDTHxDEPTH in mm, each above 0 and at most 10000, such as "
                "250x210, got '{}'",
                source, text));
        s.bed_x = xy->first, s.bed_y = xy->second;
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
            const auto xy = decimal_pair(p, "x");
            if (!xy) throw InputError(fmt::format("{}: bad point '{}'", source, pt));
            min_x = std::min(min_x, xy->first), max_x = std::max(max_x, xy->first);
            min_y = std::min(min_y, xy->second), max_y = std::max(max_y, xy->second);
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

}  // namespace setting_rows

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
        const auto wh = decimal_pair(item, "x");
        auto side = [](double v) { return v >= 1 && v <= 1024 && v == std::floor(v); };
        if (!wh || !side(wh->first) || !side(wh->second))
            throw InputError(
                fmt::format("{}: '{}' is not a thumbnail size WxH (whole pixels from 1 to 1024)",
                            source, item));
        if (format != "PNG" && format != "png")
            throw InputError(fmt::format(
                "{}: thumbnail format '{}' is not supported; carve writes PNG", source, format));
        sizes.emplace_back(static_cast<int>(wh->first), static_cast<int>(wh->second));
        if (end == text.size()) break;
    }
    if (sizes.size() > 8)
        throw InputError(fmt::format("{}: {} thumbnail sizes; at most 8", source, sizes.size()));
    return sizes;
}

namespace setting_rows {

// Heights "10,25.5": mm of the model, each from 0 to 10000, at most 100 of them.
TextField pause_at_field() {
    TextField t;
    t.get = [](const Settings& s) { return join_numbers(s.pause_at); };
    t.set = [](Settings& s, const std::string& text, const std::string& source) {
        std::vector<double> zs =
            decimal_list(text, source, 0, "a height in mm from 0 to 10000 (Z[,Z..])");
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
    t.get = [](const Settings& s) { return join_numbers(s.cut_planes); };
    t.set = [](Settings& s, const std::string& text, const std::string& source) {
        std::vector<double> values = decimal_list(
            text, source, -10000, "a number from -10000 to 10000 (X,Y,Z,NX,NY,NZ[,..])");
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
}  // namespace setting_rows

}  // namespace carve

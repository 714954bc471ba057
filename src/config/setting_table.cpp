// The table of settings (see setting_table.hpp): made of its rows (setting_rows_*.cpp), read
// and written through SettingSpec, and the final validation of a run's settings.
#include "config/setting_table.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <type_traits>

#include "base/error.hpp"
#include "base/numbers.hpp"
#include "config/bundle.hpp"
#include "config/setting_rows.hpp"

namespace carve {

namespace {

// The rows in the table's order, from the files of their groups.
std::vector<SettingSpec> make_table() {
    std::vector<SettingSpec> table = setting_rows::print_rows();
    for (auto rows : {setting_rows::layer_rows, setting_rows::output_rows})
        for (SettingSpec& spec : rows()) table.push_back(std::move(spec));
    return table;
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

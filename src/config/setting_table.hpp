// One declaration per setting: its command-line option, PrusaSlicer profile key, unit, range
// and help text, with its default taken from Settings{} itself. The CLI's options and --help,
// the profile reader, the placeholders of custom G-code, the final validation, the stats JSON's
// settings and the HTML report's settings table are all made from this table, so a setting is
// added in one place and cannot be valid in one reader and unbounded in another (NaN, 1e20 and
// negative temperatures once came in through the profile while the CLI refused them), nor be
// left out of what a run reports about itself.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "config/settings.hpp"

namespace carve {

// A setting given as a word or a few numbers in one (--seam rear, --bed 250x210, --cavities
// auto): no member pointer can hold it, so it is read and written through these.
struct TextField {
    std::function<std::string(const Settings&)> get;
    // Parses and checks `text`; throws InputError naming `source`.
    std::function<void(Settings&, const std::string& text, const std::string& source)> set;
    std::vector<std::string> choices;  // the words it takes, when it is one of a few
    const char* type_name = "TEXT";    // what --help shows for its value
};

struct SettingSpec {
    const char* option;   // command-line long option without "--" ("layer-height")
    const char* ini_key;  // PrusaSlicer profile key and placeholder name, or "" for none
    const char* unit;     // as the help states it: "mm", "mm/s", "C", "layers" ...
    double min, max;      // inclusive; the value is refused outside
    // A bool is an on/off switch (an option without a value); the numbers take one.
    std::variant<double Settings::*, int Settings::*, long long Settings::*, bool Settings::*,
                 TextField>
        field;
    const char* help;  // the help text, ending with the default in brackets
    // A profile value holding '%' (PrusaSlicer's "50%" of another speed) keeps carve's own.
    bool profile_skips_percent = false;
    // CLI11's names of a switch when they are not just --option: a negation ("!--no-m73,--m73"),
    // or only a negation ("!--keep-all-bridges" turns prune-bridges off).
    const char* switch_names = "";
    // The identifier when it must differ from the option's (stats keys other tools read).
    const char* key = "";
    // How PrusaSlicer's files spell the value when carve's own words do not (gcode_flavor =
    // marlin2, bed_shape = 0x0,250x0,250x210,0x210, arc_fitting = emit_center): the G-code's
    // configuration block writes it, and the profile reader reads it under `ini_key`.
    std::optional<TextField> prusa = std::nullopt;
    // The carving scheme it belongs to, when it changes only one (--tear-limit, --whole-width):
    // given under the other it would do nothing, so it is refused (check_scheme()).
    std::optional<CarvingScheme> scheme = std::nullopt;

    bool text() const { return std::holds_alternative<TextField>(field); }
    const TextField& text_field() const { return std::get<TextField>(field); }
    // An option without a value: a bool, or a 0/1 setting with switch names (--m73, --no-m73).
    bool is_switch() const {
        return std::holds_alternative<bool Settings::*>(field) || *switch_names;
    }
    bool integer() const { return !std::holds_alternative<double Settings::*>(field); }
    bool flag() const { return std::string_view(unit) == "0/1"; }
    // The numeric value (a switch 0 or 1); not for a text setting.
    double get(const Settings& s) const;
    // The value as the help's [default] and the report state it: "0.2", "on", "rear", "250x210".
    std::string text_value(const Settings& s) const;
    // The value with its field's type, a 0/1 setting as a flag: for writers that keep types
    // (the stats JSON), where 2 and 2.0 or 1 and true are not the same. A text setting holding
    // a whole number is that number (--cavities 6, but "auto").
    std::variant<double, long long, bool, std::string> value(const Settings& s) const;
    // An identifier for writers that have no options: the key, the option, or the profile key of
    // a profile-only setting, with '_' for '-' ("layer_height", "machine_max_jerk_x").
    std::string name() const;
    // Its key in the G-code's configuration block: the profile key, else the name.
    std::string config_key() const;
    // The value as PrusaSlicer's files spell it: `prusa`, else as text_value() but a switch
    // 0 or 1 ("marlin2", "0x0,250x0,250x210,0x210", "rear", "1", "0.2").
    std::string prusa_text(const Settings& s) const;
    // Reads that spelling, checked as set() checks; throws InputError naming `source`.
    void set_prusa(Settings& s, const std::string& text, const std::string& source) const;
    // How a person finds it: "--option" when the command line has it, else the name.
    std::string label() const;
    // The CLI11 names of a switch ("--wipe", "!--no-m73,--m73").
    std::string cli_switch_names() const;
    // Parses `text` strictly (decimal, finite, whole for integers; a switch 0 or 1; a text
    // setting by its own parser) and checks the range; throws InputError
    // "<source>: 'text' is out of range; expected from A to B unit".
    void set(Settings& s, const std::string& text, const std::string& source) const;
};

const std::vector<SettingSpec>& setting_table();
const SettingSpec* find_setting_by_ini_key(const std::string& key);

// Thumbnail sizes: "16x16,220x124" (--thumbnails), or PrusaSlicer 2.6's "16x16/PNG, 220x124/PNG"
// (the profile key `thumbnails`); each side from 1 to 1024 pixels, at most 8 sizes, PNG only.
// Throws InputError naming `source`.
std::vector<std::pair<int, int>> parse_thumbnail_sizes(const std::string& text,
                                                       const std::string& source);

// "whole" or "report", as --carving spells it.
std::string scheme_name(CarvingScheme scheme);

// Throws UsageError naming the scheme `spec` needs when `s` carves with the other: an option
// that would do nothing is refused, never ignored. The CLI calls it for every option given.
void check_scheme(const SettingSpec& spec, const Settings& s);

// Checks every numeric setting of the table, the bed and what ties two settings together once
// more after the printer preset, the profile and the options were applied: the last word before
// a run starts.
void validate_settings(const Settings& s);

}  // namespace carve

// One declaration per numeric setting: its command-line option, PrusaSlicer profile key, unit,
// range and help text, with its default taken from Settings{} itself. The CLI's options and
// --help, the profile reader, the placeholders of custom G-code and the final validation are
// all made from this table, so a setting is added in one place and cannot be valid in one
// reader and unbounded in another (NaN, 1e20 and negative temperatures once came in through the
// profile while the CLI refused them).
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "config/settings.hpp"

namespace carve {

struct SettingSpec {
    const char* option;   // command-line long option without "--" ("layer-height")
    const char* ini_key;  // PrusaSlicer profile key and placeholder name, or "" for none
    const char* unit;     // as the help states it: "mm", "mm/s", "C", "layers" ...
    double min, max;      // inclusive; the value is refused outside
    std::variant<double Settings::*, int Settings::*, long long Settings::*> field;
    const char* help;  // the help text, ending with the default in brackets
    // A profile value holding '%' (PrusaSlicer's "50%" of another speed) keeps carve's own.
    bool profile_skips_percent = false;

    bool integer() const { return !std::holds_alternative<double Settings::*>(field); }
    bool flag() const { return std::string_view(unit) == "0/1"; }
    double get(const Settings& s) const;
    // The value with its field's type, a 0/1 setting as a flag: for writers that keep types
    // (the stats JSON), where 2 and 2.0 or 1 and true are not the same.
    std::variant<double, long long, bool> value(const Settings& s) const;
    // An identifier for writers that have no options: the option, or the profile key of a
    // profile-only setting, with '_' for '-' ("layer_height", "machine_max_jerk_x").
    std::string name() const;
    // Parses `text` strictly (decimal, finite, whole for integers) and checks the range; throws
    // InputError "<source>: 'text' is out of range; expected from A to B unit".
    void set(Settings& s, const std::string& text, const std::string& source) const;
};

const std::vector<SettingSpec>& setting_table();
const SettingSpec* find_setting_by_ini_key(const std::string& key);

// Thumbnail sizes: "16x16,220x124" (--thumbnails), or PrusaSlicer 2.6's "16x16/PNG, 220x124/PNG"
// (the profile key `thumbnails`); each side from 1 to 1024 pixels, at most 8 sizes, PNG only.
// Throws InputError naming `source`.
std::vector<std::pair<int, int>> parse_thumbnail_sizes(const std::string& text,
                                                       const std::string& source);

// Checks every setting of the table (and the few the table does not hold) once more after the
// printer preset, the profile and the options were applied: the last word before a run starts.
void validate_settings(const Settings& s);

}  // namespace carve

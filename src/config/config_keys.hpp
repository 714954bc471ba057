// The keys of PrusaSlicer's files that are no rows of the setting table (setting_table.hpp):
// the custom G-code texts, and the values only the G-code's configuration block states. Declared
// here once for the profile reader and the block's writer.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "config/settings.hpp"

namespace carve {

// Values the G-code's configuration block states that are no settings of the table: internal
// (restriction_factor) or not an option (printer_name). Kept out of the table
// because everything in it is an option or profile key, a stats JSON key and a report row, and
// those must not change.
struct ConfigOnlyValue {
    const char* key;
    std::function<std::string(const Settings&)> get;
};
const std::vector<ConfigOnlyValue>& config_only_values();

// The custom G-code texts, under PrusaSlicer's keys: read from a profile, written in the
// configuration block, in this order.
struct CustomGcodeKey {
    const char* ini_key;
    std::string Settings::*text;
    bool string_list;  // per extruder ("a";"b"): the first one is carve's
};
const std::vector<CustomGcodeKey>& custom_gcode_keys();

// PrusaSlicer's one-line spelling of a multi-line text (\n, \\) and back. Escaping drops the
// final line end carve's texts carry and PrusaSlicer's do not; unescaping puts it back.
std::string escape_profile_text(const std::string& text);
std::string unescape_profile_text(const std::string& value);

}  // namespace carve

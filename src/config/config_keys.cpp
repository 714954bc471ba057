// The keys of PrusaSlicer's files beside the setting table (config_keys.hpp).
#include "config/config_keys.hpp"

#include "base/numbers.hpp"

namespace carve {

using S = Settings;

const std::vector<ConfigOnlyValue>& config_only_values() {
    static const std::vector<ConfigOnlyValue> list = {
        {"restriction_factor", [](const S& s) { return plain_number(s.restriction_factor); }},
        {"opening_factor", [](const S& s) { return plain_number(s.opening_factor); }},
        {"bridge_angle_step", [](const S& s) { return plain_number(s.bridge_angle_step); }},
        {"printer_name", [](const S& s) { return s.printer_name; }},
        // Written, but a profile's is not read (the loading note names it): carve's bridges
        // are sized for its own flow.
        {"bridge_flow_ratio", [](const S& s) { return plain_number(s.bridge_flow); }},
        // What hosts show of the filament and the printer (Moonraker's filament_type,
        // filament_name, filament_colors; PrusaSlicer's printer check), the profile's when one
        // was loaded. An id without a preset is "" as PrusaSlicer writes it.
        {"filament_type", [](const S& s) { return s.filament_type; }},
        {"filament_settings_id",
         [](const S& s) {
             return s.filament_settings_id.empty() ? std::string("\"\"") : s.filament_settings_id;
         }},
        {"filament_colour", [](const S& s) { return s.filament_colour; }},
        {"printer_model", [](const S& s) { return s.printer_model; }},
    };
    return list;
}

const std::vector<CustomGcodeKey>& custom_gcode_keys() {
    static const std::vector<CustomGcodeKey> list = {
        {"start_gcode", &S::start_gcode, false},
        {"end_gcode", &S::end_gcode, false},
        {"start_filament_gcode", &S::start_filament_gcode, true},
        {"end_filament_gcode", &S::end_filament_gcode, true},
        {"before_layer_gcode", &S::before_layer_gcode, false},
        {"layer_gcode", &S::layer_gcode, false},
    };
    return list;
}

std::string escape_profile_text(const std::string& text) {
    std::string out;
    for (char c : text) {
        if (c == '\n')
            out += "\\n";
        else if (c == '\r')
            continue;
        else if (c == '\\')
            out += "\\\\";
        else
            out += c;
    }
    while (out.size() >= 2 && out.compare(out.size() - 2, 2, "\\n") == 0)
        out.resize(out.size() - 2);
    return out;
}

std::string unescape_profile_text(const std::string& v) {
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

}  // namespace carve

// The setting table's rows, in three groups of the table's order (setting_rows_*.cpp), and the
// text fields they declare (setting_fields.cpp). Internal to config: setting_table() is the one
// list the rest of carve reads. Ranges are physical bounds, wide enough for every real printer and
// narrow enough that nothing downstream overflows: a nozzle or layer of 0.001 mm or 1e20 mm
// reaches the micrometre integers as 0 or INT64_MIN.
#pragma once

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "base/error.hpp"
#include "config/setting_table.hpp"

namespace carve::setting_rows {

using S = Settings;

inline constexpr CarvingScheme kWhole = CarvingScheme::Whole;
inline constexpr CarvingScheme kReport = CarvingScheme::Report;

// A setting that changes only `scheme`'s carving.
inline SettingSpec only(CarvingScheme scheme, SettingSpec spec) {
    spec.scheme = scheme;
    return spec;
}

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

TextField cavities_field();       // a number or "auto"
TextField bed_field();            // WxH
TextField bed_shape_field();      // PrusaSlicer's bed_shape outline
TextField flavor_prusa();         // PrusaSlicer's gcode_flavor
TextField first_layer_prusa();    // PrusaSlicer's first_layer_height
TextField thumbnails_field();     // WxH,WxH
TextField pause_at_field();       // Z[,Z..]
TextField pause_command_field();  // one G-code line
TextField cut_field();            // Z[,Z..] or "auto"
TextField cut_plane_field();      // X,Y,Z,NX,NY,NZ[,..]

// The table in order: what is printed and on what (--layer-height to --orient), the layers'
// shapes and paths (skirt and brim to the wipe), and the output (cooling to thumbnails).
std::vector<SettingSpec> print_rows();
std::vector<SettingSpec> layer_rows();
std::vector<SettingSpec> output_rows();

}  // namespace carve::setting_rows

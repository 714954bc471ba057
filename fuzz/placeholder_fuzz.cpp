// libFuzzer target: the placeholder expander of custom G-code. The input is "NOTES\0GCODE":
// NOTES becomes the profile's printer_notes (conditions match regular expressions on it),
// GCODE is expanded; without a NUL the whole input is the G-code. Seeds: the start and end
// G-code of PrusaSlicer's vendor bundle with real printer notes (fuzz/make_seeds.py).
// The expander reports what it cannot evaluate; it must never crash or recurse without bound,
// no raw placeholder may reach a line that is not a comment, and the one exception it may throw
// is InputError: the refusal of a figure it computed beyond the machine's range (M190 S215).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "base/error.hpp"
#include "gcode/placeholders.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    const size_t nul = bytes.find('\0');
    carve::Settings settings;
    std::string gcode(bytes);
    if (nul != std::string_view::npos) {
        settings.profile_values["printer_notes"] = std::string(bytes.substr(0, nul));
        gcode = std::string(bytes.substr(nul + 1));
    }
    settings.profile_values["printer_model"] = "MK3S";
    settings.profile_values["extruder_colour"] = "\"#FF8000\";\"\"";
    carve::ExpandedGcode e;
    try {
        e = carve::expand_custom_gcode(gcode, settings, {{"layer_z", 1}});
    } catch (const carve::InputError&) {
        return 0;  // refused, with its message (HostileFigures.* test what it says)
    }
    // The marker of an unexpanded placeholder never survives into the text.
    if (e.text.find('\x01') != std::string::npos) std::abort();
    return 0;
}

// libFuzzer target: the PrusaSlicer .ini reader, then the final validation and the expansion
// of the profile's start and end G-code with the values read (what `slice --load` does before
// slicing). Seeds: the sections of PrusaSlicer's own vendor bundle (fuzz/make_seeds.py).
// Only InputError may escape: from the reader, the validation, or the expander when a figure it
// computes is beyond the machine's range (M140 S600), a refusal with its message.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "base/error.hpp"
#include "config/profiles.hpp"
#include "config/setting_table.hpp"
#include "gcode/placeholders.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
    carve::Settings settings;
    try {
        carve::read_prusa_profile(in, "fuzz.ini", settings);
        carve::validate_settings(settings);
    } catch (const carve::InputError&) {
        return 0;  // a clear refusal is a correct answer
    }
    try {
        carve::expand_custom_gcode(settings.start_gcode, settings);
        carve::expand_custom_gcode(settings.end_gcode, settings,
                                   {{"max_layer_z", 10}, {"layer_z", 10}, {"layer_num", 49}});
    } catch (const carve::InputError&) {
        return 0;  // refused naming the key (HostileFigures.* test what it says)
    }
    return 0;
}

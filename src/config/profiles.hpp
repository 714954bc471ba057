// Printer and filament settings from outside the command line: built-in printer presets and
// PrusaSlicer .ini profiles, so that people can bring the printer they already use.
#pragma once

#include <string>
#include <vector>

#include "config/settings.hpp"

namespace carve {

std::string printer_preset_names();  // "mk3s, ender3, klipper, generic"
// Throws InputError for an unknown name.
void apply_printer_preset(const std::string& name, Settings& settings);

// Reads the keys carve uses from a PrusaSlicer config bundle or exported .ini; returns notes
// for the user (keys ignored). Throws InputError naming the key for an invalid value, or for an
// unreadable file.
std::vector<std::string> load_prusa_profile(const std::string& path, Settings& settings);

}  // namespace carve

// Printer and filament settings from outside the command line: built-in printer presets and
// PrusaSlicer .ini profiles, so that people can bring the printer they already use.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

#include "config/bundle.hpp"
#include "config/settings.hpp"

namespace carve {

std::string printer_preset_names();  // "mk3s, ender3, klipper, generic"
// Throws InputError for an unknown name.
void apply_printer_preset(const std::string& name, Settings& settings);

struct ProfileOptions {
    ProfileChoice choice;         // the bundle's presets to use (--printer-profile, ...)
    bool profile_shells = false;  // --profile-shells: solid layers and perimeters become
                                  // carve's covers and shells (else carve keeps its own)
};

// Reads the keys carve uses from a PrusaSlicer config bundle (only the selected presets,
// resolved through `inherits`) or exported .ini; returns notes for the user: the profile's
// covers and shells not applied, and by name the keys that change the print that carve ignores.
// Throws InputError naming the file, line, section and key for an invalid value, or for an
// unreadable file.
std::vector<std::string> load_prusa_profile(const std::string& path, Settings& settings,
                                            const ProfileOptions& options = {});
// The same from text already read (`name` names it in messages); the fuzz target's entry.
std::vector<std::string> read_prusa_profile(std::istream& in, const std::string& name,
                                            Settings& settings, const ProfileOptions& options = {});

}  // namespace carve

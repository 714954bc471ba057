// PrusaSlicer .ini files as carve reads them: a flat "Export config" file, or a config bundle of
// [printer:NAME], [filament:NAME] and [print:NAME] sections with `inherits = a; b` and a
// [presets] section naming the selected ones (PrusaSlicer's own user bundles and the vendor
// bundles in /usr/share/PrusaSlicer/profiles/). Only the selected presets, resolved through
// their parents, come out: an abstract *common* section is never read on its own.
#pragma once

#include <iosfwd>
#include <map>
#include <string>

namespace carve {

// The presets to take from a bundle by name; "" = the bundle's [presets] entry, else the
// printer's default_filament_profile / default_print_profile, else the only one there is.
struct ProfileChoice {
    std::string printer, filament, print;
};

struct IniValue {
    std::string value;
    int line = 0;
    std::string section;  // where it was written: "filament:*PLA*", "" in a flat file
    std::string owner;    // the selected preset it reached: "filament:Prusament PLA", or ""
};

struct ResolvedProfile {
    bool bundle = false;                     // false: a flat exported configuration
    std::string printer, filament, print;    // the selected names ("" when the bundle has none)
    std::map<std::string, IniValue> values;  // print, then filament, then printer keys
};

// Throws InputError: a line that is not `key = value` (naming its line), an unknown or
// abstract selected name (listing the names available), an inherits cycle or missing parent
// (naming the section).
ResolvedProfile read_ini_profile(std::istream& in, const std::string& path,
                                 const ProfileChoice& choice);

// PrusaSlicer's string lists: `"first";"second"` -> first, unescaped; a bare value unchanged.
std::string first_quoted(const std::string& value);

// `s` without the blanks around it (spaces, tabs, line ends), as the .ini readers take keys and
// values.
std::string trim_whitespace(std::string s);

}  // namespace carve

// The settings of a run from what its command line gave, in the documented precedence: carve's
// defaults, then the built-in printer, then the PrusaSlicer profile, then the print preset, then
// the options as typed (DESIGN.md). The CLI parses; this resolves, so that a program linking
// carve gets the settings `carve slice` would from the same values.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "config/profiles.hpp"
#include "config/setting_table.hpp"
#include "config/settings.hpp"

namespace carve {

struct GivenSettings {
    std::optional<std::string> printer;  // --printer; given even empty ("" is refused, not generic)
    std::string profile_path;            // --load; "" for none
    ProfileOptions profile;              // --printer-profile ... --profile-shells; need --load
    std::string preset;                  // --preset; "" for none
    // The setting table's options in the order they apply, the later winning: as typed
    // ({&layer-height's row, "0.15"}), a switch as "1" or "0".
    std::vector<std::pair<const SettingSpec*, std::string>> options;
};

struct ResolvedSettings {
    Settings settings;
    std::vector<std::string> notes;  // the profile's notes for the user (load_prusa_profile())
};

// Applies `given` in order of precedence, then --strong to the shells and ties the options did
// not set, then checks that no option belongs to the other carving scheme. `model_slenderness`
// (slenderness() of the model as loaded) is asked only when the strength comes to above 0.
// Throws InputError for a bad name, file or value, UsageError for profile choices without
// --load or an option of the other scheme. validate_settings() is left to the caller: the last
// word before the run, once whatever else it checks (the custom G-code) is said.
ResolvedSettings resolve_settings(const GivenSettings& given,
                                  const std::function<double()>& model_slenderness);

}  // namespace carve

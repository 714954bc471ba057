// Print presets and the strength scale (see presets.hpp).
#include "config/presets.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "base/error.hpp"

namespace carve {

std::string print_preset_names() {
    return "2c0s, 3c1s, strong";
}

void apply_print_preset(const std::string& name, Settings& settings) {
    if (name == "2c0s")
        settings.covers = 2, settings.shells = 0;
    else if (name == "3c1s")
        settings.covers = 3, settings.shells = 1;
    else if (name == "strong")
        settings.strength = 1;
    else
        throw InputError(
            fmt::format("unknown preset '{}'; choose one of: {}", name, print_preset_names()));
}

StrengthStep strength_step(double strength) {
    if (!(strength > 0)) return {};
    // Every step carves with the report's scheme: its nested walls are the first, cheapest
    // gain (fandisk: +1.3 g for +11 % compression), the shells the rest.
    return {static_cast<int>(std::lround(std::min(strength, 1.0) * kStrongShells)),
            CarvingScheme::Report};
}

void apply_strength(Settings& settings, bool shells_given, bool carving_given) {
    if (!(settings.strength > 0)) return;
    const StrengthStep step = strength_step(settings.strength);
    if (!shells_given) settings.shells = step.shells;
    if (!carving_given) settings.carving = step.carving;
}

}  // namespace carve

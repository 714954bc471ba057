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

double slenderness(double height_mm, double volume_mm3) {
    if (!(height_mm > 0) || !(volume_mm3 > 0)) return 0;
    return height_mm / std::sqrt(volume_mm3 / height_mm);
}

StrengthStep strength_step(double strength, double slenderness) {
    if (!(strength > 0)) return {};
    const double s = std::min(strength, 1.0);
    // Measured (bench/results/strength.md): under the top's sideways push a squat part shears,
    // and webs across its interior carry that per gram better than shells; a slender one
    // bends, and the shells, far from its middle, carry it; in compression both do alike.
    if (slenderness >= kSlender) return {static_cast<int>(std::lround(s * kSlenderShells)), 0.0};
    return {static_cast<int>(std::lround(s * kSquatShells)), kStrongTieSpacingMm / s};
}

void apply_strength(Settings& settings, double slenderness, bool shells_given, bool ties_given) {
    if (!(settings.strength > 0)) return;
    const StrengthStep step = strength_step(settings.strength, slenderness);
    if (!shells_given) settings.shells = step.shells;
    if (!ties_given) settings.tie_spacing = step.tie_spacing_mm;
}

}  // namespace carve

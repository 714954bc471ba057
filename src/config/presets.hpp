// Print presets (--preset) and the strength scale between carve's default and the strong
// preset (--strong, issue 49). The strong preset is what measurement picked (bench/strength.py,
// bench/results/strength.md): walls tied across the cavity (--ties) and two shells on a squat
// part, where the top's sideways load shears the interior; four shells and no ties on a
// slender one, where it bends the part and material far from the middle counts most.
#pragma once

#include <string>

#include "config/settings.hpp"

namespace carve {

std::string print_preset_names();  // "2c0s, 3c1s, strong"
// 2c0s and 3c1s set covers and shells; strong sets --strong 1. Throws InputError for an
// unknown name.
void apply_print_preset(const std::string& name, Settings& settings);

// A model's slenderness: its height over the side of its mean section, h / sqrt(V / h), the
// same at every scale. skull 2.2, fandisk 2.7, cat 4.6, elephant 4.7, man 8.9.
double slenderness(double height_mm, double volume_mm3);
// At or above it a part counts as slender. Measured on the five shared models
// (bench/results/strength.md): on cat and elephant four shells are stiffer than two shells and
// ties in every column, for less material; on fandisk and skull the ties are. 4 is a round
// value in the gap between 2.7 and 4.6, not fitted to it.
inline constexpr double kSlender = 4.0;
// --strong 1: on a squat part ties this far apart and kSquatShells shells, on a slender one
// kSlenderShells shells.
inline constexpr double kStrongTieSpacingMm = 5.5;
inline constexpr int kSquatShells = 2;
inline constexpr int kSlenderShells = 4;

// What --strong S resolves to: 0 is carve's default (whatever the settings already hold);
// above it round(S x shells) shells and, on a squat part, ties at kStrongTieSpacingMm / S (so
// the ties' material grows in proportion to S). S is a ratio of the strong preset's interior:
// each step holds all the material of the one below, so the steps are monotone in grams.
struct StrengthStep {
    int shells = 0;
    double tie_spacing_mm = 0;  // 0: no ties
};
StrengthStep strength_step(double strength, double slenderness);

// Applies settings.strength to shells and ties, except to those the command line gave (they
// win): called once every option is in. Nothing changes at strength 0.
void apply_strength(Settings& settings, double slenderness, bool shells_given, bool ties_given);

}  // namespace carve

// Print presets (--preset) and the strength scale between carve's default and the strong
// preset (--strong, issue 49). The strong preset is what measurement picked (bench/strength.py,
// bench/results/strength.md): of the existing options, a thicker outer wall and the report's
// nested single-filament cavity walls stiffen a hollow part most for its weight.
#pragma once

#include <string>

#include "config/settings.hpp"

namespace carve {

std::string print_preset_names();  // "2c0s, 3c1s, strong"
// 2c0s and 3c1s set covers and shells; strong sets --strong 1. Throws InputError for an
// unknown name.
void apply_print_preset(const std::string& name, Settings& settings);

// What --strong S resolves to: 0 is carve's default (whatever shells and scheme the settings
// already hold); above it the report's carving and round(4 S) shells, so 1 = --preset strong.
// Each step holds all the material of the one below, so the steps are monotone in grams.
inline constexpr int kStrongShells = 4;
struct StrengthStep {
    int shells = 0;
    CarvingScheme carving = CarvingScheme::Whole;
};
StrengthStep strength_step(double strength);

// Applies settings.strength to shells and carving, except to those the command line gave
// (they win): called once every option is in. Nothing changes at strength 0.
void apply_strength(Settings& settings, bool shells_given, bool carving_given);

}  // namespace carve

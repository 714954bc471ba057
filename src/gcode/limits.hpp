// The machine limits of the settings, written at the start of the G-code (M201 accelerations,
// M203 speeds, M204 print/retract/travel accelerations, M205 jerk or junction deviation) and
// handed to the estimate, so that the time stated is the one a firmware obeying those very
// lines takes.
#pragma once

#include <string>
#include <vector>

#include "config/settings.hpp"
#include "gcode/motion.hpp"

namespace carve {

// What the planner of the estimate obeys.
MachineLimits machine_limits(const Settings& settings);

// The lines to write (none for Klipper, whose limits live in printer.cfg: it takes the print
// and travel accelerations as M204 S as the moves change instead). RepRapFirmware's M203 is in
// mm/min.
std::vector<std::string> machine_limit_lines(const Settings& settings);

// The speed the firmware lets a filament-only move (retraction) reach.
double retract_speed_limit(const Settings& settings);

}  // namespace carve

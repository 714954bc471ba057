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

// The planner of the estimate: with --silent-mode and stealth limits, it times every move in
// the stealth mode too (M73 Q/S; the stealth limits replace the X/Y ones of the normal mode).
MotionPlanner estimate_planner(const Settings& settings);

// Whether a feed rate carve commands (any print speed, travel, `z_speed` for layer changes, the
// retraction) is above the M203 limit of its axis, so that the firmware's cap changes the motion.
bool feed_limits_bind(const Settings& settings, double z_speed);

// The lines to write (none for Klipper, whose limits live in printer.cfg: it takes the print
// and travel accelerations as M204 S as the moves change instead). RepRapFirmware's M203 is in
// mm/min. M203 is written only where it binds (feed_limits_bind), else a comment states it:
// PrusaSlicer's G-code viewer reads M203 in mm/min from any file it did not make itself, and
// then times carve's file at 4 to 10 times its length (cat: 3 h 48 min for 57 min). Where no
// commanded feed reaches the limit the line changes no move, and the estimate is the same.
std::vector<std::string> machine_limit_lines(const Settings& settings, double z_speed);

// The acceleration a move asks for (the print's or the travel's) as carve writes and plans it.
// Klipper takes M204 S as it comes, beyond printer.cfg's max_accel too: there it is held to the
// machine's limit (machine_max_acceleration_x/y, which the klipper preset sets to that
// max_accel). Marlin and RepRap cap each axis by the M201 they were given, so theirs stays.
double commanded_acceleration(const Settings& settings, double accel);

// The speed the firmware lets a filament-only move (retraction) reach.
double retract_speed_limit(const Settings& settings);

}  // namespace carve

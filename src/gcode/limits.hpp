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
// and travel accelerations as M204 S as the moves change instead; see switches_acceleration).
// RepRapFirmware's M203 is in mm/min. M203 is written only where it binds (feed_limits_bind), else
// a comment states it: PrusaSlicer's G-code viewer reads M203 in mm/min from any file it did not
// make itself, and then times carve's file at 4 to 10 times its length (cat: 3 h 48 min for 57
// min). Where no commanded feed reaches the limit the line changes no move, and the estimate is the
// same.
std::vector<std::string> machine_limit_lines(const Settings& settings, double z_speed);

// The acceleration a move asks for (the print's or the travel's) as carve writes and plans it.
// Klipper takes M204 S as it comes, beyond printer.cfg's max_accel too: there it is held to the
// machine's limit (machine_max_acceleration_x/y, which the klipper preset sets to that
// max_accel). Marlin and RepRap cap each axis by the M201 they were given, so theirs stays.
double commanded_acceleration(const Settings& settings, double accel);

// Whether the print and travel accelerations are written as M204 S as the moves change. Klipper
// reads nothing else: M204 P500 T1000 is min(P, T) to it, every move at 500 (toolhead.py's
// cmd_M204). Marlin and Prusa firmware read S as both their print and travel acceleration, so a
// Marlin file whose two differ switches S too and reads the same on either firmware (the M204
// P R T line stays, for the retraction's R). RepRapFirmware reads P and T only: told once.
bool switches_acceleration(const Settings& settings);

// The speed the firmware lets a filament-only move (retraction) reach.
double retract_speed_limit(const Settings& settings);

// How long a filament-only move of the retraction's length takes as the firmware runs it, from
// and to rest (its E jerk with classic jerk): at M204 R within M201 E on Marlin and RepRap; on
// Klipper at max_extrude_only_velocity and max_extrude_only_accel, which default to printer.cfg's
// max_velocity and max_accel (machine_max_feedrate_x, machine_max_acceleration_x) times the
// nozzle's 4 x d^2 over the filament's cross-section (extruder.py), whatever M204 S says.
double retract_time(const Settings& settings);

// How long a Z move of dz mm at z_speed takes: within M203 Z and M201 Z, which Klipper holds
// too (max_z_velocity, max_z_accel), at the acceleration `accel` in force.
double z_move_time(const Settings& settings, double dz, double z_speed, double accel);

}  // namespace carve

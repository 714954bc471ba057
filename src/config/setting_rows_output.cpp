// The setting table's rows (setting_rows.hpp), in the table's order. The output: cooling, the
// machine limits, arcs, M73, pauses, cuts and thumbnails.
#include "config/setting_rows.hpp"

namespace carve::setting_rows {

std::vector<SettingSpec> output_rows() {
    return {
        // Cooling (PrusaSlicer's keys and meanings).
        {"cooling", "cooling", "0/1", 0, 1, &S::cooling,
         "Automatic cooling: slow down short layers and raise the fan for them, 0/1 [1]"},
        {"min-layer-time", "slowdown_below_layer_time", "seconds", 0.0, 3600.0,
         &S::slowdown_below_layer_time,
         "A layer that would print faster is slowed down to take this long, seconds [5]"},
        {"min-print-speed", "min_print_speed", "mm/s", 1.0, 1000.0, &S::min_print_speed,
         "Slowing down for the minimum layer time stops at this speed, mm/s [10]"},
        {"fan-always-on", "fan_always_on", "0/1", 0, 1, &S::fan_always_on,
         "Keep the fan at least at the minimum speed on every layer, 0/1 [1]"},
        {"min-fan-speed", "min_fan_speed", "%", 0, 100, &S::min_fan_speed,
         "Fan speed for layers that take long enough, % [100]"},
        {"max-fan-speed", "max_fan_speed", "%", 0, 100, &S::max_fan_speed,
         "Fan speed for the shortest layers, % [100]"},
        {"bridge-fan-speed", "bridge_fan_speed", "%", 0, 100, &S::bridge_fan_speed,
         "Fan speed while printing bridges, % [100]"},
        {"fan-below-layer-time", "fan_below_layer_time", "seconds", 0.0, 3600.0,
         &S::fan_below_layer_time,
         "The fan rises from the minimum towards the maximum speed on layers shorter than "
         "this, seconds [60]"},
        {"disable-fan-first-layers", "disable_fan_first_layers", "layers", 0, 1000,
         &S::disable_fan_first_layers, "The fan stays off on this many first layers, layers [1]"},
        // Machine limits: profile keys only (PrusaSlicer's printer settings).
        {"", "machine_max_acceleration_x", "mm/s^2", 1.0, 100000.0, &S::max_acceleration_x,
         "Machine limit M201 X, mm/s^2 [3000]"},
        {"", "machine_max_acceleration_y", "mm/s^2", 1.0, 100000.0, &S::max_acceleration_y,
         "Machine limit M201 Y, mm/s^2 [3000]"},
        {"", "machine_max_acceleration_z", "mm/s^2", 1.0, 100000.0, &S::max_acceleration_z,
         "Machine limit M201 Z, mm/s^2 [200]"},
        {"", "machine_max_acceleration_e", "mm/s^2", 1.0, 100000.0, &S::max_acceleration_e,
         "Machine limit M201 E, mm/s^2 [5000]"},
        {"", "machine_max_acceleration_retracting", "mm/s^2", 1.0, 100000.0,
         &S::retract_acceleration, "Retraction acceleration M204 R, mm/s^2 [1500]"},
        {"", "machine_max_feedrate_x", "mm/s", 1.0, 10000.0, &S::max_feedrate_x,
         "Machine limit M203 X, mm/s [500]"},
        {"", "machine_max_feedrate_y", "mm/s", 1.0, 10000.0, &S::max_feedrate_y,
         "Machine limit M203 Y, mm/s [500]"},
        {"", "machine_max_feedrate_z", "mm/s", 0.1, 10000.0, &S::max_feedrate_z,
         "Machine limit M203 Z, mm/s [12]"},
        {"", "machine_max_feedrate_e", "mm/s", 0.1, 10000.0, &S::max_feedrate_e,
         "Machine limit M203 E, mm/s [120]"},
        {"", "machine_max_jerk_x", "mm/s", 0.0, 1000.0, &S::max_jerk_x,
         "Machine limit M205 X (classic jerk), mm/s [8]"},
        {"", "machine_max_jerk_y", "mm/s", 0.0, 1000.0, &S::max_jerk_y,
         "Machine limit M205 Y (classic jerk), mm/s [8]"},
        {"", "machine_max_jerk_z", "mm/s", 0.0, 1000.0, &S::max_jerk_z,
         "Machine limit M205 Z (classic jerk), mm/s [0.4]"},
        {"", "machine_max_jerk_e", "mm/s", 0.0, 1000.0, &S::max_jerk_e,
         "Machine limit M205 E (classic jerk), mm/s [4.5]"},
        {"", "machine_max_junction_deviation", "mm", 0.0, 1.0, &S::junction_deviation,
         "Junction deviation M205 J (Marlin 2); 0 = classic jerk, mm [0.013]"},
        // PrusaSlicer's spelling in the configuration block, but not read from a profile: a
        // profile turning arcs on could not be overruled, the option having no negation.
        {"arc-fitting", "", "0/1", 0, 1, &S::arc_fitting,
         "Write G2/G3 arcs where a path follows a circle within --arc-tolerance; the firmware "
         "must accept arcs (Klipper: [gcode_arcs]) [off]",
         false, "", "", words(&S::arc_fitting, {"disabled", "emit_center"})},
        {"arc-tolerance", "", "mm", 0.001, 0.2, &S::arc_tolerance,
         "With --arc-fitting, how far an arc may leave the path it replaces, mm [0.02]"},
        // The stats have always called it by its profile key.
        {"m73", "remaining_times", "0/1", 0, 1, &S::m73,
         "Write M73 progress and remaining time for printer screens and hosts; --no-m73: none, "
         "whatever the printer [off; on with --printer mk3s or ender3]",
         false, "!--no-m73,--m73", "remaining_times"},
        {"silent-mode", "silent_mode", "0/1", 0, 1, &S::silent_mode,
         "The printer has a stealth mode: M73 also writes Q/S, the figures its screen shows "
         "there, timed with --stealth-max-acceleration and --stealth-max-feedrate [off; on "
         "with --printer mk3s]",
         false, "!--no-silent-mode,--silent-mode"},
        {"stealth-max-acceleration", "", "mm/s^2", 0.0, 100000.0, &S::stealth_max_acceleration,
         "With --silent-mode: the stealth mode's X and Y acceleration limit that M73 Q/S are "
         "timed with (a profile's second machine_max_acceleration_x/y), mm/s^2 [0 = the "
         "normal limits; 960 with --printer mk3s]"},
        {"stealth-max-feedrate", "", "mm/s", 0.0, 10000.0, &S::stealth_max_feedrate,
         "With --silent-mode: the stealth mode's X and Y speed limit (a profile's second "
         "machine_max_feedrate_x/y), mm/s [0 = the normal limits; 100 with --printer mk3s]"},
        {"pause-at", "", "mm", 0, 0, pause_at_field(),
         "Pause before the first layer at or above each height, mm of the model (with --cut, of "
         "each plate): M600 (filament change) on Marlin and RepRap, PAUSE on Klipper, retracted "
         "and lifted 5 mm before it and back after it [none]"},
        {"pause-command", "", "", 0, 0, pause_command_field(),
         "The command --pause-at writes: a G-code or a macro's name (M601, M0, PAUSE, "
         "M600; Klipper's PAUSE needs its pause_resume section and a PAUSE macro) [none: "
         "M600 on Marlin and RepRap, PAUSE on Klipper]"},
        {"cut", "", "mm", 0, 0, cut_field(),
         "Cut the model across z at these heights above its bottom, mm, or 'auto' (the fewest "
         "cuts that fit every piece on the bed, where the cut faces are smallest); the pieces "
         "print on plates, one G-code each [none]"},
        {"cut-plane", "", "mm", 0, 0, cut_plane_field(),
         "Cut the model by planes in any direction: a point (mm from the least x, y and z corner "
         "of the model's box) and a normal each, X,Y,Z,NX,NY,NZ, groups comma-joined; each "
         "piece lies on its largest cut face [none]"},
        {"cut-connectors", "", "", 0, 0, words(&S::cut_connectors, {"none", "dowel", "pin"}),
         "What joins the pieces of --cut: dowel (holes in both faces), pin (a pin on the piece "
         "below, a hole in the one above) or none [dowel]"},
        {"dowel-diameter", "", "mm", 1.0, 50.0, &S::dowel_diameter,
         "With --cut: the diameter of a dowel or pin, mm [5]"},
        {"dowel-depth", "", "mm", 1.0, 100.0, &S::dowel_depth,
         "With --cut: the depth of each connector hole, mm [6]"},
        {"connector-clearance", "", "mm", 0.0, 2.0, &S::connector_clearance,
         "With --cut: added to the radius of a hole around a dowel or pin, mm [0.15]"},
        {"thumbnails", "thumbnails", "", 0, 0, thumbnails_field(),
         "PNG previews of the model in the header, PrusaSlicer's format, sizes WxH,WxH (e.g. "
         "16x16,220x124) [none; 16x16,220x124 with --printer mk3s, 32x32,400x300 with --printer "
         "klipper]"},
    };
}

}  // namespace carve::setting_rows

// Machine limits: the M-codes and the planner's view of them (limits.hpp).
#include "gcode/limits.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <numbers>

#include "base/numbers.hpp"

namespace carve {

MachineLimits machine_limits(const Settings& s) {
    MachineLimits m;
    m.accel_x = s.max_acceleration_x;
    m.accel_y = s.max_acceleration_y;
    m.feed_x = s.max_feedrate_x;
    m.feed_y = s.max_feedrate_y;
    m.jerk_x = s.max_jerk_x;
    m.jerk_y = s.max_jerk_y;
    m.junction_deviation = s.junction_deviation;
    if (s.flavor == GcodeFlavor::Klipper) {
        // Klipper corners by its square corner velocity, not by what a G-code says; carve's
        // limits only describe the estimate there.
        m.accel_x = m.accel_y = m.feed_x = m.feed_y = MachineLimits::kNone;
        // And its estimate plans as Klipper's lookahead, with the defaults that its stock
        // configs (kit-voron2-250mm.cfg among them) keep.
        m.square_corner_velocity = kKlipperSquareCornerVelocity;
        m.min_cruise_ratio = kKlipperMinCruiseRatio;
        m.extruder_corner_velocity = kKlipperExtruderCornerVelocity;
    }
    return m;
}

MotionPlanner estimate_planner(const Settings& s) {
    const MachineLimits normal = machine_limits(s);
    if (!s.silent_mode || (s.stealth_max_acceleration <= 0 && s.stealth_max_feedrate <= 0))
        return MotionPlanner(normal);
    MachineLimits stealth = normal;
    if (s.stealth_max_acceleration > 0)
        stealth.accel_x = stealth.accel_y = s.stealth_max_acceleration;
    if (s.stealth_max_feedrate > 0) stealth.feed_x = stealth.feed_y = s.stealth_max_feedrate;
    return MotionPlanner(normal, stealth);
}

double commanded_acceleration(const Settings& s, double accel) {
    if (s.flavor != GcodeFlavor::Klipper) return accel;
    return std::min({accel, s.max_acceleration_x, s.max_acceleration_y});
}

bool switches_acceleration(const Settings& s) {
    if (s.flavor == GcodeFlavor::Klipper) return true;
    return s.flavor == GcodeFlavor::Marlin && s.acceleration != s.travel_acceleration;
}

double retract_speed_limit(const Settings& s) {
    return s.flavor == GcodeFlavor::Klipper ? s.retract_speed
                                            : std::min(s.retract_speed, s.max_feedrate_e);
}

double retract_time(const Settings& s) {
    if (s.retract_length <= 0) return 0;
    if (s.flavor == GcodeFlavor::Klipper) {
        const double filament_area =
            std::numbers::pi * s.filament_diameter * s.filament_diameter / 4;
        const double ratio = 4 * s.nozzle * s.nozzle / filament_area;
        const double v = std::min(s.retract_speed, s.max_feedrate_x * ratio);
        return trapezoid_time(s.retract_length, 0, v, 0, s.max_acceleration_x * ratio);
    }
    const double v = retract_speed_limit(s);
    const double rest = s.junction_deviation > 0 ? 0 : std::min(v, s.max_jerk_e);
    return trapezoid_time(s.retract_length, rest, v, rest,
                          std::min(s.retract_acceleration, s.max_acceleration_e));
}

double z_move_time(const Settings& s, double dz, double z_speed, double accel) {
    return trapezoid_time(dz, 0, std::min(z_speed, s.max_feedrate_z), 0,
                          std::min(accel, s.max_acceleration_z));
}

bool feed_limits_bind(const Settings& s, double z_speed) {
    // Each feature's speed is capped by max_print_speed where that is set; the wipe moves at
    // most at the travel speed.
    double print = std::max(
        {s.perimeter_speed, s.cover_speed, s.cavity_speed, s.bridge_speed, s.first_layer_speed});
    if (s.max_print_speed > 0) print = std::min(print, s.max_print_speed);
    const double xy = std::max(print, s.travel_speed);
    return xy > std::min(s.max_feedrate_x, s.max_feedrate_y) || z_speed > s.max_feedrate_z ||
           (!s.firmware_retraction && s.retract_speed > s.max_feedrate_e);
}

std::vector<std::string> machine_limit_lines(const Settings& s, double z_speed) {
    if (s.flavor == GcodeFlavor::Klipper) return {};
    auto n = [](double v) { return plain_number(v); };
    const double feed_unit = s.flavor == GcodeFlavor::RepRap ? 60.0 : 1.0;
    std::vector<std::string> out;
    out.push_back(fmt::format("M201 X{} Y{} Z{} E{} ; sets maximum accelerations, mm/sec^2",
                              n(s.max_acceleration_x), n(s.max_acceleration_y),
                              n(s.max_acceleration_z), n(s.max_acceleration_e)));
    if (feed_limits_bind(s, z_speed))
        out.push_back(fmt::format("M203 X{} Y{} Z{} E{} ; sets maximum feedrates, {}",
                                  n(s.max_feedrate_x * feed_unit), n(s.max_feedrate_y * feed_unit),
                                  n(s.max_feedrate_z * feed_unit), n(s.max_feedrate_e * feed_unit),
                                  feed_unit == 1.0 ? "mm / sec" : "mm / min"));
    else
        out.push_back(fmt::format(
            "; maximum feedrates X{} Y{} Z{} E{} mm/sec, above every feed "
            "rate of this file: no M203",
            n(s.max_feedrate_x), n(s.max_feedrate_y), n(s.max_feedrate_z), n(s.max_feedrate_e)));
    out.push_back(
        fmt::format("M204 P{} R{} T{} ; sets acceleration (P, T) and retract "
                    "acceleration (R), mm/sec^2",
                    n(s.acceleration), n(s.retract_acceleration), n(s.travel_acceleration)));
    if (s.junction_deviation > 0)
        out.push_back(
            fmt::format("M205 J{} ; sets the junction deviation, mm", n(s.junction_deviation)));
    else
        out.push_back(fmt::format("M205 X{} Y{} Z{} E{} ; sets the jerk limits, mm/sec",
                                  n(s.max_jerk_x), n(s.max_jerk_y), n(s.max_jerk_z),
                                  n(s.max_jerk_e)));
    return out;
}

}  // namespace carve

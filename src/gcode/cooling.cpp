// Fan speeds and the slowdown of short layers (cooling.hpp).
#include "gcode/cooling.hpp"

#include <algorithm>
#include <cmath>

namespace carve {

int layer_fan_percent(const Settings& s, int layer, double t) {
    if (layer - s.first_print_layer() < s.disable_fan_first_layers) return 0;
    int fan = s.fan_always_on ? s.min_fan_speed : 0;
    if (!s.cooling) return fan;
    if (t < s.slowdown_below_layer_time) {
        fan = s.max_fan_speed;
    } else if (t < s.fan_below_layer_time) {
        // From min_fan_speed at fan_below_layer_time up to max_fan_speed at the minimum time.
        const double span = s.fan_below_layer_time - s.slowdown_below_layer_time;
        const double f = span > 0 ? (s.fan_below_layer_time - t) / span : 1.0;
        fan = static_cast<int>(
            std::lround(s.min_fan_speed + (s.max_fan_speed - s.min_fan_speed) * f));
    }
    return std::clamp(fan, 0, 100);
}

int bridge_fan_percent(const Settings& s, int layer) {
    return layer - s.first_print_layer() < s.disable_fan_first_layers ? 0 : s.bridge_fan_speed;
}

bool needs_slowdown(const Settings& s, double t) {
    return s.cooling && t > 0 && t < s.slowdown_below_layer_time;
}

double slowed_speed(double speed, double factor, double min_print_speed) {
    if (factor >= 1) return speed;
    return std::max(speed * factor, std::min(speed, min_print_speed));
}

double next_speed_factor(double full_s, double factor, double tried_s, double target_s) {
    double next = factor * 0.5;
    if (factor < 1 && tried_s > full_s) {
        const double b = (tried_s - full_s) / (1 / factor - 1);  // the part that scales
        const double a = full_s - b;                             // the part that does not
        if (b > 0 && target_s > a) next = b / (target_s - a);
    }
    // Always slower than the factor that fell short, and not absurdly so in one step.
    return std::clamp(next, factor * 0.25, factor * 0.98);
}

}  // namespace carve

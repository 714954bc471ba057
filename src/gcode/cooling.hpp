// Cooling as PrusaSlicer does it: a layer that would print in less than the minimum layer time
// (slowdown_below_layer_time) has its extrusions slowed down until it lasts that long, but no
// extrusion below min_print_speed; the fan follows the layer time (min_fan_speed with
// fan_always_on, rising to max_fan_speed between fan_below_layer_time and the minimum layer
// time), bridges run at bridge_fan_speed, and the first disable_fan_first_layers layers have
// no fan. The emitter times a layer as written, then writes it again slower when it is short
// (cooling's figures are the emitter's own estimate, so the slowed layer's time is the one the
// estimate states).
#pragma once

#include "config/settings.hpp"

namespace carve {

// The fan for a layer's ordinary extrusions, percent, from the layer's time at full speed.
int layer_fan_percent(const Settings& s, int layer_index, double layer_time_s);
// The fan while bridging on that layer, percent.
int bridge_fan_percent(const Settings& s, int layer_index);

// Is the layer, timed at full speed, to be slowed down?
bool needs_slowdown(const Settings& s, double layer_time_s);

// A speed after slowing down by `factor` (<= 1): not below min_print_speed, and a speed already
// below it is left alone.
double slowed_speed(double speed, double factor, double min_print_speed);

// The next factor to try. The layer took `full_s` at factor 1 and `tried_s` at `factor`;
// modelling its time as a + b / factor (fixed travels plus scaled extrusions), the factor that
// would make it last `target_s`, and always less than `factor` while the target is not met.
double next_speed_factor(double full_s, double factor, double tried_s, double target_s);

}  // namespace carve

// PrusaSlicer's placeholders in custom start and end G-code ([first_layer_temperature],
// {nozzle_diameter[0]}, {if layer_height < 0.075}...{else}...{endif}, arithmetic with min/max),
// expanded from the run's Settings so that a profile's G-code means on carve what it meant there.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "config/settings.hpp"

namespace carve {

struct ExpandedGcode {
    std::string text;
    // One entry per placeholder or condition carve could not evaluate. The line holding it is
    // written as a comment rather than sent to the printer with the raw placeholder in it; an
    // {if} whose condition cannot be evaluated counts as false.
    std::vector<std::string> unresolved;
    // Lines written as the profile has them that set a temperature or fan speed beyond the
    // machine's range (PrusaSlicer passes them through too; said once).
    std::vector<std::string> notes;
};

// A line of expanded custom G-code that sets a temperature (M104, M109: 0 to 450 C; M140,
// M190: 0 to 150 C, the ranges of the temperature settings) or a fan speed (M106: 0 to 255)
// beyond its range: what it sets and the range, else empty.
std::string figure_beyond_range(const std::string& line);

// Values come first from the fields of `settings` (so command-line options win over the
// profile), then from `runtime` (max_layer_z, layer_z, ... known while writing), then from the
// raw values of the loaded profile (settings.profile_values).
ExpandedGcode expand_custom_gcode(const std::string& text, const Settings& settings,
                                  const std::map<std::string, double>& runtime = {});

}  // namespace carve

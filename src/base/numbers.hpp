// Strict reading of numbers typed by a user or found in a profile: plain decimal notation only
// (no hexadecimal "0x100", no "nan" or "inf", no trailing text), finite. std::stod and
// sscanf("%lf") accept all of those, and NaN then slips through every "x < min" range check.
// Bottom layer: depends on nothing else of carve.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace carve {

// A finite decimal number ("12", "-0.5", "1e-3", "+2"), or nothing.
std::optional<double> parse_decimal(std::string_view text);

// Why `text` is not a number in [min, max] (empty if it is); `integer` also needs a whole
// number. `unit` is named in the message ("mm", "C").
std::string range_problem(std::string_view text, double min, double max, bool integer,
                          std::string_view unit);

// "0.01", "1000", "5e+06" -> the shortest decimal form, as in the help's ranges.
std::string plain_number(double v);

}  // namespace carve

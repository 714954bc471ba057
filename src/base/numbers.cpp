// Strict decimal numbers (see numbers.hpp).
#include "base/numbers.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <cstdio>

namespace carve {

std::optional<double> parse_decimal(std::string_view t) {
    if (!t.empty() && t.front() == '+') t.remove_prefix(1);
    if (t.empty() || t.size() > 400) return std::nullopt;
    // from_chars reads "inf", "nan" and "infinity"; only digits, '.', sign and exponent count.
    for (char c : t)
        if (!((c >= '0' && c <= '9') || c == '.' || c == '-' || c == 'e' || c == 'E' || c == '+'))
            return std::nullopt;
    double d = 0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), d);
    if (ec != std::errc() || end != t.data() + t.size() || !std::isfinite(d)) return std::nullopt;
    return d;
}

std::string plain_number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.10g", v);
    return buf;
}

std::string range_problem(std::string_view text, double min, double max, bool integer,
                          std::string_view unit) {
    const std::string shown =
        text.size() > 40 ? fmt::format("{}...", text.substr(0, 40)) : std::string(text);
    const std::string range = fmt::format("from {} to {}{}{}", plain_number(min), plain_number(max),
                                          unit.empty() ? "" : " ", unit);
    const std::optional<double> d = parse_decimal(text);
    if (!d)
        return fmt::format("'{}' is not a {} number; expected {}", shown,
                           integer ? "whole" : "decimal", range);
    if (integer && *d != std::floor(*d))
        return fmt::format("'{}' is not a whole number; expected {}", shown, range);
    if (*d < min || *d > max) return fmt::format("'{}' is out of range; expected {}", shown, range);
    return {};
}

}  // namespace carve

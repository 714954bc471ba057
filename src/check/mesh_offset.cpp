// The --mesh-offset parser (see mesh_offset.hpp).
#include "check/mesh_offset.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string_view>
#include <vector>

#include "base/error.hpp"
#include "base/numbers.hpp"

namespace carve {

Vec3 parse_mesh_offset(const std::string& text) {
    std::vector<std::optional<double>> parts;
    for (size_t at = 0;;) {
        const size_t comma = text.find(',', at);
        const auto v = parse_decimal(std::string_view(text).substr(at, comma - at));
        parts.push_back(v && std::abs(*v) <= 1e5 ? v : std::nullopt);
        if (comma == std::string::npos) break;
        at = comma + 1;
    }
    const bool good =
        (parts.size() == 2 || parts.size() == 3) &&
        std::all_of(parts.begin(), parts.end(), [](const auto& v) { return v.has_value(); });
    if (!good)
        throw InputError(fmt::format(
            "--mesh-offset: expected X,Y or X,Y,Z in mm (decimal, at most 100000), got '{}'",
            text));
    Vec3 o{*parts[0], *parts[1], std::numeric_limits<double>::quiet_NaN()};
    if (parts.size() == 3) o.z = *parts[2];
    return o;
}

}  // namespace carve

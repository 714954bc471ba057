// Object labels (labels.hpp).
#include "gcode/labels.hpp"

#include <fmt/format.h>

#include "gcode/safe_text.hpp"

namespace carve {

std::string object_label(const std::string& model_path) {
    std::string stem = model_path.substr(model_path.find_last_of('/') + 1);
    if (const size_t dot = stem.rfind('.'); dot != std::string::npos && dot > 0) stem.resize(dot);
    return label_text(stem);
}

std::vector<std::string> object_definition(const Settings& s, const std::string& given, double x0,
                                           double y0, double x1, double y1, int count) {
    const std::string name = label_text(given);
    if (s.flavor == GcodeFlavor::Klipper)
        return {
            fmt::format("EXCLUDE_OBJECT_DEFINE NAME={} CENTER={:.3f},{:.3f} "
                        "POLYGON=[[{:.3f},{:.3f}],[{:.3f},{:.3f}],[{:.3f},{:.3f}],[{:.3f},{:."
                        "3f}]]",
                        name, (x0 + x1) / 2, (y0 + y1) / 2, x0, y0, x1, y0, x1, y1, x0, y1)};
    return {fmt::format("M486 T{} ; objects to label", count)};
}

std::vector<std::string> object_start(const Settings& s, const std::string& given, int id,
                                      bool first) {
    const std::string name = label_text(given);
    std::vector<std::string> out{fmt::format("; printing object {}", name)};
    if (s.flavor == GcodeFlavor::Klipper) {
        out.push_back(fmt::format("EXCLUDE_OBJECT_START NAME={}", name));
    } else {
        out.push_back(fmt::format("M486 S{}", id));
        if (first) out.push_back(fmt::format("M486 A{}", name));
    }
    return out;
}

std::vector<std::string> object_end(const Settings& s, const std::string& given) {
    const std::string name = label_text(given);
    std::vector<std::string> out;
    if (s.flavor == GcodeFlavor::Klipper)
        out.push_back(fmt::format("EXCLUDE_OBJECT_END NAME={}", name));
    else
        out.push_back("M486 S-1");
    out.push_back(fmt::format("; stop printing object {}", name));
    return out;
}

}  // namespace carve

// Outside text made safe for the G-code (safe_text.hpp).
#include "gcode/safe_text.hpp"

#include <fmt/format.h>

namespace carve {

std::string comment_text(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (const char c : text) {
        const unsigned char u = static_cast<unsigned char>(c);
        if ((u >= 0x20 && u != 0x7f) || c == '\t') {
            out += c;
        } else if (c == '\n') {
            out += "\\n";
        } else if (c == '\r') {
            out += "\\r";
        } else if (c == '\0') {
            out += "\\0";
        } else {
            out += fmt::format("\\x{:02x}", u);
        }
    }
    return out;
}

std::string label_text(std::string_view name) {
    std::string out(name);
    for (char& c : out) {
        const bool keep = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                          (c >= '0' && c <= '9') || c == '_' || c == '-' || c == '.';
        if (!keep) c = '_';
    }
    return out.empty() ? "object" : out;
}

}  // namespace carve

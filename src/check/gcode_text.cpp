// G-code text for carve check (see gcode_text.hpp).
#include "check/gcode_text.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <vector>

#include "base/error.hpp"
#include "base/numbers.hpp"

namespace carve {

namespace check {

bool starts_with(std::string_view s, std::string_view prefix) {
    return s.size() >= prefix.size() && s.compare(0, prefix.size(), prefix) == 0;
}

std::string_view trim(std::string_view s) {
    size_t b = s.find_first_not_of(" \t\r");
    if (b == std::string_view::npos) return {};
    size_t e = s.find_last_not_of(" \t\r");
    return s.substr(b, e - b + 1);
}

bool parse_number(std::string_view s, double& value, size_t* used) {
    size_t skip = (!s.empty() && s[0] == '+') ? 1 : 0;
    const char* begin = s.data() + skip;
    auto [ptr, ec] = std::from_chars(begin, s.data() + s.size(), value);
    if (ec != std::errc() || !std::isfinite(value)) return false;
    if (used) *used = static_cast<size_t>(ptr - s.data());
    return true;
}

bool find_header_value(std::string_view text, std::string_view key, double& value) {
    size_t pos = 0;
    while ((pos = text.find(key, pos)) != std::string_view::npos) {
        size_t line_start = text.rfind('\n', pos);
        line_start = line_start == std::string_view::npos ? 0 : line_start + 1;
        std::string_view before = trim(text.substr(line_start, pos - line_start));
        if (before == ";" && parse_number(trim(text.substr(pos + key.size(), 32)), value))
            return true;
        pos += key.size();
    }
    return false;
}

namespace {

// PrusaSlicer prints its configuration at the end of the file and Cura (Griffin) at the start,
// so header values are looked for in both ends before the single pass: the filament diameter
// (under PrusaSlicer's key or Cura's) and the nozzle's (`nozzle_diameter`, which carve writes
// too, or Cura's), 0 when absent.
struct HeaderValues {
    double filament_diameter = 0, nozzle_diameter = 0;
};

HeaderValues header_values(std::FILE* f) {
    HeaderValues found;
    auto read_at = [&](long offset, size_t size) {
        std::string text(size, '\0');
        std::fseek(f, offset, SEEK_SET);
        text.resize(std::fread(text.data(), 1, size, f));
        return text;
    };
    // A pipe (carve check - < file, /dev/stdin) cannot seek: no header look-up, the option's
    // diameter holds, and the lines are read as they come.
    if (std::fseek(f, 0, SEEK_END) != 0) return found;
    long size = std::ftell(f);
    if (size < 0) return found;
    constexpr long kHead = 64 * 1024, kTail = 512 * 1024;
    std::string head = read_at(0, static_cast<size_t>(std::min(size, kHead)));
    std::string tail = size > kHead
                           ? read_at(std::max(kHead, size - kTail),
                                     static_cast<size_t>(size - std::max(kHead, size - kTail)))
                           : std::string();
    std::fseek(f, 0, SEEK_SET);
    for (const std::string* text : {&head, &tail}) {
        double v = 0;
        if (found.filament_diameter <= 0 &&
            (find_header_value(*text, "filament_diameter =", v) ||
             find_header_value(*text, "EXTRUDER_TRAIN.0.MATERIAL.DIAMETER:", v)))
            found.filament_diameter = std::max(v, 0.0);
        v = 0;
        if (found.nozzle_diameter <= 0 &&
            (find_header_value(*text, "nozzle_diameter =", v) ||
             find_header_value(*text, "EXTRUDER_TRAIN.0.NOZZLE.DIAMETER:", v)))
            found.nozzle_diameter = std::max(v, 0.0);
    }
    return found;
}

}  // namespace

GcodeFile open_gcode(const std::string& path, const GcodeAnalysisOptions& options, double& diameter,
                     std::string& source, double* nozzle) {
    GcodeFile file(std::fopen(path.c_str(), "rb"));
    if (!file) throw InputError("cannot open G-code file '" + path + "'");
    diameter = options.filament_diameter_mm;
    source = "option";
    const HeaderValues header = header_values(file.get());
    // Only a plausible nozzle is taken (PrusaSlicer's own range); otherwise none is known.
    if (nozzle)
        *nozzle = header.nozzle_diameter >= 0.05 && header.nozzle_diameter <= 3
                      ? header.nozzle_diameter
                      : 0;
    if (options.filament_diameter_from_header) {
        const double from_header = header.filament_diameter;
        if (from_header > 0) {
            // The same range as --filament-diameter: a header is as hostile as an option can be.
            if (!(from_header >= 0.5 && from_header <= 5))
                throw InputError(
                    "'" + path + "': the header's filament diameter " + plain_number(from_header) +
                    " mm is outside 0.5 to 5 mm; give --filament-diameter to measure it anyway");
            diameter = from_header;
            source = "header";
        }
    }
    if (!(diameter > 0)) throw InputError("filament diameter must be positive");
    return file;
}

constexpr size_t kMaxLineBytes = 1 << 20;
// The file is streamed, so its size bounds the time, not the memory: 4 GB is ten times the
// largest real G-code seen (a 400 MB PrusaSlicer file of a full bed) and minutes of reading.
constexpr long long kMaxGcodeBytes = 4LL << 30;

void feed_lines(std::FILE* file, const std::string& path,
                const std::function<void(std::string_view)>& line) {
    std::vector<char> buffer(1 << 20);
    std::string carry;
    size_t n;
    long long total = 0;
    // A line ends at a line feed, a carriage return (old Mac files end lines with it alone) or
    // both; "\r\n" is one end, even split across two blocks.
    bool after_cr = false;
    while ((n = std::fread(buffer.data(), 1, buffer.size(), file)) > 0) {
        total += static_cast<long long>(n);
        if (total > kMaxGcodeBytes)
            throw InputError("'" + path +
                             "' is larger than 4 GB; carve check reads G-code up to 4 GB");
        std::string_view chunk(buffer.data(), n);
        size_t start = 0;
        if (after_cr && chunk[0] == '\n') start = 1;
        after_cr = false;
        size_t end;
        while ((end = chunk.find_first_of("\r\n", start)) != std::string_view::npos) {
            if (!carry.empty()) {
                carry.append(chunk.substr(start, end - start));
                line(carry);
                carry.clear();
            } else {
                line(chunk.substr(start, end - start));
            }
            start = end + 1;
            if (chunk[end] == '\r') {
                if (start < chunk.size() && chunk[start] == '\n')
                    ++start;
                else if (start == chunk.size())
                    after_cr = true;
            }
        }
        carry.append(chunk.substr(start));
        // A file without line ends would otherwise be held whole; PrusaSlicer's longest lines
        // (its configuration, a thumbnail's base64) are a few kB.
        if (carry.size() > kMaxLineBytes)
            throw InputError("'" + path + "' has a line longer than 1 MB: not G-code");
    }
    if (!carry.empty()) line(carry);
    if (std::ferror(file)) throw InputError("cannot read G-code file '" + path + "'");
}

}  // namespace check

double parse_duration_s(std::string_view text) {
    double total = 0;
    bool any = false;
    size_t i = 0;
    while (i < text.size()) {
        if (!(std::isdigit(static_cast<unsigned char>(text[i])) || text[i] == '.')) {
            ++i;
            continue;
        }
        double v = 0;
        size_t used = 0;
        if (!check::parse_number(text.substr(i), v, &used)) {
            ++i;
            continue;
        }
        i += used;
        while (i < text.size() && text[i] == ' ') ++i;
        char unit = i < text.size() ? text[i] : 's';
        double scale = unit == 'd' ? 86400 : unit == 'h' ? 3600 : unit == 'm' ? 60 : 1;
        total += v * scale;
        any = true;
        if (i < text.size()) ++i;
    }
    return any ? total : -1;
}

}  // namespace carve

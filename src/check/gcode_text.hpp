// Reading G-code text for carve check: lines from a file or a pipe, header values as
// PrusaSlicer and CuraEngine write them. Internal to src/check.
#pragma once

#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

#include "check/gcode_analysis.hpp"

namespace carve::check {

bool starts_with(std::string_view s, std::string_view prefix);
std::string_view trim(std::string_view s);
// Leading number of s (a '+' sign allowed); false if none.
bool parse_number(std::string_view s, double& value, size_t* used = nullptr);
// The value after "key" in the first line of `text` that starts with it (after ';' and spaces).
bool find_header_value(std::string_view text, std::string_view key, double& value);

struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
};
using GcodeFile = std::unique_ptr<std::FILE, FileCloser>;

// Opens the file and settles the filament diameter (header or option) and where it came from;
// `nozzle`, when given, gets the header's nozzle diameter (mm, 0 when the file does not say).
GcodeFile open_gcode(const std::string& path, const GcodeAnalysisOptions& options, double& diameter,
                     std::string& source, double* nozzle = nullptr);
// Every line of the file, without its newline, in order.
void feed_lines(std::FILE* file, const std::string& path,
                const std::function<void(std::string_view)>& line);

}  // namespace carve::check

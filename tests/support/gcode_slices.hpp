// What the printer tests share: carve's G-code of a model as text, dated by SOURCE_DATE_EPOCH
// so that two runs compare byte for byte, its lines, and the words of a line.
#pragma once

#include <gtest/gtest.h>
#include <stdlib.h>

#include <cctype>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "support/carve_run.hpp"

namespace carve::test {

// `carve slice MODEL -o NAME.gcode -q ARGS`, its G-code (empty unless it exited 0); a status
// other than `want_status` fails the test, and `err` receives what it said.
inline std::string slice_text(const std::string& model, const std::string& args,
                              const std::string& name, int want_status = 0,
                              std::string* err = nullptr) {
    setenv("SOURCE_DATE_EPOCH", "1767225600", 1);
    const std::filesystem::path out = scratch() / (name + ".gcode");
    const CarveRun r = run_carve("slice " + model + " -o " + out.string() + " -q " + args);
    EXPECT_EQ(r.status, want_status) << r.err;
    if (err) *err = r.err;
    return r.status == 0 ? read(out) : std::string();
}

inline std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> out;
    std::stringstream in(text);
    for (std::string l; std::getline(in, l);) out.push_back(l);
    return out;
}

// The words of a G-code line before its comment: 'G' -> 1, 'X' -> 10.5 ...
inline std::map<char, double> words(const std::string& line) {
    std::map<char, double> w;
    std::stringstream in(line.substr(0, line.find(';')));
    for (std::string t; in >> t;)
        if (t.size() >= 2 && std::isalpha(static_cast<unsigned char>(t[0]))) {
            try {
                w[char(std::toupper(t[0]))] = std::stod(t.substr(1));
            } catch (...) {
            }
        }
    return w;
}

}  // namespace carve::test

// What the printer tests share: carve's G-code of a model as text, dated by SOURCE_DATE_EPOCH
// so that two runs compare byte for byte, and its lines.
#pragma once

#include <gtest/gtest.h>
#include <stdlib.h>

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

}  // namespace carve::test

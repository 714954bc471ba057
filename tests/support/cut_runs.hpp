// What the tests of --cut's library run share: a box written as an STL into the scratch folder,
// the run's options with its G-code and stats beside it there, and what a refused run says and
// leaves behind.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "run/pipeline.hpp"
#include "support/carve_run.hpp"
#include "support/stl_boxes.hpp"

namespace carve::test {

inline RunOptions cut_options(const std::string& model, const std::string& out) {
    RunOptions o;
    o.model_path = model;
    o.gcode_path = (scratch() / (out + ".gcode")).string();
    o.stats_path = (scratch() / (out + ".json")).string();
    return o;
}

inline std::string box_model(const std::string& name, float x, float y, float z) {
    std::vector<StlTriangle> t;
    add_box(t, 0, 0, 0, x, y, z);
    return write_stl(name, t).string();
}

// The message of the Error run_cut(s, o) throws; a test failure, and "", when it throws none.
template <class Error>
std::string refusal(const Settings& s, const RunOptions& o) {
    try {
        run_cut(s, o);
    } catch (const Error& e) {
        return e.what();
    }
    ADD_FAILURE() << "run_cut threw no error";
    return {};
}

// The scratch folder's files whose names start with `stem`, or hold a temporary's suffix: what
// a refused run must not have left.
inline std::vector<std::string> left_behind(const std::string& stem) {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(scratch())) {
        const std::string name = entry.path().filename().string();
        if (name.rfind(stem, 0) == 0 || name.find(".carve-tmp") != std::string::npos)
            names.push_back(name);
    }
    return names;
}

}  // namespace carve::test

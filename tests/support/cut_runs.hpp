// What the tests of --cut's library run share: a box written as an STL into the scratch folder,
// and the run's options with its G-code and stats beside it there.
#pragma once

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

}  // namespace carve::test

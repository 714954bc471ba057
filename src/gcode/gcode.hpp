// G-code assembly. The sweep produces layers top down while the printer needs them bottom up:
// each finished layer is written to a temporary spill file and the output is assembled in
// reverse at the end, into a temporary name renamed only when complete.
#pragma once

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "config/settings.hpp"
#include "toolpath/toolpath.hpp"

namespace carve {

struct PrintStats {
    double extruded_volume_mm3 = 0;
    double filament_length_mm = 0;
    double filament_weight_g = 0;
    double estimated_print_time_s = 0;
    double travel_length_mm = 0;
    int retractions = 0;
    int layers = 0;
    double bridge_length_mm = 0;
};

class GcodeWriter {
public:
    // `offset_mm` is added to every XY point (centres the model on the bed); z values are nozzle
    // heights above the bed.
    GcodeWriter(std::string output_path, const Settings& settings, double offset_x_mm,
                double offset_y_mm, int layer_count);
    ~GcodeWriter();  // removes the temporary files if finish() was not reached
    GcodeWriter(const GcodeWriter&) = delete;
    GcodeWriter& operator=(const GcodeWriter&) = delete;

    // Layers arrive top down (index n-1 first); each is turned into text and spilled.
    void add_layer(const LayerToolpaths& layer);
    // Writes header, layers bottom up and footer, then renames into place.
    PrintStats finish(const std::vector<std::string>& header_comments);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace carve

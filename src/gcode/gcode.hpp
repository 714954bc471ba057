// G-code assembly. The sweep produces layers top down while the printer needs them bottom up:
// each finished layer is written to a temporary spill file and the output is assembled in
// reverse at the end, into a temporary name renamed only when complete.
#pragma once

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "config/settings.hpp"
#include "gcode/labels.hpp"
#include "toolpath/toolpath.hpp"

namespace carve {

class OutputGroup;

struct PrintStats {
    double extruded_volume_mm3 = 0;
    double filament_length_mm = 0;
    double filament_weight_g = 0;
    double estimated_print_time_s = 0;
    // The same moves timed under the stealth mode's limits (--silent-mode); the normal time
    // without stealth limits.
    double estimated_stealth_time_s = 0;
    double travel_length_mm = 0;
    int retractions = 0;
    int layers = 0;
    double bridge_length_mm = 0;
    long long arcs = 0;                 // G2/G3 moves written (--arc-fitting)
    long long lines_saved_by_arcs = 0;  // G1 lines they replace, less one each
};

class GcodeWriter {
  public:
    // `offset_mm` is added to every XY point (centres the model on the bed); z values are nozzle
    // heights above the bed. `layer_count` counts the print's layers, a raft's included: they
    // are indexed from settings.first_print_layer().
    GcodeWriter(std::string output_path, const Settings& settings, double offset_x_mm,
                double offset_y_mm, int layer_count);
    ~GcodeWriter();  // removes the temporary files if finish() was not reached
    GcodeWriter(const GcodeWriter&) = delete;
    GcodeWriter& operator=(const GcodeWriter&) = delete;

    // Layers arrive in any order (the sweep's top down); each is turned into text and spilled.
    void add_layer(const LayerToolpaths& layer);
    // finish() leaves the complete file to `group` (renamed with the run's other outputs)
    // instead of renaming it at once.
    void commit_with(OutputGroup& group);
    // The object's label ("; printing object NAME", EXCLUDE_OBJECT, M486), already made safe
    // for the hosts (gcode/labels.hpp object_label); "object" when empty.
    void set_object_name(const std::string& name);
    // Several objects (--copies): each labelled on its own; see Emitter::set_objects.
    void set_objects(std::vector<ObjectLabel> objects);
    // Comment lines for the header, the thumbnails' blocks (gcode/thumbnail.hpp).
    void set_thumbnails(std::vector<std::string> lines);
    // Threads for finish() (1 by default); the file is the same for every count.
    void set_threads(int threads);
    // How finish() went: the chunks of layers it wrote side by side, those of them whose
    // second guess of the state before them held, those it wrote again because neither guess
    // did, the thread CPU of the chunks written side by side, and the rest of finish() (on the
    // calling thread alone).
    struct ChunkCount {
        int chunks = 0, second_guesses = 0, written_again = 0;
        double parallel_cpu_s = 0, serial_cpu_s = 0;
    };
    ChunkCount chunk_count() const;
    // Writes header, layers bottom up and footer, then renames into place.
    PrintStats finish(const std::vector<std::string>& header_comments);
    // Where the complete file is after finish(): its temporary name while `group` holds it back,
    // else the output path. Reading the G-code back before the group commits goes through here.
    const std::string& written_path() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// A duration for people, as the G-code header writes it: "1d 2h 3m 4s", "2h 3m 4s", "3m 4s",
// "4s". The summary and the HTML report use it too, so that the figures read alike.
std::string format_duration(double seconds);

}  // namespace carve

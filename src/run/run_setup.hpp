// What the run does before its layers flow (private to src/run): the mesh as it is sliced
// (loaded, scaled, copied), the limits that refuse a run before slicing starts or as its slices
// are cut, and the objects the G-code labels. Kept out of pipeline.cpp, which wires the filters.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "config/settings.hpp"
#include "gcode/gcode.hpp"
#include "mesh/mesh.hpp"
#include "report/run_result.hpp"
#include "run/pipeline.hpp"
#include "slice/slicer.hpp"

namespace carve {

// The mesh the run slices, loaded (a triangle soup refused), scaled about its bottom centre and
// arranged in copies; result.mesh describes it, its warnings told through `note`.
struct RunMesh {
    Mesh mesh;
    BBox3 loaded_box;                 // before scaling: the 3MF items' frame
    std::vector<CopyBox> copy_boxes;  // one per copy, when there are several
};
RunMesh load_run_mesh(const Settings& settings, const RunOptions& options, RunResult& result,
                      const std::function<void(const std::string&)>& note);

// Refuses a model larger than the bed (unless --no-bed-check), or too large for the line width
// and layer height.
void check_run_size(const Settings& settings, const RunOptions& options, const BBox3& box);

// The vertex limits, checked on each slice in order as it is cut; empty when there are none.
std::function<void(const Slice&)> vertex_limits(const Settings& settings,
                                                const RunOptions& options);

// Names the G-code's objects: the model, each copy, or each item of a 3MF plate.
void label_objects(GcodeWriter& writer, const RunOptions& options, const Settings& settings,
                   const RunMesh& run_mesh, const RunResult& result);

}  // namespace carve

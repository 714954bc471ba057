// What the run does before its layers flow (private to src/run): the mesh as it is sliced
// (loaded, scaled, copied), the limits that refuse a run before slicing starts or as its slices
// are cut, the objects the G-code labels, and the run's output files. Kept out of pipeline.cpp,
// which calls the stages in order.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "base/atomic_file.hpp"
#include "config/settings.hpp"
#include "gcode/gcode.hpp"
#include "mesh/mesh.hpp"
#include "report/html_report.hpp"
#include "report/run_result.hpp"
#include "report/svg.hpp"
#include "resin/raster.hpp"
#include "run/pipeline.hpp"
#include "slice/slicer.hpp"
#include "toolpath/skirt.hpp"

namespace carve {

// The mesh the run slices, loaded (a triangle soup refused), scaled about its bottom centre and
// arranged in copies; result.mesh describes it, its warnings told through `note`.
struct RunMesh {
    Mesh mesh;
    BBox3 loaded_box;                       // before scaling: the 3MF items' frame
    std::vector<CopyBox> copy_boxes;        // one per copy, when there are several
    std::vector<std::string> object_names;  // the copies' labels, when not numbered (--cut)
};
RunMesh load_run_mesh(const Settings& settings, const RunOptions& options, RunResult& result,
                      const std::function<void(const std::string&)>& note);

// The run of an already loaded and placed mesh: run_slice after the loading, each plate of
// run_cut. `result.mesh` describes `run_mesh`.
// `started` and `started_cpu_ns` are when the run began (its wall time, the main thread's CPU).
RunResult slice_run_mesh(const Settings& settings, const RunOptions& options, RunMesh run_mesh,
                         RunResult result, std::chrono::steady_clock::time_point started,
                         int64_t started_cpu_ns);

// Where the model sits: the offset that centres it on the bed, and its lowest point.
struct Placement {
    double offset_x = 0, offset_y = 0;  // mm, added to the model's x and y
    double z0 = 0;                      // the model's lowest z, mm
};
Placement centre_on_bed(const Settings& settings, const BBox3& box);

// Refuses a model larger than the bed (unless --no-bed-check), or too large for the line width
// and layer height.
void check_run_size(const Settings& settings, const RunOptions& options, const BBox3& box);
// Throws InputError (one line) when the skirt or brim, placed with the model's offsets on the
// bed, would leave it: an error rather than a loop clipped at the bed's edge.
// The raft's first layer likewise.
void check_loops_on_bed(const FirstLayerLoops& loops, const Paths& raft, const Settings& settings,
                        const RunOptions& options, double offset_x, double offset_y);

// The vertex limits, doubled, on the segments each plane will cut (the contours' vertices before
// any cleaning or simplification), in the order the slices are cut, before the first is
// chained: chaining, simplifying and uniting 800,000 vertices of a zig-zag took minutes a plane
// (issue #38), so the check on each slice as it is cut came too late.
void check_plane_segments(const TopDownSlicer& slicer, const Settings& settings,
                          const RunOptions& options);

// The vertex limits, checked on each slice in order as it is cut; empty when there are none.
std::function<void(const Slice&)> vertex_limits(const Settings& settings,
                                                const RunOptions& options);

// Names the G-code's objects: the model, each copy, or each item of a 3MF plate.
void label_objects(GcodeWriter& writer, const RunOptions& options, const Settings& settings,
                   const RunMesh& run_mesh, const RunResult& result);

// Points of the model whose convex hull holds its every slice up to the skirt's top, when the
// skirt rises beside more than its first layer (toolpath/skirt.hpp); none otherwise. `bottom`
// is the model's lowest Z.
std::vector<Point> skirt_shield_points(const Mesh& mesh, double bottom, const Settings& settings);

// The layer count of the model, refused if it is thinner than one layer.
int checked_layer_count(const TopDownSlicer& slicer, const Settings& settings,
                        const RunOptions& options);

// Every output of the run is complete under a temporary name before any is renamed into
// place (finish(): group.commit_all()); a run failing at any point leaves none of them,
// and the folders of pictures are written into temporary folders moved in at the end.
struct RunOutputs {
    // Opens the G-code writer (its objects named, its thumbnails drawn) and whichever of the
    // SVG pictures, the HTML report and the resin images `options` asks for.
    RunOutputs(const Settings& settings, const RunOptions& options, const RunMesh& run_mesh,
               RunResult& result, int layer_count, const Placement& place);
    // Finishes the resin images and the HTML report, writes the stats JSON, and renames every
    // output into place; sets result.peak_memory_mb. The G-code is finished before.
    void finish(RunResult& result, const Settings& settings, const RunOptions& options);

    // The group is declared first so that it is destroyed last: the writers it holds back
    // remove their temporaries when an error unwinds the run.
    OutputGroup group;
    GcodeWriter writer;
    std::unique_ptr<AtomicDir> svg_dir, raster_dir;
    std::unique_ptr<SvgLayerWriter> svg;
    std::unique_ptr<HtmlReportWriter> html;
    std::unique_ptr<RasterWriter> raster;
    // The skirt and brim (toolpath/skirt.hpp), added to the first layers' paths.
    FirstLayerLoops first_loops;
};

}  // namespace carve

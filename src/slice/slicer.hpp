// Streaming slicer: produces the slices O_i from the top layer down to layer 0.
//
// Layer i is cut at the middle of its thickness above the mesh's lowest point: z = (i + 0.5) * h,
// or with a first layer of its own height f, f / 2 and then f + (i - 0.5) * h. Triangles are sorted
// by their top z and kept in an active set while the plane sweeps down, so the whole stack of
// slices is never held: memory is the mesh plus one slice. Segments are chained through shared
// edges (vertex indices); loops are united with non-zero fill so that overlapping shells merge.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "mesh/mesh.hpp"

namespace carve {

struct Slice {
    int index = 0;  // i, bottom-up
    double z = 0;   // cut height in mm, in the mesh's own coordinates
    Paths region;   // O_i, outer contours counter-clockwise, holes clockwise
};

// One plane's crossing segments: gathered going down by TopDownSlicer::next_cut() (the active
// set is what carries from one plane to the next), chained into the slice by chain() on any
// thread. Chaining and uniting are most of the slicer's work.
class PlaneCut {
  public:
    PlaneCut();
    ~PlaneCut();
    PlaneCut(PlaneCut&&) noexcept;
    PlaneCut& operator=(PlaneCut&&) noexcept;
    Slice chain() &&;

  private:
    friend class TopDownSlicer;
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

class TopDownSlicer {
  public:
    // The mesh must outlive the slicer. first_layer_height 0: the layer height.
    TopDownSlicer(const Mesh& mesh, double layer_height, double first_layer_height = 0);
    ~TopDownSlicer();
    TopDownSlicer(const TopDownSlicer&) = delete;
    TopDownSlicer& operator=(const TopDownSlicer&) = delete;

    int layer_count() const;
    // Where layer i is cut, in the mesh's coordinates (the z of its Slice).
    double plane_z(int i) const;
    // The segments each plane will cut, by layer index, counted from the triangles' heights
    // alone: the slice's contour vertices before any cleaning or simplification. Chaining and
    // uniting a plane cost at least this (Clipper's union far more, on a zig-zag), so limits
    // on it can stop a run before the first plane is chained.
    std::vector<uint32_t> plane_segments() const;
    // The next slice going down, or nothing after layer 0.
    std::optional<Slice> next();
    // The same in two halves: the next plane's segments, in order; then PlaneCut::chain(), on
    // any thread. on_slice() is not called: the caller checks the slices itself.
    std::optional<PlaneCut> next_cut();
    // Called with every slice before next() returns it; may throw to stop the run (the pipeline
    // uses it for the --max-vertices-per-layer guard).
    void on_slice(std::function<void(const Slice&)> check);

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// Slices one plane directly (tests, previews); same chaining as the streaming slicer.
Paths slice_at(const Mesh& mesh, double z);

}  // namespace carve

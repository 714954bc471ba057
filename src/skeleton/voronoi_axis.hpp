// SKEL internals: the inner medial axis of one region component from Boost.Polygon's segment
// Voronoi diagram, with the checks that catch the builder's known failures.
//
// Private to src/skeleton (and its tests).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "geometry/types.hpp"
#include "skeleton/axis_graph.hpp"

namespace carve::skel {

// Why a diagram was rejected (kOk if it was not).
enum class AxisStatus {
    kOk,
    kOutOfRange,      // coordinates do not fit Boost's int32 input
    kBuilderAborted,  // the builder overran its storage or produced a degenerate cycle
    kMissingCell,     // an input segment has no Voronoi cell
    kInteriorRay,     // an infinite edge inside the region
    kNotEquidistant,  // an axis vertex is not equidistant from its two sites
    kDanglingAxis,    // an axis end lies inside the region (an edge is missing)
};

const char* to_string(AxisStatus status);

struct VoronoiWorkspace;  // builder, diagram and buffers, reused from call to call

struct VoronoiWorkspaceDeleter {
    void operator()(VoronoiWorkspace* w) const;
};
using VoronoiWorkspacePtr = std::unique_ptr<VoronoiWorkspace, VoronoiWorkspaceDeleter>;
VoronoiWorkspacePtr make_voronoi_workspace();

// Builds the inner medial axis of one component: contours with the interior on their left
// (outer counter-clockwise, holes clockwise), segments meeting only at common endpoints
// (contours may touch at vertices), no repeated points, coordinates within +-2^30. Parabolic
// arcs become chords with sagitta <= max_arc_error.
AxisStatus build_axis(const Paths& contours, double max_arc_error, VoronoiWorkspace& ws,
                      AxisGraph& graph);

}  // namespace carve::skel

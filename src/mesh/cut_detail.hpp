// What cut.cpp and cut_plan.cpp share (internal to the mesh stage): where a plane crosses the
// mesh's edges and how those points chain into the section's loops.
#pragma once

#include <array>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "mesh/cut.hpp"

namespace carve::cut_detail {

constexpr uint32_t kNoVertex = UINT32_MAX;

// The points where the plane crosses edges, and for each the next one along the cap of the
// piece below (counter-clockwise around the solid seen from above).
struct Crossing {
    std::unordered_map<uint64_t, uint32_t> point_of_edge;  // (lower, higher vertex) -> point
    std::vector<Vec3> points;
    std::vector<uint32_t> next;
};

// z moved off every vertex.
double off_vertices(const Mesh& mesh, double z);
Vec3 edge_point(const Mesh& mesh, uint32_t a, uint32_t b, double z);
// The corner alone on its side of the plane, or -1 when the triangle does not cross it.
int lone_corner(const Mesh& mesh, const std::array<uint32_t, 3>& t, double z);
Crossing cross_at(const Mesh& mesh, double z);  // z off every vertex
// The loops of point indices; throws InputError when one does not close.
std::vector<std::vector<uint32_t>> chain(const Crossing& c, double z);

// Where the connectors of a cut at z go: inside the face and the sections a hole's depth
// above and below it, `hole_r` + the margin clear of their edges, at most spec.per_island on
// each part of the face, far apart.
std::vector<std::pair<double, double>> connector_sites(const Mesh& mesh, double z, double hole_r,
                                                       const ConnectorSpec& spec);

}  // namespace carve::cut_detail

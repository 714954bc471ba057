// Ear-clipping triangulation of a polygon with holes (the caps of a cut, mesh/cut.cpp). Every
// input point is a vertex of the output and no point is added, so the caps share their
// boundary with the cut sides exactly: the pieces stay closed.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace carve {

struct XY {
    double x = 0, y = 0;
    uint32_t id = 0;  // the caller's vertex index, returned in the triangles
};

// `outer` counter-clockwise, each of `holes` clockwise and inside it, none crossing another.
// Triangles are counter-clockwise and traverse every ring's edges in the ring's own direction.
// A vertex whose neighbours line up with it may come out in a triangle of zero area (never
// left out). Throws std::runtime_error when the rings cannot be triangulated (they cross).
std::vector<std::array<uint32_t, 3>> triangulate(const std::vector<XY>& outer,
                                                 const std::vector<std::vector<XY>>& holes);

}  // namespace carve

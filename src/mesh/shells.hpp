// The shells of a mesh (components connected through manifold edges) as the repair sees them,
// and how deeply each closed one is nested in the others: the side a shell faces follows from
// that nesting (outermost solid, inside one other a void, and so on). Internal to the mesh
// stage (repair.cpp).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "mesh/mesh.hpp"

namespace carve::shells {

inline Vec3 sub(const Vec3& a, const Vec3& b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double dot(const Vec3& a, const Vec3& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

struct Shell {
    size_t size = 0;
    size_t flips = 0;  // triangles the walk turned relative to its seed
    bool closed = true;
    bool conflict = false;  // cannot be oriented (Moebius-like)
    Vec3 lo{}, hi{};
    std::array<uint32_t, 6> extreme{};  // vertices at min/max x, y, z
    double volume = 0;                  // about its own box centre
    double volume_about_centre = 0;     // about the mesh's box centre, for the total
    int depth = 0;                      // number of closed shells around it
};

// For every closed shell, how many other closed shells contain it (Shell::depth). A shell
// counts as inside another when every one of its extreme vertices is (by ray parity), so that
// shells which merely overlap (two intersecting spheres, blades set into a plate) are not taken
// for voids.
void nesting_depths(const Mesh& mesh, const std::vector<uint32_t>& shell_of,
                    std::vector<Shell>& shells);

}  // namespace carve::shells

// Orientations a model may be printed in (issue #48, --orient auto): the six that turn an axis
// of the model onto the bed, and those that lay one of the largest faces of its convex hull on
// it. The run carves each and keeps the lightest (src/run/orient.cpp); this file only proposes.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "geometry/types.hpp"
#include "mesh/mesh.hpp"

namespace carve {

// A rotation about the origin: v' = m v.
struct Rotation {
    std::array<std::array<double, 3>, 3> m{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    Vec3 apply(const Vec3& v) const;
    bool identity() const;
    // The same turn as an axis (unit) and an angle in degrees; (0,0,1) and 0 for none.
    Vec3 axis() const;
    double angle_deg() const;
};

// The rotation turning unit vector `down` (a direction in the model) to (0, 0, -1), about the
// axis perpendicular to both (a half turn about x when `down` is +z).
Rotation lay_down(const Vec3& down);
// `first`, then `then`.
Rotation compose(const Rotation& then, const Rotation& first);
// A quarter turn about z: what makes a model that fits the bed only across fit it.
Rotation quarter_turn_z();

// A plane of the convex hull: its outward unit normal and the area of the hull's facets in it.
struct HullPlane {
    Vec3 normal;
    double area_mm2 = 0;
};
// The planes of the convex hull of `points` (quickhull, facets of one direction within 1 degree
// merged), largest first; none when the points span no volume.
std::vector<HullPlane> hull_planes(const std::vector<Vec3>& points);

struct OrientationCandidate {
    std::string name;  // "as given", "x+90", ..., "hull face 2"
    Vec3 down;         // the model's direction that faces the bed
    Rotation rotation;
};
// "x+90 (90.0 deg about 1.000,0.000,0.000)", as the G-code header, the summary and the stats
// say it.
std::string describe(const OrientationCandidate& c);

// The six axis-aligned orientations, then those laying the `hull_faces` largest hull planes on
// the bed, any whose direction down lies within 2 degrees of one before it left out.
std::vector<OrientationCandidate> orientation_candidates(const Mesh& mesh, int hull_faces);

// The mesh turned by `r` (its triangles keep their order and their outward facing).
void rotate_mesh(Mesh& mesh, const Rotation& r);

}  // namespace carve

// Cutting a closed mesh across z into closed pieces (issue #48): the sides split along the
// planes, each cut face capped by a triangulation of the section, and connectors set into the
// faces (dowel holes in both, or a pin on the piece below and a hole in the piece above). The
// pieces are meshes like any loaded one; what prints them is the run's business.
#pragma once

#include <string>
#include <vector>

#include "mesh/mesh.hpp"
#include "mesh/orient.hpp"

namespace carve {

enum class ConnectorKind { None, Dowel, Pin };

struct ConnectorSpec {
    ConnectorKind kind = ConnectorKind::Dowel;
    double diameter_mm = 5;      // the dowel's or the pin's
    double depth_mm = 6;         // of each hole; a pin stands depth - clearance
    double clearance_mm = 0.15;  // added to a hole's radius around a pin or a dowel
    double margin_mm = 2;        // least material between a hole and the face's edge
    int per_island = 2;          // at most, on each separate part of a face
};

// A connector of a piece, in the model's frame (before the piece is laid on the bed).
struct Connector {
    double x = 0, y = 0;     // mm
    double face_z = 0;       // the cut face it is set into
    double diameter_mm = 0;  // the hole's (clearance included) or the pin's
    double depth_mm = 0;     // into the piece (a hole) or out of it (a pin)
    bool pin = false;
    Vec3 normal{0, 0, 1};  // the plane's normal, out of the face (a piece above a z cut: -z)
};

// A plane in any direction (--cut-plane): a point on it and its unit normal.
struct CutPlane {
    Vec3 point, normal;
};

// A flat face a cut left on a piece: its outward unit normal and area.
struct CutFace {
    Vec3 outward;
    double area_mm2 = 0;
    bool pins = false;  // a pin stands out of it: the piece cannot lie on it
    Vec3 point;         // a point of its plane
};

struct MeshPiece {
    Mesh mesh;          // closed, in the model's frame
    double z_from = 0;  // the cut below it (or the model's bottom), mm
    double z_to = 0;    // the cut above it (or the model's top), mm
    std::vector<Connector> connectors;
    std::vector<CutFace> faces;  // filled by cut_by_planes
};

// The mesh cut at each of `zs` (the model's frame, ascending, inside it), pieces bottom up.
// A plane through a vertex is moved by a fraction of a micrometre. Throws InputError when a
// section cannot be closed (an open or self-crossing mesh) or two cuts are closer than 1 mm.
std::vector<MeshPiece> cut_across_z(const Mesh& mesh, std::vector<double> zs,
                                    const ConnectorSpec& spec);

// The area of the mesh's section at z, mm^2 (its cut face), from the sides alone.
double section_area_mm2(const Mesh& mesh, double z);

// --cut auto: the fewest planes that leave every piece within `max_x` x `max_y` (either way
// round) and `max_height` tall, no piece under `min_height`; among those, the least cut face
// area in all. Planes are tried every `step` mm. Throws InputError naming the slab of the model
// that no cut across z can bring onto the bed.
struct CutLimits {
    double max_x = 0, max_y = 0, max_height = 0, min_height = 1, step = 0.5;
};
std::vector<double> plan_cuts(const Mesh& mesh, const CutLimits& limits,
                              const std::string& model_path);

// The mesh cut by each plane in turn (the pieces a plane crosses by more than 0.5 mm cut in
// two), each by turning the mesh so the plane's normal is z, cutting it with cut_across_z and
// turning the pieces back; the pieces stay in the model's frame. Throws as cut_across_z,
// and InputError for a plane that cuts no piece.
std::vector<MeshPiece> cut_by_planes(const Mesh& mesh, const std::vector<CutPlane>& planes,
                                     const ConnectorSpec& spec);

// The turn that lays a piece on its largest cut face with no pin: a flat face down, nothing to
// support under it. When every face has pins, the largest of them faces up; none when it has no
// cut face.
Rotation lay_on_cut_face(const MeshPiece& piece);

// --cut auto with planes across x, y and z: the fewest pieces that fit (each laid by
// lay_on_cut_face, turned a quarter about z when that fits), then the least cut face area. Only a
// plan better than `best_pieces` pieces with `best_area` mm^2 of cut faces is returned (the plan
// across z alone); none otherwise. `area` is set to the plan's cut face area.
std::vector<CutPlane> plan_planar_cuts(const Mesh& mesh, const CutLimits& limits,
                                       size_t best_pieces, double best_area, double& area);

}  // namespace carve

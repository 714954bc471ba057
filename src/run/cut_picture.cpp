// draw_piece (run/cut_picture.hpp): the piece's outline is the union of its triangles that face
// up, seen from above (a closed surface covers from above all it covers); a cut face is the
// union of the triangles that lie in its plane and face out of it, the connectors' rings
// included, their holes left open.
#include "run/cut_picture.hpp"

#include <cmath>

#include "geometry/polygon.hpp"

namespace carve {

namespace {

Vec3 minus(const Vec3& a, const Vec3& b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}

double dot(const Vec3& a, const Vec3& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

Vec3 unit_normal(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 u = minus(b, a), v = minus(c, a);
    const Vec3 n{u.y * v.z - u.z * v.y, u.z * v.x - u.x * v.z, u.x * v.y - u.y * v.x};
    const double len = std::sqrt(dot(n, n));
    return len > 0 ? Vec3{n.x / len, n.y / len, n.z / len} : Vec3{};
}

// How far from a face's plane a point of it may lie: the cut moves a plane that passes through
// a vertex by a fraction of a micrometre.
constexpr double kOnFaceMm = 0.01;

bool on_face(const CutFace& f, const Vec3& a, const Vec3& b, const Vec3& c) {
    if (dot(unit_normal(a, b, c), f.outward) < 0.999) return false;
    for (const Vec3* p : {&a, &b, &c})
        if (std::abs(dot(minus(*p, f.point), f.outward)) > kOnFaceMm) return false;
    return true;
}

// The triangle seen from above, counter-clockwise; empty when it is seen edge on.
Path from_above(const Vec3& a, const Vec3& b, const Vec3& c) {
    Path t{{to_units(a.x), to_units(a.y)},
           {to_units(b.x), to_units(b.y)},
           {to_units(c.x), to_units(c.y)}};
    const double twice = double(t[1].X - t[0].X) * double(t[2].Y - t[0].Y) -
                         double(t[1].Y - t[0].Y) * double(t[2].X - t[0].X);
    if (std::abs(twice) < 1) return {};
    if (twice < 0) std::swap(t[1], t[2]);
    return t;
}

}  // namespace

std::vector<CutFace> faces_across_z(const MeshPiece& piece, bool bottom, bool top) {
    std::vector<CutFace> faces;
    if (!bottom) faces.push_back({{0, 0, -1}, 0, false, {0, 0, piece.z_from}});
    if (!top) faces.push_back({{0, 0, 1}, 0, false, {0, 0, piece.z_to}});
    return faces;
}

PieceDrawing draw_piece(const MeshPiece& piece, const std::vector<CutFace>& faces,
                        const BedFrame& frame, const std::string& name) {
    PieceDrawing d;
    d.name = name;
    Paths up, flat;
    const Mesh& m = piece.mesh;
    for (const auto& t : m.triangles) {
        const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
        const Vec3 pa = frame.apply(a), pb = frame.apply(b), pc = frame.apply(c);
        const Vec3 n = unit_normal(pa, pb, pc);
        bool cut = false;
        for (const CutFace& f : faces) cut = cut || on_face(f, a, b, c);
        if (n.z <= 0 && !cut) continue;
        Path p = from_above(pa, pb, pc);
        if (p.empty()) continue;
        if (n.z > 0) up.push_back(p);
        if (cut && std::abs(n.z) > 0.999) flat.push_back(std::move(p));
    }
    d.outline = unite(up);
    d.cut_faces = unite(flat);
    for (const Connector& c : piece.connectors) {
        ConnectorMark mark;
        const Vec3 at = frame.apply({c.x, c.y, c.face_z});
        const Vec3 normal = frame.turn.apply(c.normal);
        mark.x = at.x;
        mark.y = at.y;
        mark.diameter_mm = c.diameter_mm;
        mark.pin = c.pin;
        mark.facing_down = normal.z < -0.5;
        mark.facing_side = std::abs(normal.z) <= 0.5;
        d.connectors.push_back(mark);
    }
    return d;
}

}  // namespace carve

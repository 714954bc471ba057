// Cuts by planes in any direction (mesh/cut.hpp, issue #48): each plane turned onto z so the
// cut across z does the work, the pieces turned back; how a piece lies on a cut face; and
// --cut auto's search over planes across x, y and z for models whose footprint no cut across z
// brings onto the bed.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "base/error.hpp"
#include "mesh/cut.hpp"

namespace carve {

namespace {

Rotation transposed(const Rotation& r) {
    Rotation t;
    for (size_t i = 0; i < 3; ++i)
        for (size_t j = 0; j < 3; ++j) t.m[i][j] = r.m[j][i];
    return t;
}

Vec3 negated(const Vec3& v) {
    return {-v.x, -v.y, -v.z};
}

// One plane through every piece it crosses.
std::vector<MeshPiece> cut_pieces(std::vector<MeshPiece> pieces, const CutPlane& plane,
                                  const ConnectorSpec& spec) {
    // The turn taking the plane's normal to +z (its opposite to -z, as lay_down does).
    const Rotation to_z = lay_down(negated(plane.normal));
    const Rotation back = transposed(to_z);
    const double d = to_z.apply(plane.point).z;
    std::vector<MeshPiece> out;
    for (MeshPiece& piece : pieces) {
        Mesh m = piece.mesh;
        rotate_mesh(m, to_z);
        const BBox3 b = bounding_box(m);
        if (!(d > b.min.z + 0.5 && d < b.max.z - 0.5)) {
            out.push_back(std::move(piece));
            continue;
        }
        const double area = std::abs(section_area_mm2(m, d));
        std::vector<MeshPiece> parts = cut_across_z(m, {d}, spec);
        for (size_t k = 0; k < parts.size(); ++k) {
            MeshPiece q;
            q.mesh = std::move(parts[k].mesh);
            rotate_mesh(q.mesh, back);
            if (q.mesh.triangles.empty() || std::abs(signed_volume(q.mesh)) < 1e-3) continue;
            const Vec3 outward = k == 0 ? plane.normal : negated(plane.normal);
            q.faces = piece.faces;
            CutFace face{outward, area, false, plane.point};
            // The piece's earlier connectors go with the side of the plane they are on.
            for (const Connector& c : piece.connectors)
                if ((to_z.apply({c.x, c.y, c.face_z}).z < d) == (k == 0)) q.connectors.push_back(c);
            for (Connector c : parts[k].connectors) {
                const Vec3 p = back.apply({c.x, c.y, c.face_z});
                c.x = p.x, c.y = p.y, c.face_z = p.z;
                c.normal = outward;
                face.pins = face.pins || c.pin;
                q.connectors.push_back(c);
            }
            q.faces.push_back(face);
            const BBox3 qb = bounding_box(q.mesh);
            q.z_from = qb.min.z;
            q.z_to = qb.max.z;
            out.push_back(std::move(q));
        }
    }
    return out;
}

struct Plan {
    std::vector<CutPlane> planes;
    size_t pieces = std::numeric_limits<size_t>::max();
    double area = std::numeric_limits<double>::infinity();
    bool better_than(const Plan& o) const {
        return pieces < o.pieces || (pieces == o.pieces && area < o.area - 1e-6);
    }
};

// The plan's pieces and cut face area when every piece fits; pieces = max otherwise.
Plan evaluate(const Mesh& mesh, std::vector<CutPlane> planes, const CutLimits& limits) {
    Plan plan;
    plan.planes = std::move(planes);
    ConnectorSpec none;
    none.kind = ConnectorKind::None;
    std::vector<MeshPiece> pieces;
    try {
        pieces = cut_by_planes(mesh, plan.planes, none);
    } catch (const InputError&) {
        return plan;
    }
    double area = 0;
    for (const MeshPiece& p : pieces) {
        Mesh m = p.mesh;
        rotate_mesh(m, lay_on_cut_face(p));
        const BBox3 b = bounding_box(m);
        const double w = b.max.x - b.min.x, d = b.max.y - b.min.y, h = b.max.z - b.min.z;
        const bool fits =
            (w <= limits.max_x && d <= limits.max_y) || (w <= limits.max_y && d <= limits.max_x);
        if (!fits || h > limits.max_height + 1e-9) return plan;
        for (const CutFace& f : p.faces) area += f.area_mm2 / 2;  // each face has two sides
    }
    plan.pieces = pieces.size();
    plan.area = area;
    return plan;
}

// n planes across axis a (0 x, 1 y, 2 z), evenly apart inside the box.
void add_even(std::vector<CutPlane>& planes, const BBox3& box, int axis, int n) {
    const double lo = axis == 0 ? box.min.x : axis == 1 ? box.min.y : box.min.z;
    const double hi = axis == 0 ? box.max.x : axis == 1 ? box.max.y : box.max.z;
    for (int i = 1; i <= n; ++i) {
        const double at = lo + (hi - lo) * i / (n + 1);
        CutPlane p;
        p.point = {axis == 0 ? at : 0, axis == 1 ? at : 0, axis == 2 ? at : 0};
        p.normal = {axis == 0 ? 1.0 : 0, axis == 1 ? 1.0 : 0, axis == 2 ? 1.0 : 0};
        planes.push_back(p);
    }
}

}  // namespace

std::vector<MeshPiece> cut_by_planes(const Mesh& mesh, const std::vector<CutPlane>& planes,
                                     const ConnectorSpec& spec) {
    std::vector<MeshPiece> pieces(1);
    pieces[0].mesh = mesh;
    const BBox3 b = bounding_box(mesh);
    pieces[0].z_from = b.min.z;
    pieces[0].z_to = b.max.z;
    for (size_t k = 0; k < planes.size(); ++k) {
        const size_t before = pieces.size();
        pieces = cut_pieces(std::move(pieces), planes[k], spec);
        if (pieces.size() == before)
            throw InputError(
                fmt::format("plane {} (normal {:.3f}, {:.3f}, {:.3f}) cuts no piece "
                            "of the model by more than 0.5 mm",
                            k + 1, planes[k].normal.x, planes[k].normal.y, planes[k].normal.z));
    }
    return pieces;
}

Rotation lay_on_cut_face(const MeshPiece& piece) {
    const CutFace* best = nullptr;
    for (bool allow_pins : {false, true}) {
        for (const CutFace& f : piece.faces)
            if ((allow_pins || !f.pins) && (!best || f.area_mm2 > best->area_mm2)) best = &f;
        if (best) break;
    }
    if (!best) return Rotation{};
    // Every face carries pins: the piece would stand on them. The largest goes up instead, its
    // pins standing clear, and the piece stands on the side across from it (the lower piece of
    // a cut across z stays as it was).
    if (best->pins) return lay_down(Vec3{-best->outward.x, -best->outward.y, -best->outward.z});
    return lay_down(best->outward);
}

std::vector<CutPlane> plan_planar_cuts(const Mesh& mesh, const CutLimits& limits,
                                       size_t best_pieces, double best_area, double& area) {
    const BBox3 box = bounding_box(mesh);
    Plan best;
    best.pieces = best_pieces;
    best.area = best_area;
    // Evenly spaced planes, fewest cells first: a plan of more cells than the best has pieces
    // rarely has fewer pieces.
    std::vector<std::array<int, 3>> counts;
    for (int nx = 0; nx <= 3; ++nx)
        for (int ny = 0; ny <= 3; ++ny)
            for (int nz = 0; nz <= 3; ++nz)
                if (nx + ny > 0) counts.push_back({nx, ny, nz});
    auto cells = [](const std::array<int, 3>& n) {
        return size_t((n[0] + 1) * (n[1] + 1) * (n[2] + 1));
    };
    std::stable_sort(counts.begin(), counts.end(),
                     [&](const auto& a, const auto& b) { return cells(a) < cells(b); });
    for (const auto& n : counts) {
        if (cells(n) > best.pieces) break;
        std::vector<CutPlane> planes;
        for (int axis = 0; axis < 3; ++axis) add_even(planes, box, axis, n[size_t(axis)]);
        const Plan p = evaluate(mesh, std::move(planes), limits);
        if (p.better_than(best)) best = p;
    }
    if (best.planes.empty()) return {};
    // Each plane moved along its normal, a few steps either way, while the cut face shrinks and
    // every piece still fits; passes again (at most four) while a plane moved.
    const double extent[3] = {box.max.x - box.min.x, box.max.y - box.min.y, box.max.z - box.min.z};
    for (int pass = 0; pass < 4; ++pass) {
        bool moved = false;
        for (size_t i = 0; i < best.planes.size(); ++i) {
            const Vec3 n = best.planes[i].normal;
            const double span = n.x > 0.5 ? extent[0] : n.y > 0.5 ? extent[1] : extent[2];
            for (double f : {-0.12, -0.06, -0.03, 0.03, 0.06, 0.12}) {
                std::vector<CutPlane> planes = best.planes;
                planes[i].point = {planes[i].point.x + n.x * f * span,
                                   planes[i].point.y + n.y * f * span,
                                   planes[i].point.z + n.z * f * span};
                const Plan p = evaluate(mesh, std::move(planes), limits);
                if (p.better_than(best)) best = p, moved = true;
            }
        }
        if (!moved) break;
    }
    area = best.area;
    return best.planes;
}

}  // namespace carve

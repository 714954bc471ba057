// The drawing of one piece of a --cut on its plate (report/cut_svg.hpp), from its mesh in the
// model's frame and the turn and shift that put it on the bed (private to src/run).
#pragma once

#include <string>
#include <vector>

#include "mesh/cut.hpp"
#include "report/cut_svg.hpp"

namespace carve {

// Model frame to bed: turn, then shift (mm).
struct BedFrame {
    Rotation turn;
    Vec3 shift;
    Vec3 apply(const Vec3& p) const {
        const Vec3 q = turn.apply(p);
        return {q.x + shift.x, q.y + shift.y, q.z + shift.z};
    }
};

// The cut faces of a piece of cut_across_z (its faces are not listed): the one under it unless
// it is the bottom piece, the one over it unless it is the top.
std::vector<CutFace> faces_across_z(const MeshPiece& piece, bool bottom, bool top);

// `piece` drawn where `frame` puts it; `faces` are its cut faces, each with a point on it.
PieceDrawing draw_piece(const MeshPiece& piece, const std::vector<CutFace>& faces,
                        const BedFrame& frame, const std::string& name);

}  // namespace carve

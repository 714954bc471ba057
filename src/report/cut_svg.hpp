// The picture of a cut (issue #48): each plate seen from above with its pieces laid out as they
// print, their cut faces and the connectors set into them, so that a user sees which face glues
// to which and where the dowels go before printing hours of plates.
#pragma once

#include <string>
#include <vector>

#include "geometry/types.hpp"

namespace carve {

struct ConnectorMark {
    double x = 0, y = 0;     // the connector's centre on its face, bed mm
    double diameter_mm = 0;  // the hole's (clearance included) or the pin's
    bool pin = false;
    bool facing_down = false;  // in the face on the bed: seen through the piece
    bool facing_side = false;  // in an upright face: its circle is seen edge on
};

struct PieceDrawing {
    std::string name;  // the piece's object name in the G-code
    Paths outline;     // what it covers of the bed seen from above, bed coordinates (um)
    Paths cut_faces;   // its cut faces that lie flat (on the bed or facing up), seen from above
    std::vector<ConnectorMark> connectors;
};

struct PlateDrawing {
    std::string gcode;  // the plate's G-code file
    double bed_x = 0, bed_y = 0;
    std::vector<PieceDrawing> pieces;
};

// The plates side by side (two to a row) as a self-contained SVG document; every piece named
// by a label, every connector a circle with class "hole" or "pin".
std::string cut_plates_svg(const std::vector<PlateDrawing>& plates, const std::string& title);

}  // namespace carve

// What `carve info MODEL` prints: a short human description of a loaded mesh and its JSON form.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "mesh/mesh.hpp"

namespace carve {

// A few lines: format, triangles, vertices, bounding box and size in mm, volume in cm^3,
// closedness, shells and what was repaired.
std::string describe(const MeshReport& report);

// Keys: format, triangles, triangles_read, vertices, bbox_min, bbox_max, size_mm,
// model_volume_mm3, closed, open_edges, nonmanifold_edges, shells, internal_voids,
// degenerate_dropped, duplicate_dropped, flipped_triangles, inverted, inverted_shells, warnings.
nlohmann::json to_json(const MeshReport& report);

}  // namespace carve

// carve check --mesh-offset: the shift from a mesh's coordinates to its G-code's, as typed.
#pragma once

#include <string>

#include "geometry/types.hpp"

namespace carve {

// "X,Y" or "X,Y,Z" in mm, each a plain decimal within 1e5 (sscanf took "nan", "inf" and
// hexadecimal); without Z, z is NaN: the print stands on the bed. Throws InputError naming
// --mesh-offset otherwise.
Vec3 parse_mesh_offset(const std::string& text);

}  // namespace carve

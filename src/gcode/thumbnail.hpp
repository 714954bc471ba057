// Thumbnails in PrusaSlicer's format, which Moonraker, OctoPrint's PrusaSlicer Thumbnails
// plugin and Prusa's and other printers' screens show: in the header,
//   ; thumbnail begin 220x124 5828
//   ; iVBORw0KGgoAAAANSUhEUgAA...      (base64 of a PNG, 76 characters a line)
//   ; thumbnail end
// where 5828 is the base64 length. carve draws them itself from the mesh, headless: an
// isometric view from the front right, a z-buffer with flat shading, 2x2 supersampled, on a
// transparent background.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "geometry/types.hpp"

namespace carve {

// RGBA pixels, rows top down, `width * height * 4` bytes.
std::vector<uint8_t> render_thumbnail(const std::vector<Vec3>& vertices,
                                      const std::vector<std::array<uint32_t, 3>>& triangles,
                                      int width, int height);

// The PNG file of RGBA pixels. Throws OutputError if libpng fails.
std::string encode_png_rgba(const std::vector<uint8_t>& rgba, int width, int height);

std::string base64(const std::string& bytes);

// The header lines of one block per size (none for no sizes).
std::vector<std::string> thumbnail_blocks(const std::vector<Vec3>& vertices,
                                          const std::vector<std::array<uint32_t, 3>>& triangles,
                                          const std::vector<std::pair<int, int>>& sizes);

}  // namespace carve

// Compact binary form of a layer's toolpaths for the spill file (private to the G-code stage).
//
// Layout: varint index, 8-byte z, varint extrusion count; per extrusion: feature byte, flags
// byte (bit 0 = closed), zig-zag varint cavity, 8-byte flow, the points; then the travel count
// (0 or the extrusion count) and per travel its kind byte and points; then the comb region's
// contour count and contours. Points are a varint
// count and zig-zag varint deltas from the previous point (the first from 0, 0). Typical paths
// take 2 to 4 bytes per point instead of 16.
#pragma once

#include <string>

#include "toolpath/toolpath.hpp"

namespace carve {

std::string encode_layer(const LayerToolpaths& layer);
// Throws std::runtime_error on a truncated or malformed blob.
LayerToolpaths decode_layer(const std::string& blob);

}  // namespace carve

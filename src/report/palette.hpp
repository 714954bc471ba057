// The colours of the pictures (SVG layers and the HTML report's viewer and plots), so that a
// cavity has the same colour wherever a person sees it.
#pragma once

#include <algorithm>
#include <array>
#include <string>

namespace carve {

// Report figures 1 and 3: C^1 red, C^2 blue, C^3 yellow, C^4 green; then hues that stay apart
// from those and from the grey of the remainder and the magenta of the bridges.
inline constexpr std::array<const char*, 12> kCavityColours = {
    "#e03131", "#1971c2", "#fcc419", "#2f9e44", "#f76707", "#7048e8",
    "#15aabf", "#8d5524", "#e64980", "#82a000", "#0b7285", "#364fc7"};
inline constexpr const char* kBridgeColour = "#ff00ff";
inline constexpr const char* kOuterWallColour = "#000000";
inline constexpr const char* kShellColour = "#3b3b3b";
// Supports under the model's overhangs: teal, apart from the cavities' hues and the bridges.
inline constexpr const char* kSupportColour = "#0ca678";
inline constexpr const char* kSupportInterfaceColour = "#087f5b";
// carve's ribs, the supports inside the model: a saturated green no cavity has.
inline constexpr const char* kRibColour = "#00c000";
// Skirt and brim, on the bed around the part: grey and orange.
inline constexpr const char* kSkirtColour = "#868e96";
inline constexpr const char* kBrimColour = "#f08c00";

// Index into kCavityColours of cavity C^j (j >= 1; the palette repeats after 12).
inline size_t cavity_colour_index(int j) {
    return size_t(std::max(j - 1, 0)) % kCavityColours.size();
}

// Colour of cavity C^j (j >= 1), as "#rrggbb".
inline std::string cavity_colour(int j) {
    return kCavityColours[cavity_colour_index(j)];
}

}  // namespace carve

// Resin (DLP / MSLA) output: every layer's partition rasterised to a grayscale PNG, white = cured
// resin. A resin printer cures whole pixels, so the cavities can be kept as regions and their
// outlines thickened to the thinnest wall the printer makes (report section 4, first paragraph)
// instead of being turned into print paths.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "carving/layer.hpp"
#include "config/settings.hpp"

namespace carve {

// A pixel grid over the bed: pixel (col, row) has its centre at
// (origin_x + (col + 0.5) * pixel, origin_y + (height - row - 0.5) * pixel), row 0 at the top
// (highest y), as images are stored.
struct RasterGrid {
    Coord origin_x = 0, origin_y = 0;  // lower-left corner, micrometres
    double pixel = 50;                 // pixel size, micrometres
    int width = 0, height = 0;
};

// Sets to `value` every pixel whose centre lies inside `region` (non-zero winding), with an
// active-edge scanline fill. `image` holds width * height bytes, row-major, row 0 on top.
void rasterize(const Paths& region, const RasterGrid& grid, std::vector<uint8_t>& image,
               uint8_t value = 255);

// The cured part of one slice: the outer shell (outline minus the outline eroded by `shell`),
// every cavity boundary thickened to `min_wall` (half on each side, so two cavities that touch
// keep a full wall between them), covers and the remainder V^k solid, cavities empty. Bridges
// become solid strips over their minimum: the layer above then rests on them as on the FDM
// bridge lines.
Paths resin_solid(const LayerRecord& layer, Coord shell, Coord min_wall, Coord bridge_half);

struct RasterLayerStats {
    int index = 0;
    int64_t white_pixels = 0;
};

class RasterWriter {
  public:
    // `bounds`: the model's XY footprint in micrometres (the union of the outlines); the images
    // cover it plus a margin of a few pixels. `min_wall_mm` <= 0 means the nozzle width; the
    // outer shell is the thicker of the nozzle width and the minimal wall.
    RasterWriter(std::string dir, const Settings& settings, BBox2 bounds, double pixel_mm = 0.05,
                 double min_wall_mm = 0);
    ~RasterWriter();
    RasterWriter(const RasterWriter&) = delete;
    RasterWriter& operator=(const RasterWriter&) = delete;

    // Layers arrive in any order (the sweep gives them top down), from several threads at once
    // if need be; each becomes DIR/layer_NNNNN.png with NNNNN = layer.index, bottom up.
    void add_layer(const LayerRecord& layer);
    // Writes DIR/raster.json (grid, pixel size, layer height) and DIR/layers.zip holding every
    // PNG and the JSON.
    void finish();

    const RasterGrid& grid() const;
    // Per layer, in index order once finish() ran.
    const std::vector<RasterLayerStats>& layer_stats() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace carve

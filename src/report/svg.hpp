// Pictures of single layers as self-contained SVG files, drawn like figures 1 and 3 of the
// report: the model's slice in light grey, covers in a neutral sand, each cavity C^j filled in
// its own colour (C^1 red, C^2 blue, C^3 yellow, C^4 green, then further distinct hues), the
// remainder V^k in grey, and the print paths on top as thin lines by feature. For looking at a
// run layer by layer (`--svg DIR`) and for debugging a stage; the HTML report has its own viewer.
#pragma once

#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "carving/layer.hpp"
#include "report/palette.hpp"
#include "toolpath/toolpath.hpp"

namespace carve {

struct SvgOptions {
    double width_px = 900;       // width of the drawing area; the height follows the model
    double max_height_px = 900;  // a tall slice is scaled down to this height instead
    double margin_mm = 1.5;      // around the slice's bounding box
    bool legend = true;          // a column to the right with swatches and areas
    bool toolpaths = true;       // draw the paths when they are given
    double path_width_mm = 0.1;  // drawn width of the print paths (thin, so walls stay apart)
    std::string title;           // empty: "layer i, z = .. mm"
};

// Text made safe inside XML/HTML markup and attributes.
std::string xml_escape(std::string_view text);

// One layer as an SVG document. `paths` may be null (partition only).
std::string layer_svg(const LayerRecord& layer, const LayerToolpaths* paths,
                      const SvgOptions& options = {});

// Writes layer_svg to `file` (through a temporary name, renamed when complete). Throws
// InputError if the file cannot be written.
void write_layer_svg(const std::string& file, const LayerRecord& layer, const LayerToolpaths* paths,
                     const SvgOptions& options = {});

// Writes DIR/layer_0123.svg for the chosen layers as they arrive (in any order, the sweep gives
// them top down). The directory is created when needed.
class SvgLayerWriter {
  public:
    // Exactly the listed layer indices.
    SvgLayerWriter(std::string dir, std::vector<int> layers, SvgOptions options = {});
    // Every n-th layer, starting at layer 0 (n <= 1: every layer).
    static SvgLayerWriter every(std::string dir, int n, SvgOptions options = {});

    bool wants(int index) const;
    // Writes the layer if it is chosen; returns the file written, or "" if it was not chosen.
    // Several threads may add layers at once.
    std::string add(const LayerRecord& layer, const LayerToolpaths* paths);
    // The files written so far, in layer order whatever order they came in.
    const std::vector<std::string>& written() const { return written_; }
    static std::string file_name(int index);  // "layer_0123.svg"
    // `count` layer indices spread evenly over 0 .. layer_count - 1, first and last included.
    static std::vector<int> spread(int layer_count, int count = 8);

  private:
    SvgLayerWriter(std::string dir, std::set<int> layers, int every, SvgOptions options);
    std::string dir_;
    std::set<int> layers_;
    int every_ = 0;  // > 0: every n-th layer instead of the list
    SvgOptions options_;
    std::vector<std::string> written_;
    std::unique_ptr<std::mutex> mutex_ = std::make_unique<std::mutex>();  // guards written_
};

}  // namespace carve

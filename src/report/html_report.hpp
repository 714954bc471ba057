// The HTML report of a run: one self-contained page (inline CSS, JS and SVG, nothing fetched
// from the network) with the figures a person cares about, the saving against ordinary infill,
// a layer viewer and per-layer plots.
//
// Layers arrive top down while the page lists them bottom up, and an object may have thousands
// of them: each layer is reduced on arrival to a simplified drawing (SVG path strings, 0.01 mm
// grid) spilled to a temporary file, plus a few numbers kept in memory. The drawing tolerance
// grows for layers that would push the page past its size budget.
#pragma once

#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "carving/layer.hpp"
#include "config/settings.hpp"
#include "report/run_result.hpp"
#include "toolpath/toolpath.hpp"

namespace carve {

namespace html {

// SVG path data for contours or polylines, coordinates in units of `grid` micrometres (first
// point absolute, then relative moves). Closed contours end with "z".
std::string svg_path_data(const Paths& paths, bool closed, double tolerance, Coord grid);

}  // namespace html

// What the report keeps of a layer besides its drawing.
struct ReportLayer {
    int index = 0;
    double z = 0;                 // nozzle height, mm
    double material_mm3 = 0;      // extrusion length x width x height x flow
    double conventional_mm3 = 0;  // the 15 % infill estimate on the same slice
    double outline_mm2 = 0;
    double perimeter_mm = 0;  // length of the slice's outline
    double covers_mm2 = 0;
    double carvable_mm2 = 0;
    double remainder_mm2 = 0;
    std::vector<double> cavity_mm2;  // C^1 .. C^k
    int bridges = 0;
    double wall_mm = 0, cover_mm = 0, cavity_wall_mm = 0, bridge_mm = 0;  // path lengths
    double support_mm = 0;
    double tolerance_mm = 0;     // simplification used for the drawing
    long offset = 0, bytes = 0;  // drawing record in the spill file
};

class OutputGroup;

class HtmlReportWriter {
  public:
    HtmlReportWriter(std::string path, const Settings& settings);
    ~HtmlReportWriter();  // removes the temporary file if finish() was not reached
    HtmlReportWriter(const HtmlReportWriter&) = delete;
    HtmlReportWriter& operator=(const HtmlReportWriter&) = delete;

    // Called top down for every layer, with the layer's partition and its print paths.
    void add_layer(const LayerRecord& layer, const LayerToolpaths& paths);
    // Writes the page to a temporary name next to `path` and renames it into place. `stats` is
    // the run's stats JSON (shown as is; "model" is used for the title when present).
    void finish(const RunResult& run, const nlohmann::json& stats);
    // finish() leaves the complete report to `group` instead of renaming it at once.
    void commit_with(OutputGroup& group);

    // The model's file (its name titles the page) when the stats JSON has no "model" entry.
    void set_model_name(std::string path);
    // Drawing budget for the whole page in bytes (default 16 MB). Set before the first layer.
    void set_budget(size_t bytes);
    const std::vector<ReportLayer>& layers() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace carve

// The HTML report writer's state, shared by its two halves (private to src/report):
// html_report.cpp reduces each layer as it arrives (figures kept, drawing spilled to a temporary
// file) and html_page.cpp writes the page from them at the end.
#pragma once

#include <array>
#include <cstdio>
#include <ostream>
#include <string>
#include <vector>

#include "config/settings.hpp"
#include "report/html_plots.hpp"
#include "report/html_report.hpp"
#include "report/html_side.hpp"

namespace carve {

namespace html {

constexpr Coord kGrid = 10;  // drawing grid, micrometres (0.01 mm)
// Simplification tolerances tried in turn until a layer's drawing fits its share of the budget.
constexpr std::array<double, 4> kTolerances = {50, 100, 200, 400};

}  // namespace html

struct HtmlReportWriter::Impl {
    std::string path;
    OutputGroup* group = nullptr;  // commit held back until the run's other outputs are done
    Settings settings;
    FILE* spill = nullptr;
    long spilled = 0;
    size_t budget = size_t(16) << 20;
    int expected_layers = 0;
    int max_cavities = 0;
    BBox2 box;
    std::vector<ReportLayer> layers;
    bool finished = false;
    std::string model_name;
    // For the side view of the tallest rib chain: every rib piece, each layer's outline.
    std::vector<html::RibPiece> ribs;
    std::vector<html::SideLayer> side_layers;

    std::string drawing(const LayerRecord& layer, const LayerToolpaths& paths, double tol) const;

    // The steps of finish(), in the order the page is written.
    struct PageFigures;
    PageFigures figures(const RunResult& run, const nlohmann::json& stats) const;
    void write_head(std::ostream& out, const PageFigures& f) const;  // <head>, style sheet
    void write_cards(std::ostream& out, const PageFigures& f, const RunResult& run) const;
    std::array<double, 4> write_viewer(std::ostream& out, const PageFigures& f) const;  // viewBox
    html::PlotFrame write_plots(std::ostream& out, const RunResult& run) const;
    void write_side(std::ostream& out) const;  // the tallest internal support, from the side
    void write_details(std::ostream& out, const PageFigures& f, const RunResult& run,
                       const nlohmann::json& stats) const;
    void write_data(std::ostream& out, const PageFigures& f, const std::array<double, 4>& vb,
                    const html::PlotFrame& frame) const;  // the layers and META for the script
};

}  // namespace carve

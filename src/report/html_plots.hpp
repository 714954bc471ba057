// Plots of the HTML report and the small number formats of the page (html_plots.cpp).
#pragma once

#include <string>
#include <vector>

#include "report/html_report.hpp"

namespace carve::html {

// Colours of the page's own features; cavities, bridges and walls use report/palette.hpp.
inline constexpr const char* kCoverColor = "#d9a441";
inline constexpr const char* kRemainderColor = "#ced4da";

// Rounds to `decimals` decimals so the JSON stays short.
double rounded(double v, int decimals);
// 1, 2 or 5 times a power of ten, so that `range` spans about `ticks` steps.
double nice_step(double range, int ticks);
// An axis label with as many decimals as the step needs.
std::string tick_label(double v, double step);

// Geometry shared by the two plots (SVG user units); the page's script uses it for the cursor.
struct PlotFrame {
    double width = 640, height = 240, left = 56, right = 12, top = 24, bottom = 38;
    int n = 1;
    double inner_w() const { return width - left - right; }
    double inner_h() const { return height - top - bottom; }
    double x(double pos) const { return left + (pos + 0.5) * inner_w() / n; }
};

// A layer marked on a plot (the weakest one of --stats-strength): its position, bottom up.
struct PlotMark {
    size_t layer = 0;
    std::string label;
};

// Material per layer against the 15 % infill estimate; layers bottom up.
std::string material_plot(const std::vector<ReportLayer>& layers, const PlotFrame& f,
                          const std::vector<PlotMark>& marks = {});
// Stacked shares of each slice's area: covers, C^1..C^k, the remainder V^k.
std::string share_plot(const std::vector<ReportLayer>& layers, int cavities, const PlotFrame& f);

// A colour swatch with its label, for the plots' captions.
std::string chip(const std::string& color, const std::string& label);
std::string fixed(double v, int decimals);
// Three significant figures, for volumes from a few mm^3 to litres.
std::string sig3(double v);

}  // namespace carve::html

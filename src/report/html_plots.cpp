// The HTML report's SVG pieces: the path data of the layer drawings (simplified, on a grid,
// relative moves), the two plots (material per layer, what each slice is made of), and the
// number formatting the page shares with them.
#include "report/html_plots.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "geometry/simplify.hpp"
#include "report/palette.hpp"

namespace carve::html {

namespace {

// Numbers in path data: a minus sign separates on its own, so only positives need a space.
void append_number(std::string& out, long long v, bool after_command) {
    if (!after_command && v >= 0) out += ' ';
    out += std::to_string(v);
}

}  // namespace

std::string svg_path_data(const Paths& paths, bool closed, double tolerance, Coord grid) {
    std::string out;
    const double g = double(std::max<Coord>(grid, 1));
    std::vector<std::pair<long long, long long>> q;
    for (const Path& path : paths) {
        const Path simple = douglas_peucker(path, closed, tolerance);
        q.clear();
        for (const Point& p : simple) {
            const std::pair<long long, long long> v{std::llround(double(p.X) / g),
                                                    std::llround(double(p.Y) / g)};
            if (q.empty() || q.back() != v) q.push_back(v);
        }
        if (closed && q.size() > 1 && q.back() == q.front()) q.pop_back();
        if (q.size() < 2) continue;
        out += 'M';
        append_number(out, q[0].first, true);
        append_number(out, q[0].second, false);
        out += 'l';
        for (size_t i = 1; i < q.size(); ++i) {
            append_number(out, q[i].first - q[i - 1].first, i == 1);
            append_number(out, q[i].second - q[i - 1].second, false);
        }
        if (closed) out += 'z';
    }
    return out;
}

// Rounds to `digits` significant-looking decimals so the JSON stays short.
double rounded(double v, int decimals) {
    const double f = std::pow(10.0, decimals);
    return std::round(v * f) / f;
}

// 1, 2 or 5 times a power of ten, so that `range` spans about `ticks` steps.
double nice_step(double range, int ticks) {
    if (!(range > 0)) return 1;
    const double raw = range / ticks;
    const double p = std::pow(10.0, std::floor(std::log10(raw)));
    const double m = raw / p;
    return (m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10) * p;
}

std::string tick_label(double v, double step) {
    if (step >= 1) return fmt::format("{:.0f}", v);
    if (step >= 0.1) return fmt::format("{:.1f}", v);
    return fmt::format("{:.2f}", v);
}

namespace {

std::string plot_axes(const PlotFrame& f, const std::vector<ReportLayer>& layers, double y_max,
                      double y_step, const std::string& y_unit) {
    std::string s;
    for (double v = 0; v <= y_max * 1.0001; v += y_step) {
        const double y = f.top + f.inner_h() * (1 - v / y_max);
        s += fmt::format(R"(<line class="grid" x1="{:.1f}" y1="{:.1f}" x2="{:.1f}" y2="{:.1f}"/>)",
                         f.left, y, f.width - f.right, y);
        s += fmt::format(R"(<text class="ytick" x="{:.1f}" y="{:.1f}">{}</text>)", f.left - 6,
                         y + 4, tick_label(v, y_step));
    }
    s += fmt::format(R"(<text class="yunit" x="{:.1f}" y="{:.1f}">{}</text>)", f.left - 6,
                     f.top - 9, y_unit);
    // x ticks at round heights; layer i sits at layers[i].z.
    if (!layers.empty()) {
        const double z0 = layers.front().z, z1 = layers.back().z;
        const double step = nice_step(std::max(z1 - z0, 1e-3), 6);
        const double h = layers.size() > 1 ? (z1 - z0) / double(layers.size() - 1) : 1.0;
        for (double z = std::ceil(z0 / step) * step; z <= z1 + 1e-9; z += step) {
            const double x = f.x((z - z0) / h);
            s += fmt::format(
                R"(<line class="xtick" x1="{:.1f}" y1="{:.1f}" x2="{:.1f}" y2="{:.1f}"/>)", x,
                f.top + f.inner_h(), x, f.top + f.inner_h() + 4);
            s += fmt::format(R"(<text class="xlabel" x="{:.1f}" y="{:.1f}">{}</text>)", x,
                             f.top + f.inner_h() + 17, tick_label(z, step));
        }
        s += fmt::format(R"(<text class="xunit" x="{:.1f}" y="{:.1f}">height z (mm)</text>)",
                         f.left + f.inner_w() / 2, f.height - 3);
    }
    return s;
}

std::string plot_cursor(const PlotFrame& f) {
    return fmt::format(R"(<line class="cursor" x1="0" y1="{:.1f}" x2="0" y2="{:.1f}"/>)", f.top,
                       f.top + f.inner_h());
}

}  // namespace

std::string material_plot(const std::vector<ReportLayer>& layers, const PlotFrame& f,
                          const std::vector<PlotMark>& marks) {
    double top = 0;
    for (const ReportLayer& l : layers) top = std::max({top, l.material_mm3, l.conventional_mm3});
    const double step = nice_step(top > 0 ? top : 1, 4);
    const double y_max = std::max(step, std::ceil((top > 0 ? top : 1) / step) * step);
    auto y = [&](double v) { return f.top + f.inner_h() * (1 - v / y_max); };
    std::string s =
        fmt::format(R"(<svg class="plot-svg" id="plot-m" viewBox="0 0 {} {}">)", f.width, f.height);
    s += plot_axes(f, layers, y_max, step, "mm³");
    std::string area = fmt::format("M{:.1f} {:.1f}", f.x(0), y(0));
    std::string carve_line, conv_line;
    for (size_t i = 0; i < layers.size(); ++i) {
        const double x = f.x(double(i));
        area += fmt::format("L{:.1f} {:.1f}", x, y(layers[i].material_mm3));
        carve_line += fmt::format("{}{:.1f} {:.1f}", i ? "L" : "M", x, y(layers[i].material_mm3));
        conv_line +=
            fmt::format("{}{:.1f} {:.1f}", i ? "L" : "M", x, y(layers[i].conventional_mm3));
    }
    area += fmt::format("L{:.1f} {:.1f}Z", f.x(double(layers.size()) - 1), y(0));
    s += fmt::format(R"(<path class="conv" d="{}"/>)", conv_line);
    s += fmt::format(R"(<path class="carve-area" d="{}"/><path class="carve-line" d="{}"/>)", area,
                     carve_line);
    // Labels stacked down from the top so that two marks on near layers stay readable.
    for (size_t k = 0; k < marks.size(); ++k) {
        const double x = f.x(double(marks[k].layer));
        s += fmt::format(
            R"(<line class="weak" x1="{0:.1f}" y1="{1:.1f}" x2="{0:.1f}" y2="{2:.1f}"/>)"
            R"(<text class="weak" x="{3:.1f}" y="{4:.1f}">{5}</text>)",
            x, f.top, f.top + f.inner_h(), x + 4, f.top + 11 + 13 * double(k), marks[k].label);
    }
    s += plot_cursor(f);
    s += "</svg>";
    return s;
}

// Stacked shares of each slice's area: covers, C^1..C^k, the remainder V^k; what is left up to
// 100 % is the outer wall's band and the shells.
std::string share_plot(const std::vector<ReportLayer>& layers, int cavities, const PlotFrame& f) {
    auto y = [&](double pct) {
        return f.top + f.inner_h() * (1 - std::clamp(pct, 0.0, 100.0) / 100);
    };
    std::string s =
        fmt::format(R"(<svg class="plot-svg" id="plot-s" viewBox="0 0 {} {}">)", f.width, f.height);
    s += plot_axes(f, layers, 100, 25, "%");
    const int series = cavities + 2;
    std::vector<double> below(layers.size(), 0.0), above(layers.size(), 0.0);
    for (int k = 0; k < series; ++k) {
        for (size_t i = 0; i < layers.size(); ++i) {
            const ReportLayer& l = layers[i];
            double v = 0;
            if (k == 0)
                v = l.covers_mm2;
            else if (k <= cavities)
                v = size_t(k - 1) < l.cavity_mm2.size() ? l.cavity_mm2[k - 1] : 0;
            else
                v = l.remainder_mm2;
            above[i] = below[i] + (l.outline_mm2 > 0 ? 100 * v / l.outline_mm2 : 0);
        }
        std::string d;
        for (size_t i = 0; i < layers.size(); ++i)
            d += fmt::format("{}{:.1f} {:.1f}", i ? "L" : "M", f.x(double(i)), y(above[i]));
        for (size_t i = layers.size(); i-- > 0;)
            d += fmt::format("L{:.1f} {:.1f}", f.x(double(i)), y(below[i]));
        d += "Z";
        const std::string color = k == 0          ? kCoverColor
                                  : k <= cavities ? cavity_colour(k)
                                                  : kRemainderColor;
        s += fmt::format(R"(<path d="{}" fill="{}" fill-opacity="{}"/>)", d, color,
                         k == 0          ? 0.75
                         : k <= cavities ? 0.55
                                         : 0.8);
        below.swap(above);
    }
    s += plot_cursor(f);
    s += "</svg>";
    return s;
}

std::string chip(const std::string& color, const std::string& label) {
    return fmt::format(R"(<span class="chip"><i style="background:{}"></i><span>{}</span></span>)",
                       color, label);
}

std::string fixed(double v, int decimals) {
    return fmt::format("{:.{}f}", v, decimals);
}

// Three significant figures, for volumes from a few mm^3 to litres.
std::string sig3(double v) {
    const double a = std::fabs(v);
    if (a >= 100) return fmt::format("{:.0f}", v);
    if (a >= 10) return fmt::format("{:.1f}", v);
    return fmt::format("{:.2f}", v);
}

}  // namespace carve::html

// The HTML report: per-layer reduction on arrival (numbers in memory, drawing spilled to a
// temporary file), then one pass at the end that writes the page bottom up.
#include "report/html_report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <utility>

#include "base/error.hpp"
#include "geometry/polygon.hpp"
#include "report/stats.hpp"
#include "report/svg.hpp"

namespace carve {

namespace html {

namespace {

double segment_distance(const Point& p, const Point& a, const Point& b) {
    const double dx = double(b.X - a.X), dy = double(b.Y - a.Y);
    const double px = double(p.X - a.X), py = double(p.Y - a.Y);
    const double len2 = dx * dx + dy * dy;
    double t = len2 > 0 ? (px * dx + py * dy) / len2 : 0.0;
    t = std::clamp(t, 0.0, 1.0);
    return std::hypot(px - t * dx, py - t * dy);
}

// Numbers in path data: a minus sign separates on its own, so only positives need a space.
void append_number(std::string& out, long long v, bool after_command) {
    if (!after_command && v >= 0) out += ' ';
    out += std::to_string(v);
}

}  // namespace

Path simplify_path(const Path& path, bool closed, double tolerance) {
    if (path.size() < 3 || tolerance <= 0) return path;
    Path pts = path;
    if (closed) pts.push_back(path.front());
    const size_t n = pts.size();
    std::vector<char> keep(n, 0);
    keep[0] = keep[n - 1] = 1;
    std::vector<std::pair<size_t, size_t>> stack;
    if (closed) {
        // A loop starts and ends on the same point: split it at the point farthest from it.
        size_t far = 1;
        double best = -1;
        for (size_t i = 1; i + 1 < n; ++i) {
            const double d = std::hypot(double(pts[i].X - pts[0].X), double(pts[i].Y - pts[0].Y));
            if (d > best) best = d, far = i;
        }
        keep[far] = 1;
        stack.push_back({0, far});
        stack.push_back({far, n - 1});
    } else {
        stack.push_back({0, n - 1});
    }
    while (!stack.empty()) {
        const auto [a, b] = stack.back();
        stack.pop_back();
        if (b <= a + 1) continue;
        size_t worst = a;
        double worst_d = -1;
        for (size_t i = a + 1; i < b; ++i) {
            const double d = segment_distance(pts[i], pts[a], pts[b]);
            if (d > worst_d) worst_d = d, worst = i;
        }
        if (worst_d > tolerance) {
            keep[worst] = 1;
            stack.push_back({a, worst});
            stack.push_back({worst, b});
        }
    }
    Path out;
    for (size_t i = 0; i < n; ++i)
        if (keep[i]) out.push_back(pts[i]);
    if (closed && out.size() > 1) out.pop_back();
    return out;
}

std::string svg_path_data(const Paths& paths, bool closed, double tolerance, Coord grid) {
    std::string out;
    const double g = double(std::max<Coord>(grid, 1));
    std::vector<std::pair<long long, long long>> q;
    for (const Path& path : paths) {
        const Path simple = simplify_path(path, closed, tolerance);
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

}  // namespace html

namespace {

constexpr Coord kGrid = 10;  // drawing grid, micrometres (0.01 mm)
// Simplification tolerances tried in turn until a layer's drawing fits its share of the budget.
constexpr std::array<double, 4> kTolerances = {50, 100, 200, 400};
// Cavity colours: cool hues, none close to the bridges' magenta or the covers' ochre.
constexpr std::array<const char*, 8> kCavityColors = {"#1c7ed6", "#0ca678", "#7048e8", "#15aabf",
                                                      "#74b816", "#364fc7", "#087f5b", "#4dabf7"};
constexpr const char* kOuterColor = "#e8590c";
constexpr const char* kShellColor = "#f59f00";
constexpr const char* kCoverColor = "#d9a441";
constexpr const char* kBridgeColor = "#ff00ff";
constexpr const char* kRemainderColor = "#ced4da";

const char* cavity_color(int j) {
    return kCavityColors[size_t(std::max(j - 1, 0)) % kCavityColors.size()];
}
int cavity_class(int j) {
    return (std::max(j - 1, 0) % int(kCavityColors.size())) + 1;
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

// Geometry shared by the two plots (SVG user units); the page's script uses it for the cursor.
struct PlotFrame {
    double width = 640, height = 240, left = 56, right = 12, top = 24, bottom = 38;
    int n = 1;
    double inner_w() const { return width - left - right; }
    double inner_h() const { return height - top - bottom; }
    double x(double pos) const { return left + (pos + 0.5) * inner_w() / n; }
};

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

std::string material_plot(const std::vector<ReportLayer>& layers, const PlotFrame& f) {
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
        const char* color = k == 0          ? kCoverColor
                            : k <= cavities ? cavity_color(k)
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

std::string chip(const char* color, const std::string& label) {
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

const char* kCss = R"CSS(
:root{--bg:#f3f4f6;--card:#fff;--ink:#1d2433;--muted:#6b7280;--line:#e5e7eb;--accent:#1c7ed6}
*{box-sizing:border-box}
body{margin:0;background:var(--bg);color:var(--ink);font:14px/1.45 system-ui,-apple-system,"Segoe UI",Roboto,"Helvetica Neue",Arial,sans-serif}
header.top{display:flex;align-items:center;gap:18px;padding:14px 28px;background:#111827;color:#f9fafb}
.brand{font-weight:800;font-size:20px;letter-spacing:.04em;padding:5px 12px;border-radius:8px;background:linear-gradient(135deg,#1c7ed6,#7048e8)}
header h1{margin:0;font-size:19px;font-weight:650}
header .sub{color:#9ca3af;font-size:13px}
main{max-width:1400px;margin:0 auto;padding:16px 22px 36px}
.cards{display:grid;grid-template-columns:repeat(5,minmax(0,1fr));gap:12px}
.card,.panel{background:var(--card);border-radius:12px;box-shadow:0 1px 2px rgba(16,24,40,.05),0 1px 4px rgba(16,24,40,.08)}
.card{padding:12px 16px 14px}
.label{font-size:11.5px;text-transform:uppercase;letter-spacing:.07em;color:var(--muted);font-weight:650}
.big{font-size:29px;font-weight:720;margin:2px 0 2px;font-variant-numeric:tabular-nums;white-space:nowrap}
.unit{font-size:15px;font-weight:600;color:var(--muted);margin-left:2px}
.small{font-size:12.5px;color:var(--muted)}
.card.good .big{color:#087f5b}
.bars{margin:6px 0 4px}
.bar{display:flex;align-items:center;gap:6px;font-size:11.5px;color:var(--muted);margin:2px 0}
.bar b{display:block;height:9px;border-radius:5px;min-width:2px}
.bar span{white-space:nowrap}
.panel{margin-top:14px;padding:14px 16px}
.viewer{display:grid;grid-template-columns:minmax(0,1fr) 318px;gap:16px}
.view-wrap{position:relative;background:#fcfcfd;border:1px solid var(--line);border-radius:10px;overflow:hidden}
#view{display:block;width:100%;height:640px;cursor:grab;touch-action:none}
#view.dragging{cursor:grabbing}
.zoom{position:absolute;right:10px;top:10px;display:flex;gap:4px}
.zoom button,.controls button{font:inherit;font-size:13px;border:1px solid var(--line);background:#fff;border-radius:7px;padding:3px 10px;cursor:pointer;color:var(--ink)}
.zoom button:hover,.controls button:hover{background:#f3f4f6}
.hint{position:absolute;left:12px;top:12px;font-size:11.5px;color:#9ca3af}
.side h2{margin:0;font-size:22px;font-weight:720;font-variant-numeric:tabular-nums}
.side .z{color:var(--muted);font-size:13px;margin-bottom:8px}
#slider{width:100%;accent-color:var(--accent);margin:4px 0 6px}
.controls{display:flex;gap:6px;margin-bottom:12px}
.legend{display:grid;grid-template-columns:1fr;gap:3px;border-top:1px solid var(--line);padding-top:10px}
.legend label{display:flex;align-items:center;gap:8px;font-size:13px;cursor:pointer;user-select:none}
.legend input{margin:0;accent-color:#4b5563}
.sw{display:inline-block;width:22px;height:6px;border-radius:3px}
.sw.fill{height:12px;border-radius:3px;opacity:.55}
.cavsw{display:inline-flex;gap:2px}.cavsw .sw{width:9px}
dl.figs{display:grid;grid-template-columns:auto 1fr;gap:3px 12px;margin:12px 0 0;padding-top:10px;border-top:1px solid var(--line);font-size:13px}
dl.figs dt{color:var(--muted)}dl.figs dd{margin:0;text-align:right;font-variant-numeric:tabular-nums}
.note{font-size:12px;color:var(--muted);margin:10px 0 0}
.plots{display:grid;grid-template-columns:1fr 1fr;gap:22px}
.plots h3{margin:0;font-size:15px}
.plots .cap{margin:2px 0 0;font-size:12.5px;color:var(--muted)}
.chip{display:inline-flex;align-items:center;gap:5px;margin-right:12px;font-size:12.5px;color:var(--muted)}
.chip i{display:inline-block;width:12px;height:12px;border-radius:3px}
.plot-svg{width:100%;height:auto;display:block;cursor:crosshair}
.plot-svg .grid{stroke:#eef0f3;stroke-width:1}
.plot-svg text{font-size:11px;fill:#8b93a1}
.plot-svg .ytick,.plot-svg .yunit{text-anchor:end}.plot-svg .xlabel,.plot-svg .xunit{text-anchor:middle}
.plot-svg .xtick{stroke:#c4c9d2}
.plot-svg .carve-area{fill:#1c7ed6;fill-opacity:.18}
.plot-svg .carve-line{fill:none;stroke:#1c7ed6;stroke-width:1.6;stroke-linejoin:round}
.plot-svg .conv{fill:none;stroke:#6b7280;stroke-width:1.4;stroke-dasharray:5 3}
.plot-svg .cursor{stroke:#111827;stroke-width:1.2;stroke-dasharray:2 2}
.details h2{font-size:16px;margin:0 0 8px}
.details .cols{display:grid;grid-template-columns:1.3fr 1fr;gap:28px}
.formula{font-family:ui-monospace,SFMono-Regular,Menlo,Consolas,monospace;background:#f6f7f9;border-radius:8px;padding:8px 10px;font-size:12.5px;overflow-x:auto}
table.settings{border-collapse:collapse;width:100%;font-size:13px}
table.settings td{padding:3px 6px;border-bottom:1px solid #f0f1f3}
table.settings td:last-child{text-align:right;font-variant-numeric:tabular-nums}
.warn{color:#b45309}
details pre{background:#f6f7f9;border-radius:8px;padding:10px;font-size:12px;max-height:360px;overflow:auto}
footer{text-align:center;color:#9ca3af;font-size:12px;padding:0 0 24px}
#view path{fill:none;stroke-linecap:round;stroke-linejoin:round}
#view path.O{fill:#eef1f4;stroke:none;fill-rule:evenodd}
#view path.r{stroke:none;fill-rule:evenodd;fill-opacity:.16}
#view path.g{stroke:#c9ced6}
#view .ruler line{stroke:#6b7280}
#view .ruler text{fill:#6b7280}
#view.hide-O .O,#view.hide-o .o,#view.hide-o .s,#view.hide-c .c,#view.hide-w .w,#view.hide-b .b,#view.hide-r .r,#view.hide-g .g{display:none}
@media (max-width:1100px){.cards{grid-template-columns:repeat(2,minmax(0,1fr))}.viewer,.plots,.details .cols{grid-template-columns:1fr}}
)CSS";

const char* kScript = R"JS(
(function () {
  'use strict';
  const L = LAYERS, N = L.length, M = META;
  const view = document.getElementById('view');
  const layerG = document.getElementById('layer'), ghostG = document.getElementById('ghost');
  const slider = document.getElementById('slider');
  const cursors = Array.from(document.querySelectorAll('.plot-svg .cursor'));
  let current = -1;
  const fmt = (v, d) => (v === undefined || v === null) ? '\u2014' : Number(v).toFixed(d);
  const drawn = k => L[k] && L[k].P !== undefined;
  function drawnBelow(k) {
    for (; k >= 0; k--) if (drawn(k)) return k;
    return -1;
  }
  function nearestDrawn(k) {
    for (let d = 0; d < N; d++) {
      if (k - d >= 0 && drawn(k - d)) return k - d;
      if (k + d < N && drawn(k + d)) return k + d;
    }
    return -1;
  }
  function paths(r, ghost) {
    let h = '';
    if (!r || r.P === undefined) return h;
    if (ghost) {
      for (const p of r.P) h += '<path class="g" d="' + p[2] + '"/>';
      return h;
    }
    if (r.O) h += '<path class="O" d="' + r.O + '"/>';
    for (const c of r.R) h += '<path class="r k' + c[0] + '" d="' + c[1] + '"/>';
    for (const p of r.P) h += '<path class="' + p[0] + (p[0] === 'w' ? ' k' + p[1] : '') + '" d="' + p[2] + '"/>';
    return h;
  }
  function row(k, v) { return '<dt>' + k + '</dt><dd>' + v + '</dd>'; }
  function show(k) {
    k = Math.max(0, Math.min(N - 1, k | 0));
    current = k;
    slider.value = k;
    const r = L[k], d = nearestDrawn(k);
    layerG.innerHTML = d >= 0 ? paths(L[d], false) : '';
    const below = d > 0 ? drawnBelow(d - 1) : -1;
    ghostG.innerHTML = below >= 0 ? paths(L[below], true) : '';
    document.getElementById('lnum').textContent = 'Layer ' + (r.i + 1) + ' of ' + M.layers;
    document.getElementById('lz').textContent = 'z = ' + fmt(r.z, 2) + ' mm';
    let f = '';
    f += row('material', fmt(r.m, 1) + ' mm\u00b3');
    f += row('15 % infill estimate', fmt(r.v, 1) + ' mm\u00b3');
    f += row('slice area', fmt(r.a[0], 0) + ' mm\u00b2');
    f += row('covers', fmt(r.a[1], 0) + ' mm\u00b2');
    let cav = 0;
    r.C.forEach(function (c, j) {
      if (c <= 0) return;
      cav += c;
      f += row('<span class="sw" style="background:' + M.colors[j % M.colors.length] + '"></span> cavity ' + (j + 1), fmt(c, c < 10 ? 1 : 0) + ' mm\u00b2');
    });
    f += row('hollow share', r.a[0] > 0 ? fmt(100 * cav / r.a[0], 1) + ' %' : '\u2014');
    f += row('bridges', r.b + (r.b ? ' (' + fmt(r.l[3], 0) + ' mm)' : ''));
    f += row('walls / covers', fmt(r.l[0] + r.l[2], 0) + ' / ' + fmt(r.l[1], 0) + ' mm');
    document.getElementById('figs').innerHTML = f;
    let note = '';
    if (d !== k && d >= 0) note = 'Drawing of layer ' + (L[d].i + 1) + ' shown: only one layer in ' + M.stride + ' is drawn in this page. ';
    if (d >= 0) note += 'Paths simplified to ' + fmt(L[d].t, 2) + ' mm.';
    document.getElementById('note').textContent = note;
    cursors.forEach(function (c) {
      const x = M.plot.left + (k + 0.5) * M.plot.w / N;
      c.setAttribute('x1', x); c.setAttribute('x2', x);
    });
  }
  slider.addEventListener('input', function () { show(+slider.value); });
  document.getElementById('up').onclick = function () { show(current + 1); };
  document.getElementById('down').onclick = function () { show(current - 1); };
  let timer = null;
  const play = document.getElementById('play');
  play.onclick = function () {
    if (timer) { clearInterval(timer); timer = null; play.textContent = '\u25b6 play'; return; }
    if (current >= N - 1) show(0);
    play.textContent = '\u275a\u275a pause';
    timer = setInterval(function () {
      if (current >= N - 1) { play.onclick(); return; }
      show(current + 1);
    }, Math.max(15, Math.min(120, 6000 / N)));
  };
  document.addEventListener('keydown', function (e) {
    if (e.target && e.target.tagName === 'INPUT' && e.target.type === 'range') return;
    const step = { ArrowUp: 1, ArrowRight: 1, ArrowDown: -1, ArrowLeft: -1, PageUp: 10, PageDown: -10 }[e.key];
    if (step) { show(current + step); e.preventDefault(); }
    if (e.key === 'Home') show(0);
    if (e.key === 'End') show(N - 1);
  });
  document.querySelectorAll('.legend input').forEach(function (box) {
    const apply = function () { view.classList.toggle('hide-' + box.dataset.k, !box.checked); };
    box.addEventListener('change', apply);
    apply();
  });
  // Zoom about the pointer and pan by dragging; the base view box fits the whole model.
  const vb0 = M.viewBox.slice();
  let vb = vb0.slice();
  const setVB = function () { view.setAttribute('viewBox', vb.join(' ')); };
  function toUser(cx, cy) {
    const r = view.getBoundingClientRect();
    const s = Math.max(vb[2] / r.width, vb[3] / r.height);
    const ox = vb[0] - (r.width * s - vb[2]) / 2, oy = vb[1] - (r.height * s - vb[3]) / 2;
    return [ox + (cx - r.left) * s, oy + (cy - r.top) * s, s];
  }
  function zoom(f, cx, cy) {
    const r = view.getBoundingClientRect();
    if (cx === undefined) { cx = r.left + r.width / 2; cy = r.top + r.height / 2; }
    const u = toUser(cx, cy);
    vb = [u[0] - (u[0] - vb[0]) * f, u[1] - (u[1] - vb[1]) * f, vb[2] * f, vb[3] * f];
    setVB();
  }
  view.addEventListener('wheel', function (e) { e.preventDefault(); zoom(Math.exp(e.deltaY * 0.0015), e.clientX, e.clientY); }, { passive: false });
  let drag = null;
  view.addEventListener('pointerdown', function (e) { drag = [e.clientX, e.clientY]; view.classList.add('dragging'); view.setPointerCapture(e.pointerId); });
  view.addEventListener('pointermove', function (e) {
    if (!drag) return;
    const s = toUser(e.clientX, e.clientY)[2];
    vb[0] -= (e.clientX - drag[0]) * s; vb[1] -= (e.clientY - drag[1]) * s;
    drag = [e.clientX, e.clientY];
    setVB();
  });
  const endDrag = function () { drag = null; view.classList.remove('dragging'); };
  view.addEventListener('pointerup', endDrag);
  view.addEventListener('pointercancel', endDrag);
  view.addEventListener('dblclick', function () { vb = vb0.slice(); setVB(); });
  document.getElementById('zin').onclick = function () { zoom(1 / 1.5); };
  document.getElementById('zout').onclick = function () { zoom(1.5); };
  document.getElementById('zfit').onclick = function () { vb = vb0.slice(); setVB(); };
  document.querySelectorAll('.plot-svg').forEach(function (svg) {
    svg.addEventListener('click', function (e) {
      const r = svg.getBoundingClientRect();
      const x = (e.clientX - r.left) * M.plot.width / r.width;
      show(Math.floor((x - M.plot.left) / M.plot.w * N));
    });
  });
  const fromHash = /layer=(\d+)/.exec(location.hash);
  show(fromHash ? +fromHash[1] - 1 : M.start);
})();
)JS";

}  // namespace

struct HtmlReportWriter::Impl {
    std::string path;
    std::string tmp_path;
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

    std::string drawing(const LayerPartition& layer, const LayerToolpaths& paths, double tol) const;
};

std::string HtmlReportWriter::Impl::drawing(const LayerPartition& layer,
                                            const LayerToolpaths& paths, double tol) const {
    nlohmann::json rec;
    rec["t"] = rounded(tol / kUnitsPerMm, 3);
    rec["O"] = html::svg_path_data(layer.outline, true, tol, kGrid);
    nlohmann::json regions = nlohmann::json::array();
    for (size_t j = 0; j < layer.cavities.size(); ++j) {
        if (layer.cavities[j].empty()) continue;
        std::string d = html::svg_path_data(layer.cavities[j], true, tol, kGrid);
        if (!d.empty()) regions.push_back({cavity_class(int(j) + 1), std::move(d)});
    }
    rec["R"] = std::move(regions);
    // One path element per feature (and per cavity for cavity walls), drawn in this order so
    // that bridges come out on top.
    std::map<std::pair<int, int>, std::string> groups;
    for (const Extrusion& e : paths.extrusions) {
        int kind = 0, j = 0;
        switch (e.feature) {
            case Feature::OuterWall:
                kind = 0;
                break;
            case Feature::Shell:
                kind = 1;
                break;
            case Feature::Cover:
                kind = 2;
                break;
            case Feature::CavityWall:
                kind = 3, j = cavity_class(e.cavity);
                break;
            case Feature::Bridge:
                kind = 4;
                break;
        }
        groups[{kind, j}] += html::svg_path_data(Paths{e.points}, e.closed, tol, kGrid);
    }
    static constexpr const char* kKinds[] = {"o", "s", "c", "w", "b"};
    nlohmann::json drawn = nlohmann::json::array();
    for (auto& [key, d] : groups)
        if (!d.empty()) drawn.push_back({kKinds[key.first], key.second, std::move(d)});
    rec["P"] = std::move(drawn);
    std::string s = rec.dump();
    return s.substr(1, s.size() - 2);  // the members only: merged with the numbers at the end
}

HtmlReportWriter::HtmlReportWriter(std::string path, const Settings& settings)
    : impl_(std::make_unique<Impl>()) {
    impl_->path = std::move(path);
    impl_->tmp_path = impl_->path + ".tmp";
    impl_->settings = settings;
    impl_->spill = std::tmpfile();
    if (!impl_->spill) throw InputError("cannot create a temporary file for the HTML report");
}

HtmlReportWriter::~HtmlReportWriter() {
    if (impl_->spill) std::fclose(impl_->spill);
    if (!impl_->finished) {
        std::error_code ec;
        std::filesystem::remove(impl_->tmp_path, ec);
    }
}

void HtmlReportWriter::set_model_name(std::string path) {
    impl_->model_name = std::move(path);
}

void HtmlReportWriter::set_budget(size_t bytes) {
    impl_->budget = std::max<size_t>(bytes, 1024);
}

const std::vector<ReportLayer>& HtmlReportWriter::layers() const {
    return impl_->layers;
}

void HtmlReportWriter::add_layer(const LayerPartition& layer, const LayerToolpaths& paths) {
    Impl& m = *impl_;
    const Settings& st = m.settings;
    ReportLayer r;
    r.index = layer.index;
    r.z = paths.index == layer.index && paths.z > 0 ? paths.z : (layer.index + 1) * st.layer_height;
    r.outline_mm2 = area_mm2(layer.outline);
    r.perimeter_mm = length(layer.outline, true) / kUnitsPerMm;
    r.covers_mm2 = area_mm2(layer.covers);
    r.carvable_mm2 = area_mm2(layer.carvable);
    r.remainder_mm2 = area_mm2(layer.remainder);
    for (const Paths& c : layer.cavities) r.cavity_mm2.push_back(area_mm2(c));
    while (!r.cavity_mm2.empty() && r.cavity_mm2.back() <= 0) r.cavity_mm2.pop_back();
    m.max_cavities = std::max(m.max_cavities, int(r.cavity_mm2.size()));
    r.bridges = int(layer.bridges.size());
    const double w = st.nozzle, h = st.layer_height;
    for (const Extrusion& e : paths.extrusions) {
        const double len = length(Paths{e.points}, e.closed) / kUnitsPerMm;
        r.material_mm3 += len * w * h * e.flow;
        switch (e.feature) {
            case Feature::OuterWall:
            case Feature::Shell:
                r.wall_mm += len;
                break;
            case Feature::Cover:
                r.cover_mm += len;
                break;
            case Feature::CavityWall:
                r.cavity_wall_mm += len;
                break;
            case Feature::Bridge:
                r.bridge_mm += len;
                break;
        }
    }
    // What a conventional slicer would extrude on the same slice: two perimeters, solid where
    // this layer has covers, 15 % grid in the rest of the interior.
    r.conventional_mm3 = 2 * r.perimeter_mm * w * h + r.covers_mm2 * h + 0.15 * r.carvable_mm2 * h;

    expand(m.box, bounds(layer.outline.empty() ? layer.wall_region : layer.outline));

    // The first layer to arrive is the top one: its index tells how many will follow.
    if (m.expected_layers == 0) m.expected_layers = layer.index + 1;
    const size_t share =
        m.budget / size_t(std::max<int>(m.expected_layers, int(m.layers.size()) + 1));
    std::string d;
    for (double tol : kTolerances) {
        d = m.drawing(layer, paths, tol);
        r.tolerance_mm = tol / kUnitsPerMm;
        if (d.size() <= share) break;
    }
    r.offset = m.spilled;
    r.bytes = long(d.size());
    if (std::fwrite(d.data(), 1, d.size(), m.spill) != d.size())
        throw InputError("cannot write the HTML report's temporary file");
    m.spilled += r.bytes;
    m.layers.push_back(std::move(r));
}

void HtmlReportWriter::finish(const RunResult& run, const nlohmann::json& stats) {
    Impl& m = *impl_;
    const Settings& st = m.settings;
    std::vector<ReportLayer>& layers = m.layers;
    // Bottom up for the page; remember where each layer's drawing lies in the spill file.
    std::sort(layers.begin(), layers.end(),
              [](const ReportLayer& a, const ReportLayer& b) { return a.index < b.index; });
    const size_t n = layers.size();

    // If the drawings still exceed the budget, keep every stride-th (and the top and bottom).
    int stride = 1;
    if (m.spilled > 0 && size_t(m.spilled) > m.budget + m.budget / 8)
        stride = int(std::ceil(double(m.spilled) / double(m.budget)));
    auto keep_drawing = [&](size_t i) { return stride == 1 || i % stride == 0 || i + 1 == n; };

    // Totals.
    double material_sum = 0, conventional = 0, best_score = -1;
    size_t start = n / 2;
    for (size_t i = 0; i < n; ++i) {
        material_sum += layers[i].material_mm3;
        conventional += layers[i].conventional_mm3;
        // The page opens on the layer that shows the carving best: most cavities present, then
        // the most cavity wall, then a bridge.
        int present = 0;
        for (double a : layers[i].cavity_mm2) present += a > 1.0;
        const double score = present * 1e6 + layers[i].cavity_wall_mm + (layers[i].bridges > 0);
        if (score > best_score && keep_drawing(i)) best_score = score, start = i;
    }
    const double material =
        run.print.extruded_volume_mm3 > 0 ? run.print.extruded_volume_mm3 : material_sum;
    const double filament_area = std::numbers::pi * st.filament_diameter * st.filament_diameter / 4;
    const double filament_m = run.print.filament_length_mm > 0 ? run.print.filament_length_mm / 1000
                                                               : material / filament_area / 1000;
    const double grams = run.print.filament_weight_g > 0 ? run.print.filament_weight_g
                                                         : material / 1000 * st.filament_density;
    const double conventional_g = conventional / 1000 * st.filament_density;
    const double model_volume = run.mesh.volume_mm3;
    const int layer_count = run.layers > 0 ? run.layers : int(n);
    double carved = 0;
    for (double v : run.cavity_volume_mm3) carved += v;
    int cavities = run.cavities > 0 ? run.cavities : m.max_cavities;
    int bridges = run.bridges;
    if (bridges == 0)
        for (const ReportLayer& l : layers) bridges += l.bridges;

    std::string model = m.model_name.empty()
                            ? std::string("model")
                            : std::filesystem::path(m.model_name).filename().string();
    if (stats.is_object()) {
        for (const char* key : {"model", "model_path", "input"}) {
            if (stats.contains(key) && stats[key].is_string()) {
                model = std::filesystem::path(stats[key].get<std::string>()).filename().string();
                break;
            }
        }
    }

    std::string date;
    {
        const std::time_t now = std::time(nullptr);
        char buf[64];
        if (std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M", std::localtime(&now))) date = buf;
    }

    std::ofstream out(m.tmp_path, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError("cannot write the HTML report " + m.tmp_path);

    const double grid = double(kGrid);
    const double line_w = st.nozzle * kUnitsPerMm / grid;  // stroke width in drawing units
    out << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
           "<meta name=\"viewport\" content=\"width=device-width,initial-scale=1\">\n";
    out << "<title>carve report: " << xml_escape(model) << "</title>\n<style>" << kCss;
    out << fmt::format("#view .o{{stroke:{};stroke-width:{:.1f}px}}\n", kOuterColor, 0.85 * line_w);
    out << fmt::format("#view .s{{stroke:{};stroke-width:{:.1f}px}}\n", kShellColor, 0.85 * line_w);
    out << fmt::format("#view .c{{stroke:{};stroke-width:{:.1f}px}}\n", kCoverColor, 0.7 * line_w);
    out << fmt::format("#view .w{{stroke-width:{:.1f}px}}\n", 0.75 * line_w);
    out << fmt::format("#view .g{{stroke-width:{:.1f}px}}\n", 0.6 * line_w);
    out << fmt::format("#view .b{{stroke:{};stroke-width:{:.1f}px;stroke-linecap:butt}}\n",
                       kBridgeColor, 1.3 * line_w);
    for (size_t k = 0; k < kCavityColors.size(); ++k)
        out << fmt::format("#view .w.k{0}{{stroke:{1}}} #view .r.k{0}{{fill:{1}}}\n", k + 1,
                           kCavityColors[k]);
    out << "</style>\n</head>\n<body>\n";

    // Header.
    const std::string preset =
        fmt::format("{} layers of {} mm, nozzle {} mm, {} cavities, {} covers, {} shells, {} walls",
                    layer_count, st.layer_height, st.nozzle,
                    st.cavities_auto ? std::string("auto") : std::to_string(st.cavities), st.covers,
                    st.shells, st.walls == WallMode::Single ? "single-filament" : "double");
    out << "<header class=\"top\"><div class=\"brand\">carve</div><div><h1>" << xml_escape(model)
        << "</h1><div class=\"sub\">" << xml_escape(preset) << " &middot; " << xml_escape(date)
        << "</div></div></header>\n<main>\n";

    // Cards.
    out << "<section class=\"cards\">\n";
    out << "<div class=\"card\"><div class=\"label\">Material</div><div class=\"big\">"
        << fixed(material / 1000, 2) << "<span class=\"unit\">cm³</span></div><div class=\"small\">"
        << (model_volume > 0 ? fixed(100 * material / model_volume, 1) + " % of the model's volume"
                             : std::string("model volume unknown"))
        << "<br>" << fixed(grams, 1) << " g &middot; " << fixed(filament_m, 2) << " m of "
        << st.filament_diameter << " mm filament</div></div>\n";
    if (conventional > 0) {
        const double saving = 100 * (1 - material / conventional);
        const double frac = std::clamp(material / conventional, 0.0, 1.0);
        out << "<div class=\"card good\"><div class=\"label\">Saved against 15 % infill</div>"
            << "<div class=\"big\">" << fixed(saving, 0) << "<span class=\"unit\">%</span></div>"
            << "<div class=\"bars\"><div class=\"bar\"><b style=\"width:" << fixed(70 * frac, 1)
            << "%;background:#1c7ed6\"></b><span>carve " << sig3(material / 1000)
            << " cm³</span></div><div class=\"bar\"><b style=\"width:70%;background:#9ca3af\"></b>"
            << "<span>infill " << sig3(conventional / 1000) << " cm³</span></div></div>"
            << "<div class=\"small\">" << fixed(conventional_g - grams, 1)
            << " g less filament (estimate, see below)</div></div>\n";
    } else {
        out << "<div class=\"card\"><div class=\"label\">Saved against 15 % infill</div>"
               "<div class=\"big\">&mdash;</div></div>\n";
    }
    out << "<div class=\"card\"><div class=\"label\">Estimated print time</div><div class=\"big\">"
        << (run.print.estimated_print_time_s > 0
                ? xml_escape(format_duration(run.print.estimated_print_time_s))
                : std::string("&mdash;"))
        << "</div><div class=\"small\">sliced in " << fixed(run.processing_time_s, 1) << " s";
    if (run.peak_memory_mb > 0) out << ", peak memory " << fixed(run.peak_memory_mb, 0) << " MB";
    if (run.print.retractions > 0) out << "<br>" << run.print.retractions << " retractions";
    out << "</div></div>\n";
    out << "<div class=\"card\"><div class=\"label\">Cavities</div><div class=\"big\">" << cavities
        << "<span class=\"unit\">nested</span></div><div class=\"small\">";
    if (model_volume > 0 && carved > 0)
        out << fixed(100 * carved / model_volume, 1) << " % of the volume left hollow<br>";
    out << bridges << (bridges == 1 ? " bridge" : " bridges");
    if (run.bridge_length_mm > 0) out << ", " << fixed(run.bridge_length_mm, 0) << " mm of lines";
    out << "</div></div>\n";
    const Vec3 size{run.mesh.bbox.max.x - run.mesh.bbox.min.x,
                    run.mesh.bbox.max.y - run.mesh.bbox.min.y,
                    run.mesh.bbox.max.z - run.mesh.bbox.min.z};
    out << "<div class=\"card\"><div class=\"label\">Model</div><div class=\"big\">"
        << (model_volume > 0 ? sig3(model_volume / 1000) : std::string("&mdash;"))
        << "<span class=\"unit\">cm³</span></div><div class=\"small\">" << run.mesh.triangles
        << " triangles &middot; " << layer_count << " layers<br>" << fixed(size.x, 1) << " × "
        << fixed(size.y, 1) << " × " << fixed(size.z, 1) << " mm</div></div>\n";
    out << "</section>\n";

    // Layer viewer.
    const double pad =
        std::max(2.0 * kUnitsPerMm,
                 0.04 * double(std::max(m.box.max_x - m.box.min_x, m.box.max_y - m.box.min_y))) /
        grid;
    const double bx0 = double(m.box.min_x) / grid, bx1 = double(m.box.max_x) / grid;
    const double by0 = double(m.box.min_y) / grid, by1 = double(m.box.max_y) / grid;
    const std::array<double, 4> vb = {std::floor(bx0 - pad), std::floor(-by1 - pad),
                                      std::ceil(bx1 - bx0 + 2 * pad),
                                      std::ceil(by1 - by0 + 2.6 * pad)};
    // A ruler under the model, in model units so that it zooms with the drawing.
    const double span_mm = (bx1 - bx0) * grid / kUnitsPerMm;
    double ruler_mm = nice_step(std::max(span_mm, 1.0), 4);
    if (ruler_mm > span_mm) ruler_mm /= 2;
    const double ry = -by0 + 0.9 * pad, rlen = ruler_mm * kUnitsPerMm / grid;
    out << "<section class=\"panel viewer\">\n<div class=\"view-wrap\"><svg id=\"view\" viewBox=\""
        << vb[0] << ' ' << vb[1] << ' ' << vb[2] << ' ' << vb[3] << "\">"
        << "<g transform=\"scale(1,-1)\"><g id=\"ghost\"></g><g id=\"layer\"></g></g>"
        << fmt::format(
               "<g class=\"ruler\"><line x1=\"{0:.0f}\" y1=\"{1:.0f}\" x2=\"{2:.0f}\" "
               "y2=\"{1:.0f}\" stroke-width=\"{3:.1f}\"/><line x1=\"{0:.0f}\" "
               "y1=\"{4:.0f}\" x2=\"{0:.0f}\" y2=\"{5:.0f}\" stroke-width=\"{3:.1f}\"/>"
               "<line x1=\"{2:.0f}\" y1=\"{4:.0f}\" x2=\"{2:.0f}\" y2=\"{5:.0f}\" "
               "stroke-width=\"{3:.1f}\"/><text x=\"{6:.0f}\" y=\"{7:.0f}\" "
               "font-size=\"{8:.0f}\">{9} mm</text></g>",
               bx0, ry, bx0 + rlen, vb[3] / 500, ry - pad * 0.15, ry + pad * 0.15,
               bx0 + rlen + pad * 0.3, ry + pad * 0.2, vb[3] / 38, tick_label(ruler_mm, ruler_mm))
        << "</svg>"
        << "<div class=\"zoom\"><button id=\"zin\" title=\"zoom in\">+</button><button id=\"zout\" "
           "title=\"zoom out\">&minus;</button><button id=\"zfit\">fit</button></div>"
        << "<div class=\"hint\">scroll to zoom &middot; drag to pan &middot; double-click to fit "
           "&middot; arrow keys change layer</div></div>\n";
    out << "<aside class=\"side\"><h2 id=\"lnum\">Layer</h2><div class=\"z\" id=\"lz\"></div>"
        << "<input type=\"range\" id=\"slider\" min=\"0\" max=\"" << (n ? n - 1 : 0)
        << "\" value=\"" << start << "\" aria-label=\"layer\">"
        << "<div class=\"controls\"><button id=\"down\" title=\"layer below\">&#9660;</button>"
           "<button id=\"play\">&#9654; play</button><button id=\"up\" title=\"layer above\">"
           "&#9650;</button></div>\n<div class=\"legend\">";
    auto toggle = [&](const char* key, const std::string& swatch, const std::string& label,
                      bool on) {
        out << "<label><input type=\"checkbox\" data-k=\"" << key << "\"" << (on ? " checked" : "")
            << ">" << swatch << label << "</label>";
    };
    auto sw = [](const char* color, bool fill = false) {
        return fmt::format("<span class=\"sw{}\" style=\"background:{}\"></span>",
                           fill ? " fill" : "", color);
    };
    toggle("o", sw(kOuterColor), st.shells > 0 ? "outer wall and shells" : "outer wall", true);
    toggle("c", sw(kCoverColor), "covers (solid top and bottom)", true);
    std::string cav_sw = "<span class=\"cavsw\">";
    for (int j = 1; j <= std::max(1, std::min(m.max_cavities, int(kCavityColors.size()))); ++j)
        cav_sw += sw(cavity_color(j));
    cav_sw += "</span>";
    toggle("w", cav_sw, "cavity walls, one colour per cavity", true);
    toggle("b", sw(kBridgeColor), "bridges", true);
    toggle("r", sw(kCavityColors[0], true), "cavity regions", true);
    toggle("O", sw("#dfe3e8"), "slice of the model", true);
    toggle("g", sw("#c9ced6"), "layer below", false);
    out << "</div>\n<dl class=\"figs\" id=\"figs\"></dl><p class=\"note\" id=\"note\"></p>"
        << "</aside>\n</section>\n";

    // Plots.
    PlotFrame frame;
    frame.n = int(std::max<size_t>(n, 1));
    out << "<section class=\"panel plots\">\n<div><h3>Material per layer</h3><p class=\"cap\">"
        << chip("#1c7ed6", "carve") << chip("#6b7280", "ordinary 15 % infill (estimate)")
        << "</p><p class=\"cap\">volume extruded in each layer; click a plot to show that layer"
        << "</p>" << material_plot(layers, frame) << "</div>\n";
    out << "<div><h3>What each slice is made of</h3><p class=\"cap\">"
        << chip(kCoverColor, "covers");
    for (int j = 1; j <= m.max_cavities; ++j)
        out << chip(cavity_color(j), fmt::format("C<sup>{}</sup>", j));
    out << chip(kRemainderColor, "remainder V<sup>k</sup>")
        << "</p><p class=\"cap\">share of each slice's area; the rest up to 100 % is the "
        << "outer wall's band</p>" << share_plot(layers, m.max_cavities, frame)
        << "</div>\n</section>\n";

    // How the figures are computed.
    double covers_mm3 = 0, carvable_mm3 = 0, perimeter_mm3 = 0;
    for (const ReportLayer& l : layers) {
        covers_mm3 += l.covers_mm2 * st.layer_height;
        carvable_mm3 += 0.15 * l.carvable_mm2 * st.layer_height;
        perimeter_mm3 += 2 * l.perimeter_mm * st.nozzle * st.layer_height;
    }
    int min_tol_layers = 0;
    double max_tol = 0;
    for (const ReportLayer& l : layers) {
        max_tol = std::max(max_tol, l.tolerance_mm);
        if (l.tolerance_mm <= kTolerances[0] / kUnitsPerMm + 1e-9) ++min_tol_layers;
    }
    out << "<section class=\"panel details\"><div class=\"cols\"><div>\n"
        << "<h2>How these figures are computed</h2>\n"
        << "<p>Material, filament and time come from the G-code writer (extrusion width "
        << st.nozzle << " mm &times; layer height " << st.layer_height
        << " mm &times; path length &times; flow). The per-layer plot adds up the print paths "
           "of each layer the same way.</p>\n"
        << "<p><b>Ordinary 15 % infill</b> is an estimate on the same slices of what a "
           "conventional slicer would extrude with 2 perimeters, solid top and bottom layers and "
           "a 15 % grid. For each layer:</p>\n<div class=\"formula\">V<sub>layer</sub> = 2 "
           "&middot; P &middot; w &middot; h + A<sub>covers</sub> &middot; h + 0.15 &middot; "
           "A<sub>interior</sub> &middot; h</div>\n"
        << "<p class=\"small\">P: length of the slice's outline; w = " << st.nozzle
        << " mm; h = " << st.layer_height
        << " mm; A<sub>covers</sub>: this layer's cover area (the solid layers near top and "
           "bottom surfaces, standing in for a conventional slicer's 3 top and 3 bottom layers); "
           "A<sub>interior</sub>: the carvable area. Over the whole model: perimeters "
        << sig3(perimeter_mm3 / 1000) << " cm³ + solid " << sig3(covers_mm3 / 1000)
        << " cm³ + infill " << sig3(carvable_mm3 / 1000) << " cm³ = " << sig3(conventional / 1000)
        << " cm³ (" << fixed(conventional_g, 1)
        << " g). It is an estimate: a real slicer's figure differs with its overlaps, gap "
           "fill and infill pattern.</p>\n"
        << "<p class=\"small\">Layer drawings: paths simplified (Douglas&ndash;Peucker) to "
        << fixed(kTolerances[0] / kUnitsPerMm, 2) << " mm and rounded to 0.01 mm";
    if (max_tol > kTolerances[0] / kUnitsPerMm + 1e-9)
        out << "; " << (n - size_t(min_tol_layers))
            << " busy layers were simplified further, up to " << fixed(max_tol, 2)
            << " mm, to keep this page small";
    if (stride > 1)
        out << "; only one layer in " << stride << " is drawn (the figures cover every layer)";
    out << ". Lines are drawn at " << 0.75 * st.nozzle << "&ndash;" << 0.85 * st.nozzle
        << " mm so that neighbours stay apart; bridges at " << 1.3 * st.nozzle << " mm.</p>\n";
    if (!run.mesh.warnings.empty()) {
        out << "<h2>What was repaired in the mesh</h2><ul>";
        for (const std::string& wline : run.mesh.warnings)
            out << "<li class=\"warn\">" << xml_escape(wline) << "</li>";
        out << "</ul>\n";
    }
    out << "</div><div>\n<h2>Settings</h2><table class=\"settings\">";
    auto setting = [&](const std::string& k, const std::string& v) {
        out << "<tr><td>" << k << "</td><td>" << xml_escape(v) << "</td></tr>";
    };
    setting("printer", st.printer_name);
    setting("layer height", fmt::format("{} mm", st.layer_height));
    setting("nozzle / line width", fmt::format("{} mm", st.nozzle));
    setting("max overhang", fmt::format("{}°", st.max_overhang));
    setting("cavities k", st.cavities_auto ? "auto" : std::to_string(st.cavities));
    setting("covers / shells", fmt::format("{} / {}", st.covers, st.shells));
    setting("cavity walls", st.walls == WallMode::Single ? "single filament" : "double");
    setting("filament", fmt::format("{} mm, {} g/cm³", st.filament_diameter, st.filament_density));
    setting("temperatures",
            fmt::format("{} °C nozzle, {} °C bed", st.nozzle_temperature, st.bed_temperature));
    out << "</table>\n<details><summary>Stats JSON</summary><pre>" << xml_escape(stats.dump(2))
        << "</pre></details>\n</div></div></section>\n</main>\n"
        << "<footer>Made by carve &middot; self-contained page, nothing is loaded from the "
           "network</footer>\n";

    // Data: one entry per layer, bottom up, the numbers then the drawing.
    out << "<script>\nconst LAYERS = [\n";
    std::string buf;
    for (size_t i = 0; i < n; ++i) {
        const ReportLayer& l = layers[i];
        nlohmann::ordered_json num;
        num["i"] = l.index;
        num["z"] = rounded(l.z, 3);
        num["m"] = rounded(l.material_mm3, 2);
        num["v"] = rounded(l.conventional_mm3, 2);
        num["a"] = {rounded(l.outline_mm2, 1), rounded(l.covers_mm2, 1), rounded(l.carvable_mm2, 1),
                    rounded(l.remainder_mm2, 1)};
        nlohmann::ordered_json cav = nlohmann::ordered_json::array();
        for (double a : l.cavity_mm2) cav.push_back(rounded(a, 1));
        num["C"] = std::move(cav);
        num["b"] = l.bridges;
        num["l"] = {rounded(l.wall_mm, 1), rounded(l.cover_mm, 1), rounded(l.cavity_wall_mm, 1),
                    rounded(l.bridge_mm, 1)};
        std::string entry = num.dump();
        if (keep_drawing(i) && l.bytes > 0) {
            buf.resize(size_t(l.bytes));
            if (std::fseek(m.spill, l.offset, SEEK_SET) != 0 ||
                std::fread(buf.data(), 1, buf.size(), m.spill) != buf.size())
                throw InputError("cannot read back the HTML report's temporary file");
            entry.pop_back();
            entry += ',';
            entry += buf;
            entry += '}';
        }
        out << entry << (i + 1 < n ? ",\n" : "\n");
    }
    out << "];\n";
    nlohmann::json meta;
    meta["layers"] = layer_count;
    meta["start"] = start;
    meta["stride"] = stride;
    meta["viewBox"] = vb;
    meta["plot"] = {{"left", frame.left}, {"w", frame.inner_w()}, {"width", frame.width}};
    meta["colors"] = kCavityColors;
    out << "const META = " << meta.dump() << ";\n" << kScript << "</script>\n</body>\n</html>\n";
    out.close();
    if (!out) throw InputError("cannot write the HTML report " + m.tmp_path);

    std::error_code ec;
    std::filesystem::rename(m.tmp_path, m.path, ec);
    if (ec) throw InputError("cannot write the HTML report " + m.path + ": " + ec.message());
    m.finished = true;
    std::fclose(m.spill);
    m.spill = nullptr;
}

}  // namespace carve

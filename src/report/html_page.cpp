// The HTML report's page, written once at the end of the run from the layers html_report.cpp
// reduced: the figures of the page, then its head, cards, layer viewer, plots, details and the
// data the script draws from, in the order the page is written.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <string_view>
#include <utility>

#include "base/atomic_file.hpp"
#include "base/error.hpp"
#include "base/numbers.hpp"
#include "config/setting_table.hpp"
#include "gcode/gcode.hpp"
#include "geometry/polygon.hpp"
#include "report/html_assets.hpp"
#include "report/html_plots.hpp"
#include "report/html_report.hpp"
#include "report/html_report_impl.hpp"
#include "report/palette.hpp"
#include "report/stats.hpp"
#include "report/svg.hpp"

namespace carve {

namespace {

using namespace html;

// A table setting's value with its unit as a person reads it ("0.2 mm", "45°", "on", "rear").
std::string setting_text(const SettingSpec& spec, const Settings& st) {
    if (spec.text()) {
        const std::string t = spec.text_field().get(st);
        if (t.empty()) return "none";
        return *spec.unit ? t + " " + spec.unit : t;
    }
    const double v = spec.get(st);
    if (spec.flag()) return v != 0 ? "on" : "off";
    static const std::map<std::string_view, std::string_view> shown = {
        {"degrees", "°"},     {"C", " °C"},      {"g/cm^3", " g/cm³"},
        {"mm/s^2", " mm/s²"}, {"seconds", " s"}, {"ratio", "×"},
    };
    const auto it = shown.find(spec.unit);
    return plain_number(v) +
           (it != shown.end() ? std::string(it->second) : std::string(" ") + spec.unit);
}

// The report's layer nearest to height z (layers bottom up, not empty).
size_t nearest_layer(const std::vector<ReportLayer>& layers, double z) {
    size_t best = 0;
    for (size_t i = 1; i < layers.size(); ++i)
        if (std::fabs(layers[i].z - z) < std::fabs(layers[best].z - z)) best = i;
    return best;
}

// --stats-strength's card: the stiffness and the weakest layer, which the plot marks.
void strength_card(std::ostream& out, const StrengthFigures& s) {
    out << "<div class=\"card\"><div class=\"label\">Stiffness (compression)</div>"
        << "<div class=\"big\">" << sig3(s.stiffness.compression_n_per_mm)
        << "<span class=\"unit\">N/mm</span></div><div class=\"small\">shear "
        << sig3(s.stiffness.shear_n_per_mm) << " N/mm (" << s.law << " law, "
        << plain_number(s.voxel_mm)
        << " mm voxels)<br><b style=\"color:#e03131\">weakest layer</b> z "
        << fixed(s.weakest_section_z_mm, 2) << " mm: section " << sig3(s.weakest_section_mm4)
        << " mm⁴";
    if (s.has_weakest_bond)
        out << "<br>weakest bond " << sig3(s.weakest_bond_mm2) << " mm² at z "
            << fixed(s.weakest_bond_z_mm, 2) << " mm";
    out << "</div></div>\n";
}

}  // namespace

// What the page shows before it is written: totals, the layer it opens on, the drawing stride.
struct HtmlReportWriter::Impl::PageFigures {
    size_t n = 0;      // layers, bottom up
    int stride = 1;    // every stride-th drawing kept when the page would exceed its budget
    size_t start = 0;  // the layer the page opens on
    double material = 0, conventional = 0, filament_m = 0, grams = 0, conventional_g = 0;
    double model_volume = 0, carved = 0;
    int layer_count = 0, cavities = 0, bridges = 0;
    std::string model, date;
    bool keep_drawing(size_t i) const { return stride == 1 || i % stride == 0 || i + 1 == n; }
};

HtmlReportWriter::Impl::PageFigures HtmlReportWriter::Impl::figures(
    const RunResult& run, const nlohmann::json& stats) const {
    const Settings& st = settings;
    const size_t n = layers.size();
    PageFigures f;
    // If the drawings still exceed the budget, keep every stride-th (and the top and bottom).
    f.n = n;
    if (spilled > 0 && size_t(spilled) > budget + budget / 8)
        f.stride = int(std::ceil(double(spilled) / double(budget)));

    // Totals.
    double material_sum = 0, best_score = -1;
    f.start = n / 2;
    for (size_t i = 0; i < n; ++i) {
        material_sum += layers[i].material_mm3;
        f.conventional += layers[i].conventional_mm3;
        // The page opens on the layer that shows the carving best: most cavities present, then
        // the most cavity wall, then a bridge.
        int present = 0;
        for (double a : layers[i].cavity_mm2) present += a > 1.0;
        const double score = present * 1e6 + layers[i].cavity_wall_mm + (layers[i].bridges > 0);
        if (score > best_score && f.keep_drawing(i)) best_score = score, f.start = i;
    }
    f.material = run.print.extruded_volume_mm3 > 0 ? run.print.extruded_volume_mm3 : material_sum;
    const double filament_area = std::numbers::pi * st.filament_diameter * st.filament_diameter / 4;
    f.filament_m = run.print.filament_length_mm > 0 ? run.print.filament_length_mm / 1000
                                                    : f.material / filament_area / 1000;
    f.grams = run.print.filament_weight_g > 0 ? run.print.filament_weight_g
                                              : f.material / 1000 * st.filament_density;
    f.conventional_g = f.conventional / 1000 * st.filament_density;
    f.model_volume = run.mesh.volume_mm3;
    f.layer_count = run.layers > 0 ? run.layers : int(n);
    for (double v : run.cavity_volume_mm3) f.carved += v;
    f.cavities = run.cavities > 0 ? run.cavities : max_cavities;
    f.bridges = run.bridges;
    if (f.bridges == 0)
        for (const ReportLayer& l : layers) f.bridges += l.bridges;

    f.model = model_name.empty() ? std::string("model")
                                 : std::filesystem::path(model_name).filename().string();
    if (stats.is_object()) {
        for (const char* key : {"model", "model_path", "input"}) {
            if (stats.contains(key) && stats[key].is_string()) {
                f.model = std::filesystem::path(stats[key].get<std::string>()).filename().string();
                break;
            }
        }
    }

    {
        const std::time_t now = std::time(nullptr);
        char buf[64];
        if (std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M", std::localtime(&now))) f.date = buf;
    }

    return f;
}

void HtmlReportWriter::Impl::write_head(std::ostream& out, const PageFigures& f) const {
    const Settings& st = settings;
    const double line_w = st.nozzle * kUnitsPerMm / double(kGrid);  // stroke width, drawing units
    out << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
           "<meta name=\"viewport\" content=\"width=device-width,initial-scale=1\">\n";
    out << "<title>carve report: " << xml_escape(f.model) << "</title>\n<style>" << kCss;
    out << fmt::format("#view .o{{stroke:{};stroke-width:{:.1f}px}}\n", kOuterWallColour,
                       0.85 * line_w);
    out << fmt::format("#view .s{{stroke:{};stroke-width:{:.1f}px}}\n", kShellColour,
                       0.85 * line_w);
    out << fmt::format("#view .c{{stroke:{};stroke-width:{:.1f}px}}\n", kCoverColor, 0.7 * line_w);
    out << fmt::format("#view .w{{stroke-width:{:.1f}px}}\n", 0.75 * line_w);
    out << fmt::format("#view .g{{stroke-width:{:.1f}px}}\n", 0.6 * line_w);
    out << fmt::format("#view .b{{stroke:{};stroke-width:{:.1f}px;stroke-linecap:butt}}\n",
                       kBridgeColour, 1.3 * line_w);
    for (size_t k = 0; k < kCavityColours.size(); ++k)
        out << fmt::format("#view .w.k{0}{{stroke:{1}}} #view .r.k{0}{{fill:{1}}}\n", k + 1,
                           kCavityColours[k]);
    out << fmt::format(
        "#view .f{{stroke:{};stroke-width:{:.1f}px}} #view.hide-f .f{{display:none}} "
        ".panel.side svg{{max-width:100%;height:auto}}\n",
        kRibColour, 1.0 * line_w);
    if (st.support != SupportMode::None)
        out << fmt::format(
            "#view .p{{stroke:{};stroke-width:{:.1f}px}} #view "
            ".i{{stroke:{};stroke-width:{:.1f}px}}"
            " #view.hide-p .p,#view.hide-p .i{{display:none}}\n",
            kSupportColour, 0.75 * line_w, kSupportInterfaceColour, 0.75 * line_w);
    out << "</style>\n</head>\n<body>\n";
}

void HtmlReportWriter::Impl::write_cards(std::ostream& out, const PageFigures& f,
                                         const RunResult& run) const {
    const Settings& st = settings;
    // Header.
    const std::string preset = fmt::format(
        "--carving {}: {} layers of {} mm, nozzle {} mm, {} cavities, {} covers, {} shells, {} "
        "walls",
        scheme_name(st.carving), f.layer_count, st.layer_height, st.nozzle,
        st.cavities_auto ? std::string("auto") : std::to_string(st.cavities), st.covers, st.shells,
        st.walls == WallMode::Single ? "single-filament" : "double");
    out << "<header class=\"top\"><div class=\"brand\">carve</div><div><h1>" << xml_escape(f.model)
        << "</h1><div class=\"sub\">" << xml_escape(preset) << " &middot; " << xml_escape(f.date)
        << "</div></div></header>\n<main>\n";

    // Cards.
    out << "<section class=\"cards\">\n";
    out << "<div class=\"card\"><div class=\"label\">Material</div><div class=\"big\">"
        << fixed(f.material / 1000, 2)
        << "<span class=\"unit\">cm³</span></div><div class=\"small\">"
        << (f.model_volume > 0
                ? fixed(100 * f.material / f.model_volume, 1) + " % of the model's volume"
                : std::string("model volume unknown"))
        << "<br>" << fixed(f.grams, 1) << " g &middot; " << fixed(f.filament_m, 2) << " m of "
        << st.filament_diameter << " mm filament</div></div>\n";
    if (f.conventional > 0) {
        const double saving = 100 * (1 - f.material / f.conventional);
        const double frac = std::clamp(f.material / f.conventional, 0.0, 1.0);
        out << "<div class=\"card good\"><div class=\"label\">Saved against 15 % infill</div>"
            << "<div class=\"big\">" << fixed(saving, 0) << "<span class=\"unit\">%</span></div>"
            << "<div class=\"bars\"><div class=\"bar\"><b style=\"width:" << fixed(70 * frac, 1)
            << "%;background:#1c7ed6\"></b><span>carve " << sig3(f.material / 1000)
            << " cm³</span></div><div class=\"bar\"><b style=\"width:70%;background:#9ca3af\"></b>"
            << "<span>infill " << sig3(f.conventional / 1000) << " cm³</span></div></div>"
            << "<div class=\"small\">" << fixed(f.conventional_g - f.grams, 1)
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
    out << "<div class=\"card\"><div class=\"label\">Cavities</div><div class=\"big\">"
        << f.cavities << "<span class=\"unit\">"
        << (st.carving == CarvingScheme::Report ? "nested" : "carved whole")
        << "</span></div><div class=\"small\">";
    if (f.model_volume > 0 && f.carved > 0)
        out << fixed(100 * f.carved / f.model_volume, 1) << " % of the volume left hollow<br>";
    out << f.bridges << (f.bridges == 1 ? " bridge" : " bridges");
    if (run.bridge_length_mm > 0) out << ", " << fixed(run.bridge_length_mm, 0) << " mm of lines";
    out << "</div></div>\n";
    const Vec3 size{run.mesh.bbox.max.x - run.mesh.bbox.min.x,
                    run.mesh.bbox.max.y - run.mesh.bbox.min.y,
                    run.mesh.bbox.max.z - run.mesh.bbox.min.z};
    out << "<div class=\"card\"><div class=\"label\">Model</div><div class=\"big\">"
        << (f.model_volume > 0 ? sig3(f.model_volume / 1000) : std::string("&mdash;"))
        << "<span class=\"unit\">cm³</span></div><div class=\"small\">" << run.mesh.triangles
        << " triangles &middot; " << f.layer_count << " layers<br>" << fixed(size.x, 1) << " × "
        << fixed(size.y, 1) << " × " << fixed(size.z, 1) << " mm</div></div>\n";
    if (run.strength) strength_card(out, *run.strength);
    out << "</section>\n";
}

std::array<double, 4> HtmlReportWriter::Impl::write_viewer(std::ostream& out,
                                                           const PageFigures& f) const {
    const Settings& st = settings;
    // Layer viewer.
    const double grid = double(kGrid);
    const double pad =
        std::max(2.0 * kUnitsPerMm,
                 0.04 * double(std::max(box.max_x - box.min_x, box.max_y - box.min_y))) /
        grid;
    const double bx0 = double(box.min_x) / grid, bx1 = double(box.max_x) / grid;
    const double by0 = double(box.min_y) / grid, by1 = double(box.max_y) / grid;
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
        << "<input type=\"range\" id=\"slider\" min=\"0\" max=\"" << (f.n ? f.n - 1 : 0)
        << "\" value=\"" << f.start << "\" aria-label=\"layer\">"
        << "<div class=\"controls\"><button id=\"down\" title=\"layer below\">&#9660;</button>"
           "<button id=\"play\">&#9654; play</button><button id=\"up\" title=\"layer above\">"
           "&#9650;</button></div>\n<div class=\"legend\">";
    auto toggle = [&](const char* key, const std::string& swatch, const std::string& label,
                      bool on) {
        out << "<label><input type=\"checkbox\" data-k=\"" << key << "\"" << (on ? " checked" : "")
            << ">" << swatch << label << "</label>";
    };
    auto sw = [](const std::string& color, bool fill = false) {
        return fmt::format("<span class=\"sw{}\" style=\"background:{}\"></span>",
                           fill ? " fill" : "", color);
    };
    toggle("o", sw(kOuterWallColour), st.shells > 0 ? "outer wall and shells" : "outer wall", true);
    toggle("c", sw(kCoverColor), "covers (solid top and bottom)", true);
    std::string cav_sw = "<span class=\"cavsw\">";
    for (int j = 1; j <= std::max(1, std::min(max_cavities, int(kCavityColours.size()))); ++j)
        cav_sw += sw(cavity_colour(j));
    cav_sw += "</span>";
    toggle("w", cav_sw, "cavity walls, one colour per cavity", true);
    toggle("b", sw(kBridgeColour), "bridges", true);
    if (!ribs.empty()) toggle("f", sw(kRibColour), "ribs (supports inside the model)", true);
    if (st.support != SupportMode::None) toggle("p", sw(kSupportColour), "supports", true);
    toggle("r", sw(kCavityColours[0], true), "cavity regions", true);
    toggle("O", sw("#dfe3e8"), "slice of the model", true);
    toggle("g", sw("#c9ced6"), "layer below", false);
    out << "</div>\n<dl class=\"figs\" id=\"figs\"></dl><p class=\"note\" id=\"note\"></p>"
        << "</aside>\n</section>\n";

    return vb;
}

PlotFrame HtmlReportWriter::Impl::write_plots(std::ostream& out, const RunResult& run) const {
    // Plots.
    PlotFrame frame;
    frame.n = int(std::max<size_t>(layers.size(), 1));
    std::vector<PlotMark> marks;
    if (run.strength && !layers.empty()) {
        const StrengthFigures& s = *run.strength;
        marks.push_back({nearest_layer(layers, s.weakest_section_z_mm), "weakest section"});
        if (s.has_weakest_bond)
            marks.push_back({nearest_layer(layers, s.weakest_bond_z_mm), "weakest bond"});
    }
    out << "<section class=\"panel plots\">\n<div><h3>Material per layer</h3><p class=\"cap\">"
        << chip("#1c7ed6", "carve") << chip("#6b7280", "ordinary 15 % infill (estimate)")
        << "</p><p class=\"cap\">volume extruded in each layer; click a plot to show that layer"
        << (marks.empty() ? "" : "; red: the weakest layers (--stats-strength)") << "</p>"
        << material_plot(layers, frame, marks) << "</div>\n";
    out << "<div><h3>What each slice is made of</h3><p class=\"cap\">"
        << chip(kCoverColor, "covers");
    for (int j = 1; j <= max_cavities; ++j)
        out << chip(cavity_colour(j), fmt::format("C<sup>{}</sup>", j));
    out << chip(kRemainderColor, "remainder V<sup>k</sup>")
        << "</p><p class=\"cap\">share of each slice's area; the rest up to 100 % is the "
        << "outer wall's band</p>" << share_plot(layers, max_cavities, frame)
        << "</div>\n</section>\n";

    return frame;
}

void HtmlReportWriter::Impl::write_details(std::ostream& out, const PageFigures& f,
                                           const RunResult& run,
                                           const nlohmann::json& stats) const {
    const Settings& st = settings;
    // How the figures are computed.
    double covers_mm3 = 0, carvable_mm3 = 0, perimeter_mm3 = 0;
    for (const ReportLayer& l : layers) {
        const double h = st.layer_thickness_mm(l.index);  // the first layer's may differ
        covers_mm3 += l.covers_mm2 * h;
        carvable_mm3 += 0.15 * l.carvable_mm2 * h;
        perimeter_mm3 += 2 * l.perimeter_mm * st.layer_width_mm(l.index) * h;
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
        << " mm &times; path length &times; flow"
        << (st.first_layer_height > 0 || st.first_layer_extrusion_width > 0
                ? fmt::format("; the first layer {} mm thick, its lines {} mm wide",
                              plain_number(st.first_layer_mm()), plain_number(st.layer_width_mm(0)))
                : std::string())
        << (st.extrusion_multiplier != 1
                ? fmt::format("; every flow &times; {}", plain_number(st.extrusion_multiplier))
                : std::string())
        << "). The per-layer plot adds up the print paths "
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
        << " cm³ + infill " << sig3(carvable_mm3 / 1000) << " cm³ = " << sig3(f.conventional / 1000)
        << " cm³ (" << fixed(f.conventional_g, 1)
        << " g). It is an estimate: a real slicer's figure differs with its overlaps, gap "
           "fill and infill pattern.</p>\n"
        << "<p class=\"small\">Layer drawings: paths simplified (Douglas&ndash;Peucker) to "
        << fixed(kTolerances[0] / kUnitsPerMm, 2) << " mm and rounded to 0.01 mm";
    if (max_tol > kTolerances[0] / kUnitsPerMm + 1e-9)
        out << "; " << (f.n - size_t(min_tol_layers))
            << " busy layers were simplified further, up to " << fixed(max_tol, 2)
            << " mm, to keep this page small";
    if (f.stride > 1)
        out << "; only one layer in " << f.stride << " is drawn (the figures cover every layer)";
    out << ". Lines are drawn at " << 0.75 * st.nozzle << "&ndash;" << 0.85 * st.nozzle
        << " mm so that neighbours stay apart; bridges at " << 1.3 * st.nozzle << " mm.</p>\n";
    if (!run.mesh.warnings.empty()) {
        out << "<h2>What was repaired in the mesh</h2><ul>";
        for (const std::string& wline : run.mesh.warnings)
            out << "<li class=\"warn\">" << xml_escape(wline) << "</li>";
        out << "</ul>\n";
    }
    out << "</div><div>\n<h2>Settings</h2><table class=\"settings\">";
    auto setting = [&](const std::string& k, const std::string& v, const std::string& help) {
        out << "<tr><td";
        if (!help.empty()) out << " title=\"" << xml_escape(help) << "\"";
        out << ">" << xml_escape(k) << "</td><td>" << xml_escape(v) << "</td></tr>";
    };
    // Not a setting but where they came from (--printer's preset).
    setting("printer", st.printer_name, "");
    // The line width is the nozzle's unless --extrusion-width sets it: its row below says 0.
    setting("line width", fmt::format("{} mm", plain_number(st.width_mm())), "");
    // Every setting of the table under the name it is given by.
    for (const SettingSpec& spec : setting_table())
        setting(spec.label(), setting_text(spec, st), spec.help);
    out << "</table>\n<details><summary>Stats JSON</summary><pre>" << xml_escape(stats.dump(2))
        << "</pre></details>\n</div></div></section>\n</main>\n"
        << "<footer>Made by carve &middot; self-contained page, nothing is loaded from the "
           "network</footer>\n";
}

void HtmlReportWriter::Impl::write_data(std::ostream& out, const PageFigures& f,
                                        const std::array<double, 4>& vb,
                                        const PlotFrame& frame) const {
    // Data: one entry per layer, bottom up, the numbers then the drawing.
    out << "<script>\nconst LAYERS = [\n";
    std::string buf;
    for (size_t i = 0; i < f.n; ++i) {
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
        if (f.keep_drawing(i) && l.bytes > 0) {
            buf.resize(size_t(l.bytes));
            if (std::fseek(spill, l.offset, SEEK_SET) != 0 ||
                std::fread(buf.data(), 1, buf.size(), spill) != buf.size())
                throw InputError("cannot read back the HTML report's temporary file");
            entry.pop_back();
            entry += ',';
            entry += buf;
            entry += '}';
        }
        out << entry << (i + 1 < f.n ? ",\n" : "\n");
    }
    out << "];\n";
    nlohmann::json meta;
    meta["layers"] = f.layer_count;
    meta["start"] = f.start;
    meta["stride"] = f.stride;
    meta["viewBox"] = vb;
    meta["plot"] = {{"left", frame.left}, {"w", frame.inner_w()}, {"width", frame.width}};
    meta["colors"] = kCavityColours;
    out << "const META = " << meta.dump() << ";\n" << kScript << "</script>\n</body>\n</html>\n";
}

void HtmlReportWriter::Impl::write_side(std::ostream& out) const {
    std::vector<html::SideLayer> sorted = side_layers;
    std::sort(sorted.begin(), sorted.end(),
              [](const html::SideLayer& a, const html::SideLayer& b) { return a.index < b.index; });
    html::TallestSupport t;
    const std::string svg =
        html::tallest_support_svg(ribs, sorted, settings.layer_height, settings.width_mm(), t);
    if (svg.empty()) return;
    out << "<section class=\"panel side\"><h3>The tallest internal support, from the side</h3>"
        << "<p class=\"cap\">"
        << fmt::format(
               "{} ribs chained over {} layers, {:.1f} mm from z {:.1f} to {:.1f}, from x {:.1f} "
               "y {:.1f} to x {:.1f} y {:.1f}; seen across the vertical plane through its ends, "
               "at equal scales, in the model's section (grey). Paler: other ribs crossing the "
               "plane. carve check --strict fails a free-standing one over 5 mm "
               "(docs/check.md).",
               chip(kRibColour, "rib"), t.layers, t.height_mm, t.z_from, t.z_to, t.x0, t.y0, t.x1,
               t.y1)
        << "</p>" << svg << "</section>\n";
}

void HtmlReportWriter::finish(const RunResult& run, const nlohmann::json& stats) {
    Impl& m = *impl_;
    // Bottom up for the page; each layer's drawing is found in the spill file by its offset.
    std::sort(m.layers.begin(), m.layers.end(),
              [](const ReportLayer& a, const ReportLayer& b) { return a.index < b.index; });
    const Impl::PageFigures f = m.figures(run, stats);

    // The atomic writer's temporary (unique per run, removed on any error or signal), written
    // through a stream of its own; AtomicFile::close() then fsyncs it.
    auto file = std::make_unique<AtomicFile>(m.path);
    std::ofstream out(file->temporary(), std::ios::binary | std::ios::trunc);
    if (!out) throw OutputError("cannot write the HTML report " + m.path);
    m.write_head(out, f);
    m.write_cards(out, f, run);
    const std::array<double, 4> vb = m.write_viewer(out, f);
    const PlotFrame frame = m.write_plots(out, run);
    m.write_side(out);
    m.write_details(out, f, run, stats);
    m.write_data(out, f, vb, frame);
    out.close();
    if (!out) throw OutputError("cannot write the HTML report " + m.path);
    file->close();
    if (m.group)
        m.group->hold(std::move(file));
    else
        file->commit();
    m.finished = true;
    std::fclose(m.spill);
    m.spill = nullptr;
}

}  // namespace carve

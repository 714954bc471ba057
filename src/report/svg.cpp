// Layer pictures as SVG: the partition filled by region, the print paths stroked on top.
//
// Coordinates are written in pixels with the y axis flipped (model y up, SVG y down) rather
// than through a transform, so that the text of the title and legend stays upright and every
// viewer draws the same thing. Points closer than a quarter pixel to the last one drawn are
// skipped: a scanned model's slice has thousands of edges shorter than a pixel.
#include "report/svg.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numeric>

#include "base/atomic_file.hpp"
#include "base/error.hpp"
#include "geometry/polygon.hpp"

namespace carve {

namespace {

constexpr const char* kOutlineFill = "#e9e9e9";
constexpr const char* kOutlineStroke = "#b4b4b4";
constexpr const char* kCoverFill = "#d8ccb4";  // sand: neutral, apart from every cavity hue
constexpr const char* kRemainderFill = "#9a9a9a";
constexpr const char* kBridge = kBridgeColour;
constexpr const char* kOuterWall = kOuterWallColour;
constexpr const char* kShell = kShellColour;
constexpr const char* kCoverLine = "#ffffff";
constexpr const char* kSupport = kSupportColour;
constexpr const char* kSupportInterface = kSupportInterfaceColour;

// The cavity's colour darkened, for its wall lines: dark enough to read on its own fill.
std::string dark(const std::string& colour) {
    const unsigned v = std::stoul(colour.substr(1), nullptr, 16);
    auto shade = [&](int shift) { return unsigned(((v >> shift) & 0xff) * 0.45); };
    return fmt::format("#{:02x}{:02x}{:02x}", shade(16), shade(8), shade(0));
}

std::string superscript(int n) {
    static constexpr std::array<const char*, 10> digits = {"⁰", "¹", "²", "³", "⁴",
                                                           "⁵", "⁶", "⁷", "⁸", "⁹"};
    std::string out;
    for (char c : std::to_string(std::max(n, 0))) out += digits[size_t(c - '0')];
    return out;
}

// Model micrometres to picture pixels.
struct Frame {
    double min_x = 0, max_y = 0;      // um
    double margin_mm = 0, scale = 1;  // px per mm
    double left = 0, top = 0;         // px
    double x(Coord u) const { return left + ((double(u) - min_x) / 1000.0 + margin_mm) * scale; }
    double y(Coord v) const { return top + ((max_y - double(v)) / 1000.0 + margin_mm) * scale; }
};

void append_contour(std::string& d, const Path& path, bool closed, const Frame& f) {
    if (path.empty()) return;
    double lx = f.x(path[0].X), ly = f.y(path[0].Y);
    d += fmt::format("M{:.2f} {:.2f}", lx, ly);
    size_t drawn = 1;
    for (size_t i = 1; i < path.size(); ++i) {
        const double px = f.x(path[i].X), py = f.y(path[i].Y);
        const bool last = i + 1 == path.size();
        if (!last && std::hypot(px - lx, py - ly) < 0.25) continue;
        d += fmt::format(" {:.2f} {:.2f}", px, py);
        lx = px;
        ly = py;
        ++drawn;
    }
    if (drawn == 1 && !closed) d += fmt::format(" {:.2f} {:.2f}", lx + 0.01, ly);  // a dot
    if (closed) d += "Z";
}

std::string path_data(const Paths& paths, bool closed, const Frame& f) {
    std::string d;
    for (const Path& p : paths) append_contour(d, p, closed, f);
    return d;
}

void fill(std::string& svg, const char* cls, const Paths& region, const std::string& colour,
          const Frame& f, const std::string& extra = "") {
    if (region.empty()) return;
    svg += fmt::format(R"~(<path class="{}" fill="{}" fill-rule="nonzero"{} d="{}"/>)~", cls,
                       colour, extra, path_data(region, true, f));
    svg += "\n";
}

// A readable scale bar length (1, 2, 5 x 10^k mm) near a fifth of the drawing's width.
double scale_bar_mm(double width_mm) {
    const double target = std::max(width_mm / 5, 1e-3);
    const double base = std::pow(10.0, std::floor(std::log10(target)));
    for (double m : {5.0, 2.0, 1.0})
        if (m * base <= target) return m * base;
    return base;
}

struct LegendEntry {
    std::string swatch;  // SVG fragment drawn at (0, 0), 16 x 12 px
    std::string label;
};

std::string fill_swatch(const std::string& colour, const std::string& stroke = "#808080") {
    return fmt::format(
        R"~(<rect width="16" height="12" fill="{}" stroke="{}" stroke-width="0.6"/>)~", colour,
        stroke);
}

std::string line_swatch(const std::string& colour, double width) {
    return fmt::format(
        R"~(<rect width="16" height="12" fill="{}"/><line x1="1" y1="6" x2="15" y2="6" stroke="{}" stroke-width="{:.1f}"/>)~",
        kCoverFill, colour, width);
}

// The legend's entries: the partition's regions with their areas, and each kind of line with
// its length.
std::vector<LegendEntry> layer_legend(const LayerRecord& record, const LayerToolpaths* paths,
                                      double line_px) {
    const LayerPartition& layer = record.partition();
    const BridgedPartition& bridged = record.bridged;
    std::vector<LegendEntry> legend;
    auto mm2 = [](const Paths& r) {
        const double a = area_mm2(r);
        return a < 1 ? fmt::format("{:.3f} mm²", a) : fmt::format("{:.1f} mm²", a);
    };
    const int k = int(bridged.cavities.size());
    legend.push_back(
        {fill_swatch(kOutlineFill, kOutlineStroke), "model slice O " + mm2(layer.outline)});
    if (!layer.covers.empty())
        legend.push_back({fill_swatch(kCoverFill), "covers " + mm2(layer.covers)});
    for (int j = 1; j <= k; ++j)
        if (!bridged.cavities[size_t(j - 1)].empty())
            legend.push_back(
                {fill_swatch(cavity_colour(j)),
                 "cavity C" + superscript(j) + " " + mm2(bridged.cavities[size_t(j - 1)])});
    if (!bridged.remainder.empty())
        legend.push_back({fill_swatch(kRemainderFill),
                          "remainder V" + superscript(k) + " " + mm2(bridged.remainder)});
    if (!bridged.bridges.empty())
        legend.push_back(
            {fill_swatch(kBridge), fmt::format("bridges ({})", bridged.bridges.size())});
    if (!record.support.region.empty())
        legend.push_back({fill_swatch(kSupport), "support " + mm2(record.support.region)});

    if (paths) {
        std::array<double, kFeatureCount> length_mm{};
        for (const Extrusion& e : paths->extrusions)
            length_mm[size_t(e.feature)] += length(Paths{e.points}, e.closed) / 1000.0;
        auto add_line = [&](Feature feat, const std::string& colour, const char* name) {
            if (length_mm[size_t(feat)] > 0)
                legend.push_back({line_swatch(colour, std::max(line_px, 1.2)),
                                  fmt::format("{} {:.0f} mm", name, length_mm[size_t(feat)])});
        };
        add_line(Feature::OuterWall, kOuterWall, "outer wall");
        add_line(Feature::Shell, kShell, "shells");
        add_line(Feature::CavityWall, dark(cavity_colour(1)), "cavity walls");
        add_line(Feature::Cover, kCoverLine, "cover lines");
        add_line(Feature::Bridge, kBridge, "bridge lines");
        add_line(Feature::Rib, kRibColour, "ribs");
        add_line(Feature::Tie, dark(cavity_colour(0)), "ties");
        add_line(Feature::Support, kSupport, "support lines");
        add_line(Feature::SupportInterface, kSupportInterface, "support interface");
        add_line(Feature::Skirt, kSkirtColour, "skirt");
        add_line(Feature::Brim, kBrimColour, "brim");
    }
    return legend;
}

// The toolpaths, one path per kind (and per cavity), drawn over the partition.
void toolpath_strokes(std::string& svg, const LayerToolpaths& layer_paths, const Frame& f,
                      double line_px) {
    const LayerToolpaths* paths = &layer_paths;
    svg += fmt::format(
        R"~(<g id="toolpaths" fill="none" stroke-linejoin="round" stroke-linecap="round" stroke-width="{:.2f}">)~",
        line_px);
    svg += "\n";
    auto stroke = [&](Feature feat, int cavity, const char* cls, const std::string& colour,
                      double width_factor) {
        std::string d;
        for (const Extrusion& e : paths->extrusions)
            if (e.feature == feat && (feat != Feature::CavityWall || e.cavity == cavity))
                append_contour(d, e.points, e.closed, f);
        if (d.empty()) return;
        svg += fmt::format(R"~(<path class="{}" stroke="{}")~", cls, colour);
        if (width_factor != 1)
            svg += fmt::format(R"~( stroke-width="{:.2f}")~", line_px * width_factor);
        if (feat == Feature::CavityWall) svg += fmt::format(R"~( data-cavity="{}")~", cavity);
        svg += fmt::format(R"~( d="{}"/>)~", d);
        svg += "\n";
    };
    // Printed order inside a layer does not matter for the picture; the light cover lines
    // go first so that walls crossing them stay visible.
    stroke(Feature::Cover, 0, "cover-lines", kCoverLine, 1);
    int max_cavity = 0;
    for (const Extrusion& e : paths->extrusions)
        if (e.feature == Feature::CavityWall) max_cavity = std::max(max_cavity, e.cavity);
    for (int j = 0; j <= max_cavity; ++j)
        stroke(Feature::CavityWall, j, "cavity-wall", dark(cavity_colour(j)), 1);
    stroke(Feature::Tie, 0, "ties", dark(cavity_colour(0)), 1);
    stroke(Feature::Shell, 0, "shell", kShell, 1);
    stroke(Feature::OuterWall, 0, "outer-wall", kOuterWall, 1.2);
    stroke(Feature::Bridge, 0, "bridge-lines", kBridge, 1.5);
    stroke(Feature::Rib, 0, "ribs", kRibColour, 1.2);
    stroke(Feature::Support, 0, "support-lines", kSupport, 1);
    stroke(Feature::SupportInterface, 0, "support-interface", kSupportInterface, 1);
    stroke(Feature::Skirt, 0, "skirt", kSkirtColour, 1);
    stroke(Feature::Brim, 0, "brim", kBrimColour, 1);
    svg += "</g>\n";
}

// The legend beside the picture, and the scale bar under it.
void legend_group(std::string& svg, const std::vector<LegendEntry>& legend, const Frame& f,
                  double draw_w, double w_mm) {
    const double lx = f.left + draw_w + 16;
    svg += fmt::format(
        R"~(<g id="legend" font-size="13" fill="#222" transform="translate({:.1f} {:.1f})">)~", lx,
        f.top);
    svg += "\n";
    double y = 4;
    for (const LegendEntry& e : legend) {
        svg += fmt::format(
            R"~(<g transform="translate(0 {:.1f})">{}<text x="22" y="11">{}</text></g>)~", y,
            e.swatch, xml_escape(e.label));
        svg += "\n";
        y += 22;
    }
    // Scale bar.
    const double bar_mm = scale_bar_mm(w_mm);
    const double bar_px = bar_mm * f.scale;
    y += 12;
    svg += fmt::format(
        R"~(<g id="scale" transform="translate(0 {:.1f})"><rect width="{:.2f}" height="4" fill="#222"/><text x="0" y="20">{} mm</text></g>)~",
        y, bar_px, fmt::format("{:g}", bar_mm));
    svg += "\n</g>\n";
}

}  // namespace

std::string layer_svg(const LayerRecord& record, const LayerToolpaths* paths,
                      const SvgOptions& options) {
    const LayerPartition& layer = record.partition();
    const BridgedPartition& bridged = record.bridged;
    if (!options.toolpaths) paths = nullptr;
    BBox2 box;
    expand(box, bounds(layer.outline));
    expand(box, bounds(layer.wall_region));
    expand(box, bounds(record.support.region));
    if (paths)
        for (const Extrusion& e : paths->extrusions) expand(box, bounds(e.points));
    if (box.empty) box = {0, 0, 10000, 10000, false};  // an empty layer still gets a frame

    Frame f;
    f.min_x = double(box.min_x);
    f.max_y = double(box.max_y);
    f.margin_mm = std::max(options.margin_mm, 0.0);
    const double w_mm = double(box.max_x - box.min_x) / 1000.0 + 2 * f.margin_mm;
    const double h_mm = double(box.max_y - box.min_y) / 1000.0 + 2 * f.margin_mm;
    f.scale = std::max(options.width_px, 50.0) / w_mm;
    if (h_mm * f.scale > options.max_height_px)
        f.scale = std::max(options.max_height_px, 50.0) / h_mm;
    const double draw_w = w_mm * f.scale, draw_h = h_mm * f.scale;
    f.left = 10;
    f.top = 42;

    // Legend first: its height decides the picture's.
    const double line_px = std::clamp(options.path_width_mm * f.scale, 0.4, 3.0);
    const std::vector<LegendEntry> legend = layer_legend(record, paths, line_px);
    const int k = int(bridged.cavities.size());
    const double legend_w = options.legend ? 230 : 0;
    const double legend_h = options.legend ? 22.0 * double(legend.size()) + 50 : 0;
    const double width = f.left + draw_w + 10 + legend_w;
    const double height = f.top + std::max(draw_h, legend_h) + 10;

    const std::string title = options.title.empty()
                                  ? fmt::format("layer {}, z = {:.2f} mm", layer.index, layer.z)
                                  : options.title;

    std::string svg;
    svg.reserve(1 << 16);
    svg += R"~(<?xml version="1.0" encoding="UTF-8"?>)~";
    svg += "\n";
    svg += fmt::format(
        R"~(<svg xmlns="http://www.w3.org/2000/svg" width="{0:.0f}" height="{1:.0f}" viewBox="0 0 {0:.0f} {1:.0f}" font-family="DejaVu Sans, Helvetica, Arial, sans-serif">)~",
        std::ceil(width), std::ceil(height));
    svg += "\n";
    svg += fmt::format("<title>{}</title>\n", xml_escape(title));
    svg += R"~(<rect x="0" y="0" width="100%" height="100%" fill="#ffffff"/>)~";
    svg += "\n";
    svg += fmt::format(
        R"~(<text x="{}" y="27" font-size="18" font-weight="bold" fill="#222">{}</text>)~", f.left,
        xml_escape(title));
    svg += "\n";

    // The partition, back to front. Cavities, covers and remainder are disjoint; the outline
    // under them shows the outer wall's band and whatever the stages left out.
    svg += R"~(<g id="partition" stroke="none">)~";
    svg += "\n";
    fill(svg, "outline", layer.outline, kOutlineFill, f,
         fmt::format(R"~( stroke="{}" stroke-width="1")~", kOutlineStroke));
    fill(svg, "covers", layer.covers, kCoverFill, f);
    fill(svg, "remainder", bridged.remainder, kRemainderFill, f);
    for (int j = 1; j <= k; ++j)
        fill(svg, "cavity", bridged.cavities[size_t(j - 1)], cavity_colour(j), f,
             fmt::format(R"~( data-cavity="{}")~", j));
    for (const Bridge& b : bridged.bridges)
        fill(svg, "bridge-region", b.region, kBridge, f, R"~( fill-opacity="0.3")~");
    fill(svg, "support", record.support.region, kSupport, f, R"~( fill-opacity="0.25")~");
    svg += "</g>\n";

    if (paths) toolpath_strokes(svg, *paths, f, line_px);
    if (options.legend) legend_group(svg, legend, f, draw_w, w_mm);
    svg += "</svg>\n";
    return svg;
}

void write_layer_svg(const std::string& file, const LayerRecord& layer, const LayerToolpaths* paths,
                     const SvgOptions& options) {
    const std::string svg = layer_svg(layer, paths, options);
    write_file_atomically(file, svg);
}

SvgLayerWriter::SvgLayerWriter(std::string dir, std::set<int> layers, int every, SvgOptions options)
    : dir_(std::move(dir)),
      layers_(std::move(layers)),
      every_(every),
      options_(std::move(options)) {
    std::error_code ec;
    std::filesystem::create_directories(dir_, ec);
    if (ec || !std::filesystem::is_directory(dir_))
        throw OutputError("cannot create the directory for layer pictures: " + dir_);
}

SvgLayerWriter::SvgLayerWriter(std::string dir, std::vector<int> layers, SvgOptions options)
    : SvgLayerWriter(std::move(dir), std::set<int>(layers.begin(), layers.end()), 0,
                     std::move(options)) {}

SvgLayerWriter SvgLayerWriter::every(std::string dir, int n, SvgOptions options) {
    return SvgLayerWriter(std::move(dir), std::set<int>{}, std::max(n, 1), std::move(options));
}

bool SvgLayerWriter::wants(int index) const {
    if (index < 0) return false;
    return every_ > 0 ? index % every_ == 0 : layers_.count(index) > 0;
}

std::string SvgLayerWriter::file_name(int index) {
    return fmt::format("layer_{:04d}.svg", index);
}

std::vector<int> SvgLayerWriter::spread(int layer_count, int count) {
    std::vector<int> out;
    if (layer_count <= 0 || count <= 0) return out;
    if (count == 1 || layer_count == 1) return {0};
    for (int i = 0; i < count; ++i) {
        const int index = int(std::lround(double(i) * (layer_count - 1) / (count - 1)));
        if (out.empty() || out.back() != index) out.push_back(index);
    }
    return out;
}

std::string SvgLayerWriter::add(const LayerRecord& layer, const LayerToolpaths* paths) {
    const int index = layer.partition().index;
    if (!wants(index)) return {};
    const std::string file = (std::filesystem::path(dir_) / file_name(index)).string();
    write_layer_svg(file, layer, paths, options_);
    std::lock_guard lock(*mutex_);
    // Names hold the index zero-padded to 4 digits, so shorter then lexicographic is layer order.
    auto before = [](const std::string& a, const std::string& b) {
        return a.size() != b.size() ? a.size() < b.size() : a < b;
    };
    written_.insert(std::upper_bound(written_.begin(), written_.end(), file, before), file);
    return file;
}

std::string xml_escape(std::string_view text) {
    // One escaper for the SVG pictures and the HTML report.
    std::string out;
    for (char c : text) {
        switch (c) {
            case '&':
                out += "&amp;";
                break;
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '"':
                out += "&quot;";
                break;
            default:
                out += c;
        }
    }
    return out;
}

}  // namespace carve

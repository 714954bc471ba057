// cut_plates_svg (report/cut_svg.hpp): bed millimetres to pixels at a fixed scale, y flipped so
// the picture is the bed seen from above as the printer's front faces the viewer.
#include "report/cut_svg.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "geometry/polygon.hpp"
#include "report/svg.hpp"

namespace carve {

namespace {

constexpr double kPxPerMm = 2;
constexpr double kGapPx = 24, kTitlePx = 30, kLegendPx = 34;
constexpr int kColumns = 2;
constexpr const char* kBedFill = "#f6f6f2";
constexpr const char* kPieceFill = "#d9dde3";
constexpr const char* kPieceStroke = "#6b7280";
constexpr const char* kFaceFill = "#f2a65a";
constexpr const char* kInk = "#222222";

struct Panel {
    double left = 0, top = 0, bed_y = 0;
    double x(double mm) const { return left + mm * kPxPerMm; }
    double y(double mm) const { return top + kTitlePx + (bed_y - mm) * kPxPerMm; }
};

std::string path_d(const Paths& paths, const Panel& p) {
    std::string d;
    for (const Path& path : paths) {
        if (path.size() < 3) continue;
        for (size_t i = 0; i < path.size(); ++i)
            d += fmt::format("{}{:.1f} {:.1f}", i == 0 ? "M" : " ", p.x(double(path[i].X) / 1000),
                             p.y(double(path[i].Y) / 1000));
        d += "Z";
    }
    return d;
}

void draw_connector(std::string& svg, const ConnectorMark& c, const Panel& p) {
    const double r = std::max(c.diameter_mm / 2 * kPxPerMm, 2.0);
    // A pin stands solid; a hole is open; either dashed when it lies in the face on the bed.
    svg += fmt::format(
        R"~(<circle class="{}" cx="{:.1f}" cy="{:.1f}" r="{:.1f}" fill="{}" stroke="{}" stroke-width="1.2"{}/>)~",
        c.pin ? "pin" : "hole", p.x(c.x), p.y(c.y), r, c.pin ? kInk : "#ffffff", kInk,
        c.facing_down ? R"~( stroke-dasharray="2 2")~"
                      : (c.facing_side ? R"~( stroke-dasharray="5 1")~" : ""));
    svg += "\n";
}

void draw_plate(std::string& svg, const PlateDrawing& plate, size_t index, const Panel& p) {
    svg += fmt::format(R"~(<g class="plate" data-plate="{}">)~", index + 1);
    svg += "\n";
    svg += fmt::format(
        R"~(<text x="{:.1f}" y="{:.1f}" font-size="15" font-weight="bold" fill="{}">plate {}: {}</text>)~",
        p.left, p.top + 18, kInk, index + 1, xml_escape(plate.gcode));
    svg += "\n";
    svg += fmt::format(
        R"~(<rect x="{:.1f}" y="{:.1f}" width="{:.1f}" height="{:.1f}" fill="{}" stroke="#999" stroke-width="1"/>)~",
        p.x(0), p.y(plate.bed_y), plate.bed_x * kPxPerMm, plate.bed_y * kPxPerMm, kBedFill);
    svg += "\n";
    for (const PieceDrawing& piece : plate.pieces) {
        svg += fmt::format(R"~(<g class="piece" data-name="{}">)~", xml_escape(piece.name));
        svg += fmt::format(
            R"~(<path class="outline" fill="{}" stroke="{}" stroke-width="1" fill-rule="nonzero" d="{}"/>)~",
            kPieceFill, kPieceStroke, path_d(piece.outline, p));
        if (!piece.cut_faces.empty())
            svg += fmt::format(
                R"~(<path class="cut-face" fill="{}" fill-opacity="0.75" stroke="#b8641f" stroke-width="0.8" fill-rule="nonzero" d="{}"/>)~",
                kFaceFill, path_d(piece.cut_faces, p));
        svg += "\n";
        for (const ConnectorMark& c : piece.connectors) draw_connector(svg, c, p);
        const BBox2 b = bounds(piece.outline);
        const double cx = b.empty ? 0 : double(b.min_x + b.max_x) / 2000;
        const double cy = b.empty ? 0 : double(b.min_y + b.max_y) / 2000;
        svg += fmt::format(
            R"~(<text class="label" x="{:.1f}" y="{:.1f}" font-size="12" text-anchor="middle" fill="{}" stroke="#ffffff" stroke-width="3" paint-order="stroke">{}</text>)~",
            p.x(cx), p.y(cy), kInk, xml_escape(piece.name));
        svg += "</g>\n";
    }
    svg += "</g>\n";
}

}  // namespace

std::string cut_plates_svg(const std::vector<PlateDrawing>& plates, const std::string& title) {
    double cell_w = 0, cell_h = 0;
    for (const PlateDrawing& plate : plates) {
        cell_w = std::max(cell_w, plate.bed_x * kPxPerMm);
        cell_h = std::max(cell_h, plate.bed_y * kPxPerMm + kTitlePx);
    }
    const size_t columns = std::min<size_t>(kColumns, std::max<size_t>(plates.size(), 1));
    const size_t rows = (plates.size() + columns - 1) / columns;
    const double width = kGapPx + double(columns) * (cell_w + kGapPx);
    const double height = kTitlePx + kGapPx + double(rows) * (cell_h + kGapPx) + kLegendPx;
    std::string svg = fmt::format(
        R"~(<svg xmlns="http://www.w3.org/2000/svg" width="{:.0f}" height="{:.0f}" viewBox="0 0 {:.0f} {:.0f}" font-family="sans-serif">)~",
        width, height, width, height);
    svg += "\n";
    svg += fmt::format("<title>{}</title>\n", xml_escape(title));
    svg += R"~(<rect x="0" y="0" width="100%" height="100%" fill="#ffffff"/>)~";
    svg += fmt::format(
        R"~(<text x="{:.0f}" y="26" font-size="18" font-weight="bold" fill="{}">{}</text>)~",
        kGapPx, kInk, xml_escape(title));
    svg += "\n";
    for (size_t k = 0; k < plates.size(); ++k) {
        Panel p;
        p.left = kGapPx + double(k % columns) * (cell_w + kGapPx);
        p.top = kTitlePx + kGapPx + double(k / columns) * (cell_h + kGapPx);
        p.bed_y = plates[k].bed_y;
        draw_plate(svg, plates[k], k, p);
    }
    // The legend: what each mark means.
    const double y = height - kLegendPx + 8;
    svg += fmt::format(
        R"~(<g class="legend" font-size="12" fill="{0}"><rect x="{1:.0f}" y="{2:.0f}" width="16" height="12" fill="{3}" stroke="{4}"/><text x="{5:.0f}" y="{6:.0f}">piece seen from above</text><rect x="{7:.0f}" y="{2:.0f}" width="16" height="12" fill="{8}" stroke="#b8641f"/><text x="{9:.0f}" y="{6:.0f}">cut face (flat: on the bed or facing up)</text><circle cx="{10:.0f}" cy="{11:.0f}" r="6" fill="#ffffff" stroke="{0}"/><text x="{12:.0f}" y="{6:.0f}">hole</text><circle cx="{13:.0f}" cy="{11:.0f}" r="6" fill="{0}" stroke="{0}"/><text x="{14:.0f}" y="{6:.0f}">pin</text><circle cx="{15:.0f}" cy="{11:.0f}" r="6" fill="#ffffff" stroke="{0}" stroke-dasharray="2 2"/><text x="{16:.0f}" y="{6:.0f}">in the face on the bed</text></g>)~",
        kInk, kGapPx, y, kPieceFill, kPieceStroke, kGapPx + 22, y + 11, kGapPx + 170, kFaceFill,
        kGapPx + 192, kGapPx + 440, y + 6, kGapPx + 452, kGapPx + 500, kGapPx + 512, kGapPx + 550,
        kGapPx + 562);
    svg += "\n</svg>\n";
    return svg;
}

}  // namespace carve

// The HTML report: per-layer reduction on arrival (numbers in memory, drawing spilled to a
// temporary file), then one pass at the end that writes the page bottom up (html_page.cpp).
// This file is the writer and the per-layer half: each layer's figures and its drawing,
// simplified until it fits its share of the page's budget.
#include "report/html_report.hpp"

#include <algorithm>
#include <map>
#include <utility>

#include "base/error.hpp"
#include "geometry/polygon.hpp"
#include "geometry/simplify.hpp"
#include "report/html_plots.hpp"
#include "report/html_report_impl.hpp"
#include "report/palette.hpp"

namespace carve {

namespace {

using namespace html;

// The CSS class number (1..) of cavity C^j's colour.
int cavity_class(int j) {
    return int(cavity_colour_index(j)) + 1;
}

}  // namespace

std::string HtmlReportWriter::Impl::drawing(const LayerRecord& layer, const LayerToolpaths& paths,
                                            double tol) const {
    nlohmann::json rec;
    rec["t"] = rounded(tol / kUnitsPerMm, 3);
    rec["O"] = html::svg_path_data(layer.partition().outline, true, tol, kGrid);
    nlohmann::json regions = nlohmann::json::array();
    const std::vector<Paths>& cavities = layer.bridged.cavities;
    for (size_t j = 0; j < cavities.size(); ++j) {
        if (cavities[j].empty()) continue;
        std::string d = html::svg_path_data(cavities[j], true, tol, kGrid);
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
            case Feature::Tie:  // drawn as the walls they join
                kind = 3, j = cavity_class(e.cavity);
                break;
            case Feature::Rib:  // internal supports: their own colour, drawn over the rest
                kind = 7;
                break;
            case Feature::Bridge:
                kind = 4;
                break;
            case Feature::Support:
                kind = 5;
                break;
            case Feature::SupportInterface:
                kind = 6;
                break;
            case Feature::Skirt:  // on the bed around the part, not the part's: not drawn
            case Feature::Brim:
                continue;
        }
        groups[{kind, j}] += html::svg_path_data(Paths{e.points}, e.closed, tol, kGrid);
    }
    static constexpr const char* kKinds[] = {"o", "s", "c", "w", "b", "p", "i", "f"};
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
    impl_->settings = settings;
    impl_->spill = std::tmpfile();
    if (!impl_->spill) throw InputError("cannot create a temporary file for the HTML report");
}

HtmlReportWriter::~HtmlReportWriter() {
    if (impl_->spill) std::fclose(impl_->spill);
}

void HtmlReportWriter::commit_with(OutputGroup& group) {
    impl_->group = &group;
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

void HtmlReportWriter::add_layer(const LayerRecord& record, const LayerToolpaths& paths) {
    const LayerPartition& layer = record.partition();
    Impl& m = *impl_;
    const Settings& st = m.settings;
    ReportLayer r;
    r.index = layer.index;
    r.z = paths.index == layer.index && paths.z > 0 ? paths.z : st.layer_top_mm(layer.index);
    r.outline_mm2 = area_mm2(layer.outline);
    r.perimeter_mm = length(layer.outline, true) / kUnitsPerMm;
    r.covers_mm2 = area_mm2(layer.covers);
    r.carvable_mm2 = area_mm2(layer.carvable);
    r.remainder_mm2 = area_mm2(record.bridged.remainder);
    for (const Paths& c : record.bridged.cavities) r.cavity_mm2.push_back(area_mm2(c));
    while (!r.cavity_mm2.empty() && r.cavity_mm2.back() <= 0) r.cavity_mm2.pop_back();
    m.max_cavities = std::max(m.max_cavities, int(r.cavity_mm2.size()));
    r.bridges = int(record.bridged.bridges.size());
    // The layer's own width and thickness and the flow the G-code extrudes, as the run's
    // material figures (run/layer_figures.cpp).
    const double w = st.layer_width_mm(layer.index), h = st.layer_thickness_mm(layer.index);
    for (const Extrusion& e : paths.extrusions) {
        const double len = length(Paths{e.points}, e.closed) / kUnitsPerMm;
        r.material_mm3 += len * w * h * e.flow * st.extrusion_multiplier;
        switch (e.feature) {
            case Feature::OuterWall:
            case Feature::Shell:
                r.wall_mm += len;
                break;
            case Feature::Cover:
                r.cover_mm += len;
                break;
            case Feature::CavityWall:
            case Feature::Rib:
            case Feature::Tie:
                r.cavity_wall_mm += len;
                break;
            case Feature::Bridge:
                r.bridge_mm += len;
                break;
            case Feature::Support:
            case Feature::SupportInterface:
                r.support_mm += len;
                break;
            case Feature::Skirt:  // its material only
            case Feature::Brim:
                break;
        }
    }
    // What a conventional slicer would extrude on the same slice: two perimeters, solid where
    // this layer has covers, 15 % grid in the rest of the interior.
    r.conventional_mm3 = 2 * r.perimeter_mm * w * h + r.covers_mm2 * h + 0.15 * r.carvable_mm2 * h;

    for (const Extrusion& e : paths.extrusions)
        if (e.feature == Feature::Rib) m.ribs.push_back({layer.index, r.z, e.points});
    {
        // The outline at 0.2 mm: enough for a section seen at the scale of a support.
        html::SideLayer side{layer.index, r.z, {}};
        for (const Path& p : layer.outline) {
            Path q = douglas_peucker(p, true, 200);
            if (q.size() >= 3) side.outline.push_back(std::move(q));
        }
        m.side_layers.push_back(std::move(side));
    }
    expand(m.box, bounds(layer.outline.empty() ? layer.wall_region : layer.outline));
    expand(m.box, bounds(record.support.region));

    // The first layer to arrive is the top one: its index tells how many will follow.
    if (m.expected_layers == 0) m.expected_layers = layer.index + 1;
    const size_t share =
        m.budget / size_t(std::max<int>(m.expected_layers, int(m.layers.size()) + 1));
    std::string d;
    for (double tol : kTolerances) {
        d = m.drawing(record, paths, tol);
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

}  // namespace carve

// HTML report on hand-made layers: path simplification and encoding, a well-formed page with
// one data entry per layer bottom up, nothing loaded from the network, the size budget, and the
// atomic write.
#include "report/html_report.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "base/error.hpp"
#include "base/numbers.hpp"
#include "config/setting_table.hpp"
#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"
#include "report/html_side.hpp"
#include "report/palette.hpp"
#include "report/stats.hpp"
#include "support/shapes.hpp"

using namespace carve;
using carve::test::circle;
using carve::test::rect_region;

namespace {

constexpr Coord kMm = 1000;

// One hand-made layer: a 20 mm square, covers on the bottom and top layers, a round cavity C^1
// and a slot C^2 in the middle one, with a bridge.
struct HandLayer {
    LayerRecord part;
    LayerToolpaths paths;
};

HandLayer make_layer(const Settings& st, int index, bool cover) {
    HandLayer h;
    LayerPartition l;
    l.index = index;
    l.z = (index + 0.5) * st.layer_height;
    l.outline = rect_region(0, 0, 20 * kMm, 20 * kMm);
    l.wall_region = erode(l.outline, st.nozzle_radius());
    l.shell_paths_region = l.wall_region;
    h.paths.index = index;
    h.paths.z = (index + 1) * st.layer_height;
    Extrusion wall;
    wall.feature = Feature::OuterWall;
    wall.points = l.wall_region.front();
    wall.closed = true;
    h.paths.extrusions.push_back(wall);
    if (cover) {
        l.covers = l.wall_region;
        for (Coord y = 1 * kMm; y < 19 * kMm; y += 400) {
            Extrusion e;
            e.feature = Feature::Cover;
            e.points = {{600, y}, {19400, y}};
            h.paths.extrusions.push_back(e);
        }
        h.part = std::move(l);
        return h;
    }
    l.carvable = l.wall_region;
    l.cavities.push_back({circle(7 * kMm, 10 * kMm, 4 * kMm, 360)});
    l.cavities.push_back(rect_region(13 * kMm, 3 * kMm, 16 * kMm, 17 * kMm));
    l.remainder = subtract(subtract(l.carvable, l.cavities[0]), l.cavities[1]);
    for (int j = 0; j < 2; ++j) {
        Extrusion e;
        e.feature = Feature::CavityWall;
        e.cavity = j + 1;
        e.points = l.cavities[j].front();
        e.closed = true;
        h.paths.extrusions.push_back(e);
    }
    Bridge b;
    b.cavity = 1;
    b.region = rect_region(6 * kMm, 9 * kMm, 8 * kMm, 11 * kMm);
    b.lines = {{{3 * kMm, 10 * kMm}, {11 * kMm, 10 * kMm}}};
    h.part = std::move(l);
    h.part.bridged.bridges.push_back(b);
    Extrusion e;
    e.feature = Feature::Bridge;
    e.cavity = 1;
    e.points = b.lines.front();
    h.paths.extrusions.push_back(e);
    return h;
}

RunResult fake_run() {
    RunResult run;
    run.mesh.volume_mm3 = 20 * 20 * 0.6;
    run.mesh.triangles = 12;
    run.mesh.bbox.max = {20, 20, 0.6};
    run.layers = 3;
    run.cavities = 2;
    run.bridges = 1;
    run.processing_time_s = 0.25;
    return run;  // print stats left empty: the report falls back on its own sums
}

std::string read_all(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

size_t count(const std::string& text, const std::string& what) {
    size_t n = 0;
    for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
}

std::filesystem::path temp_file(const std::string& name) {
    const auto p = std::filesystem::temp_directory_path() / ("carve_html_test_" + name);
    std::filesystem::remove(p);
    return p;
}

std::string write_report(const std::filesystem::path& path, size_t budget = 0,
                         std::vector<ReportLayer>* layers_out = nullptr,
                         const Settings& st = Settings{}) {
    HtmlReportWriter writer(path.string(), st);
    if (budget) writer.set_budget(budget);
    for (int i = 2; i >= 0; --i) {  // top down, like the sweep
        const HandLayer h = make_layer(st, i, i != 1);
        writer.add_layer(h.part, h.paths);
    }
    if (layers_out) *layers_out = writer.layers();
    nlohmann::json stats = {{"model", "/some/where/cube.stl"}, {"layers", 3}};
    writer.finish(fake_run(), stats);
    return read_all(path);
}

// A value off the default for each text setting that is not one of a few words.
const std::map<std::string, std::string> kOffDefaultText = {
    {"cavities", "auto"},    {"bed", "300x200"},           {"thumbnails", "16x16,220x124"},
    {"pause_at", "12.4,30"}, {"pause_command", "M601"},

    {"cut", "auto"},         {"cut_plane", "0,0,10,0,0,1"}};

// Every table setting moved off its default (a number to an end of its range, a switch turned
// over, a word to another word), so that a writer showing defaults, or a value of the wrong
// setting, is caught.
Settings off_default_settings() {
    Settings st;
    const Settings defaults;
    for (const SettingSpec& spec : setting_table()) {
        if (spec.text()) {
            const std::string now = spec.text_value(defaults);
            std::string other;
            for (const std::string& word : spec.text_field().choices)
                if (word != now) other = word;
            if (other.empty()) {
                const auto it = kOffDefaultText.find(spec.name());
                EXPECT_NE(it, kOffDefaultText.end()) << spec.name() << " needs a value here";
                if (it == kOffDefaultText.end()) continue;
                other = it->second;
            }
            spec.set(st, other, "test");
            EXPECT_NE(spec.text_value(st), now) << spec.name();
            continue;
        }
        const double v = spec.get(defaults) == spec.max ? spec.min : spec.max;
        spec.set(st, plain_number(v), "test");
    }
    return st;
}

}  // namespace

TEST(SvgPathData, RelativeCoordinatesOnTheGrid) {
    EXPECT_EQ(html::svg_path_data(rect_region(0, 0, kMm, kMm), true, 50, 10),
              "M0 0l100 0 0 100-100 0z");
    EXPECT_EQ(html::svg_path_data(Paths{{{-1234, 5678}, {4321, -8765}}}, false, 50, 10),
              "M-123 568l555-1445");
    // Points that fall on one grid node vanish; a path reduced to one point is dropped.
    EXPECT_EQ(html::svg_path_data(Paths{{{0, 0}, {3, 2}}}, false, 50, 10), "");
}

TEST(HtmlReport, WellFormedSelfContainedPage) {
    const auto path = temp_file("page.html");
    std::vector<ReportLayer> layers;
    const std::string page = write_report(path, 0, &layers);
    ASSERT_FALSE(page.empty());
    EXPECT_EQ(page.rfind("<!DOCTYPE html>", 0), 0u);
    EXPECT_NE(page.find("</html>"), std::string::npos);
    EXPECT_NE(page.find("id=\"slider\""), std::string::npos);
    EXPECT_NE(page.find("cube.stl"), std::string::npos);
    // One data entry per layer, bottom up.
    EXPECT_EQ(count(page, "{\"i\":"), 3u);
    const size_t l0 = page.find("{\"i\":0,"), l1 = page.find("{\"i\":1,"),
                 l2 = page.find("{\"i\":2,");
    ASSERT_NE(l0, std::string::npos);
    ASSERT_NE(l2, std::string::npos);
    EXPECT_LT(l0, l1);
    EXPECT_LT(l1, l2);
    // Nothing from the network: no URL at all, no external script or style sheet.
    EXPECT_EQ(page.find("http:"), std::string::npos);
    EXPECT_EQ(page.find("https:"), std::string::npos);
    EXPECT_EQ(page.find("<script src"), std::string::npos);
    EXPECT_EQ(page.find("<link"), std::string::npos);
    // Balanced structure.
    EXPECT_EQ(count(page, "<section"), count(page, "</section>"));
    EXPECT_EQ(count(page, "<div"), count(page, "</div>"));
    EXPECT_EQ(count(page, "<svg"), count(page, "</svg>"));
    EXPECT_EQ(count(page, "<script>"), 1u);
    EXPECT_EQ(count(page, "</script>"), 1u);
    // The drawing has the features: outer wall, covers, cavity walls by cavity, bridges.
    EXPECT_NE(page.find("[\"o\",0,\"M"), std::string::npos);
    EXPECT_NE(page.find("[\"c\",0,\"M"), std::string::npos);
    EXPECT_NE(page.find("[\"w\",1,\"M"), std::string::npos);
    EXPECT_NE(page.find("[\"w\",2,\"M"), std::string::npos);
    EXPECT_NE(page.find("[\"b\",0,\"M"), std::string::npos);
    EXPECT_NE(page.find("#ff00ff"), std::string::npos);
    EXPECT_NE(page.find("0.15"), std::string::npos);  // the stated infill formula
    EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp"));

    // Per-layer numbers: the bridge layer's material is its path lengths x w x h.
    ASSERT_EQ(layers.size(), 3u);
    const ReportLayer& mid = layers[1];
    EXPECT_EQ(mid.index, 1);
    EXPECT_EQ(mid.bridges, 1);
    ASSERT_EQ(mid.cavity_mm2.size(), 2u);
    EXPECT_NEAR(mid.cavity_mm2[0], std::numbers::pi * 16, 0.1);
    EXPECT_NEAR(mid.cavity_mm2[1], 3 * 14, 1e-6);
    const double lengths = 4 * 19.6 + 2 * std::numbers::pi * 4 + 2 * (3 + 14) + 8;
    EXPECT_NEAR(mid.material_mm3, lengths * 0.4 * 0.2, 0.05);
    // The conventional estimate: 2 perimeters + 15 % of the interior (no covers here).
    EXPECT_NEAR(mid.conventional_mm3, 2 * 80 * 0.4 * 0.2 + 0.15 * 19.6 * 19.6 * 0.2, 0.05);
    EXPECT_NEAR(layers[0].conventional_mm3, 2 * 80 * 0.4 * 0.2 + 19.6 * 19.6 * 0.2, 0.05);
    std::filesystem::remove(path);
}

TEST(HtmlReport, BudgetSimplifiesThenSubsamples) {
    const auto path = temp_file("budget.html");
    std::vector<ReportLayer> layers;
    const std::string page = write_report(path, 2000, &layers);
    // Every layer keeps its numbers, coarser drawings first, then only some are drawn.
    EXPECT_EQ(count(page, "{\"i\":"), 3u);
    double coarsest = 0;
    for (const ReportLayer& l : layers) coarsest = std::max(coarsest, l.tolerance_mm);
    EXPECT_GT(coarsest, 0.05);
    EXPECT_NE(page.find("only one layer in "), std::string::npos);
    std::filesystem::remove(path);
}

TEST(HtmlReport, ModelNameWithoutStatsEntry) {
    const auto path = temp_file("named.html");
    Settings st;
    HtmlReportWriter writer(path.string(), st);
    writer.set_model_name("/models/fandisk.stl");
    const HandLayer h = make_layer(st, 0, true);
    writer.add_layer(h.part, h.paths);
    writer.finish(fake_run(), nlohmann::json::object());
    EXPECT_NE(read_all(path).find("<h1>fandisk.stl</h1>"), std::string::npos);
    std::filesystem::remove(path);
}

TEST(HtmlReport, NothingLeftBehindWithoutFinish) {
    const auto path = temp_file("abandoned.html");
    {
        Settings st;
        HtmlReportWriter writer(path.string(), st);
        const HandLayer h = make_layer(st, 0, true);
        writer.add_layer(h.part, h.paths);
    }
    EXPECT_FALSE(std::filesystem::exists(path));
    EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp"));
}

TEST(HtmlReport, UnwritablePathIsAnOutputError) {
    Settings st;
    HtmlReportWriter writer("/nonexistent-dir/for/sure/report.html", st);
    const HandLayer h = make_layer(st, 0, true);
    writer.add_layer(h.part, h.paths);
    EXPECT_THROW(writer.finish(fake_run(), nlohmann::json::object()), OutputError);
}

// The settings block of the stats JSON and the report's settings table are made from the table;
// a setting declared there and left out of either fails here.
TEST(StatsJson, SettingsBlockHoldsEveryTableSetting) {
    const Settings st = off_default_settings();
    const nlohmann::json s = stats_json(fake_run(), st)["settings"];
    std::set<std::string> keys;
    for (const SettingSpec& spec : setting_table()) {
        const std::string key = stats_key(spec);
        SCOPED_TRACE(key);
        EXPECT_TRUE(keys.insert(key).second) << "two settings share the key";
        EXPECT_EQ(key.rfind(spec.name(), 0), 0u) << "the key starts with the setting's name";
        ASSERT_TRUE(s.contains(key));
        const nlohmann::json& v = s[key];
        if (spec.text()) {
            // A word is a string; --cavities 6 is the number 6 (and "auto" a word).
            const std::string text = spec.text_value(st);
            if (v.is_number_integer())
                EXPECT_EQ(std::to_string(v.get<long long>()), text);
            else
                EXPECT_EQ(v.get<std::string>(), text);
        } else if (spec.flag()) {
            ASSERT_TRUE(v.is_boolean());
            EXPECT_EQ(v.get<bool>(), spec.get(st) != 0);
        } else if (spec.integer()) {
            ASSERT_TRUE(v.is_number_integer());
            EXPECT_EQ(v.get<long long>(), static_cast<long long>(spec.get(st)));
        } else {
            ASSERT_TRUE(v.is_number_float());
            // At the ends of the ranges the derived values (support_angle_deg, support_z_gap_mm)
            // equal the given ones; with --keep-all-bridges no bridge is cut to a length.
            const bool uncut = key == "max_bridge_length_mm" && !st.prune_bridges;
            EXPECT_DOUBLE_EQ(v.get<double>(), uncut ? 0.0 : spec.get(st));
        }
    }
}

// The settings the command line once made by hand, outside the table, so that they were missing
// from the stats and the report: in the table now, which the two tests around make sure of.
TEST(SettingTable, HoldsTheSettingsOnceOutsideIt) {
    std::set<std::string> names;
    for (const SettingSpec& spec : setting_table()) names.insert(spec.name());
    for (const char* name :
         {"cavities", "walls", "support", "flavor", "relative_e", "bed", "bed_check", "combing",
          "avoid_crossing_perimeters", "seam", "wipe", "firmware_retraction", "prune_bridges",
          "arc_fitting", "remaining_times", "thumbnails"})
        EXPECT_TRUE(names.count(name)) << name;
}

// The keys the stats JSON had before it was made from the table: other tools read them
// (DESIGN.md, "stats JSON"), so they keep their names and types.
TEST(StatsJson, SettingsBlockKeepsItsOlderKeys) {
    const nlohmann::json s = stats_json(fake_run(), Settings{})["settings"];
    using T = nlohmann::json::value_t;
    const std::vector<std::pair<std::string, T>> older = {
        {"layer_height_mm", T::number_float},
        {"nozzle_mm", T::number_float},
        {"max_overhang_deg", T::number_float},
        {"support_angle_deg", T::number_float},
        {"cavities", T::number_integer},
        {"covers", T::number_integer},
        {"shells", T::number_integer},
        {"walls", T::string},
        {"filament_diameter_mm", T::number_float},
        {"tear_limit_mm", T::number_float},
        {"whole_width_mm", T::number_float},
        {"whole_width_max_mm", T::number_float},
        {"max_bridge_length_mm", T::number_float},
        {"rib_reach_mm", T::number_float},
        {"rib_spacing_mm", T::number_float},
        {"prune_bridges", T::boolean},
        {"printer", T::string},
        {"copies", T::number_integer},
        {"support", T::string},
        {"support_z_gap_mm", T::number_float},
        {"support_xy_gap_mm", T::number_float},
        {"support_interface_layers", T::number_integer},
    };
    for (const auto& [key, type] : older) {
        SCOPED_TRACE(key);
        ASSERT_TRUE(s.contains(key));
        // nlohmann keeps non-negative integers as unsigned or signed depending on the source.
        const T got = s[key].type() == T::number_unsigned ? T::number_integer : s[key].type();
        EXPECT_EQ(got, type);
    }
    EXPECT_DOUBLE_EQ(s["support_angle_deg"].get<double>(), 45.0);  // 0 given: --max-overhang
}

TEST(HtmlReport, SettingsTableListsEveryTableSetting) {
    const auto path = temp_file("settings.html");
    const Settings st = off_default_settings();
    const std::string page = write_report(path, 0, nullptr, st);
    const size_t from = page.find("<table class=\"settings\">");
    ASSERT_NE(from, std::string::npos);
    const std::string table = page.substr(from, page.find("</table>", from) - from);
    for (const SettingSpec& spec : setting_table()) {
        const std::string label = spec.label();
        SCOPED_TRACE(label);
        const size_t row = table.find(">" + label + "</td><td>");
        ASSERT_NE(row, std::string::npos);
        const size_t value = table.find("</td><td>", row) + 9;
        const std::string shown = table.substr(value, table.find("</td>", value) - value);
        if (spec.text()) {
            const std::string text = spec.text_value(st);
            EXPECT_EQ(shown.rfind(text, 0), 0u) << shown;
            if (*spec.unit) {
                EXPECT_NE(shown.find(spec.unit), std::string::npos) << shown;
            }
        } else if (spec.flag()) {
            EXPECT_EQ(shown, spec.get(st) != 0 ? "on" : "off");
        } else {
            const std::string number = plain_number(spec.get(st));
            EXPECT_EQ(shown.rfind(number, 0), 0u) << shown;
            EXPECT_GT(shown.size(), number.size()) << "the unit is shown: " << shown;
        }
    }
    std::filesystem::remove(path);
}

namespace carve {
namespace {

// A rib leaning 1 mm per layer over 30 layers, a short one beside it, a wide slab as the model:
// the side view follows the tall one, one piece a layer, from its lowest to its highest.
TEST(HtmlSideView, FollowsTheTallestRibChain) {
    std::vector<html::RibPiece> ribs;
    std::vector<html::SideLayer> layers;
    const Path slab{Point(-20000, -20000), Point(60000, -20000), Point(60000, 20000),
                    Point(-20000, 20000)};
    for (int k = 0; k < 40; ++k) {
        const double z = 0.2 * (k + 1);
        layers.push_back({k, z, {slab}});
        if (k >= 5 && k < 35) {
            const Coord x = 1000 * (k - 5) / 2;  // 0.5 mm a layer: pieces 0.8 mm long overlap
            ribs.push_back({k, z, Path{Point(x, 0), Point(x + 800, 0)}});
        }
        if (k >= 10 && k < 14) ribs.push_back({k, z, Path{Point(-10000, 0), Point(-9200, 0)}});
    }
    html::TallestSupport t;
    const std::string svg = html::tallest_support_svg(ribs, layers, 0.2, 0.45, t);
    EXPECT_EQ(t.layers, 30);
    EXPECT_NEAR(t.height_mm, 6.0, 1e-9);
    EXPECT_NEAR(t.z_from, 1.0, 1e-9);
    EXPECT_NEAR(t.z_to, 7.0, 1e-9);
    EXPECT_NEAR(t.x0, 0.4, 1e-9);
    EXPECT_NEAR(t.x1, 14.9, 1e-9);
    EXPECT_EQ(svg.rfind("<svg class=\"side\"", 0), 0u);
    EXPECT_NE(svg.find(kRibColour), std::string::npos);
    EXPECT_TRUE(html::tallest_support_svg({}, layers, 0.2, 0.45, t).empty());
    EXPECT_EQ(t.layers, 0);
}

}  // namespace
}  // namespace carve

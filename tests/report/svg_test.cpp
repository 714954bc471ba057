// Tests of the layer pictures: a partition built by hand is drawn, the SVG is checked for
// well-formedness (balanced tags, quoted attributes), one filled path per cavity in its own
// colour, the flipped y axis, the legend, and the writer's choice of layers and file names.
#include "report/svg.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "base/error.hpp"
#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"
#include "support/regex.hpp"
#include "support/shapes.hpp"

using namespace carve;
using carve::test::circle;
using carve::test::rect;

namespace {

// A 40 x 30 mm slice with a round hole, a cover band along its bottom, four cavities (a
// disk, a ring around it, and two side blocks), the remainder in between, and one bridge.
LayerRecord hand_made_layer(int index = 12) {
    LayerPartition layer;
    layer.index = index;
    layer.z = 2.5;
    Path hole = circle(32000, 22000, 3000);
    std::reverse(hole.begin(), hole.end());
    layer.outline = unite(Paths{rect(0, 0, 40000, 30000), hole});
    layer.wall_region = erode(layer.outline, 200);
    layer.shell_paths_region = layer.wall_region;
    const Paths band{rect(0, 0, 40000, 4000)};
    layer.carvable = subtract(layer.wall_region, band);
    layer.covers = subtract(layer.shell_paths_region, layer.carvable);
    const Paths c1{circle(12000, 17000, 3000)};
    const Paths c2 = subtract(Paths{circle(12000, 17000, 7000)}, Paths{circle(12000, 17000, 3500)});
    const Paths c3{rect(22000, 6000, 26000, 26000)};
    const Paths c4{rect(28000, 6000, 38000, 14000)};
    for (const Paths& c : {c1, c2, c3, c4}) layer.cavities.push_back(intersect(c, layer.carvable));
    Paths all;
    for (const Paths& c : layer.cavities) all = unite(all, c);
    layer.remainder = subtract(layer.carvable, all);
    Bridge b;
    b.cavity = 3;
    b.region = Paths{rect(23000, 15000, 25000, 17000)};
    for (Coord y = 15000; y <= 17000; y += 400) b.lines.push_back({{22000, y}, {26000, y}});
    LayerRecord record = std::move(layer);
    record.bridged.bridges.push_back(b);
    return record;
}

LayerToolpaths hand_made_paths(const LayerRecord& record) {
    const LayerPartition& layer = record.partition();
    LayerToolpaths paths;
    paths.index = layer.index;
    paths.z = 2.6;
    for (const Path& p : layer.wall_region)
        paths.extrusions.push_back({Feature::OuterWall, p, true, 1.0, 0});
    for (size_t j = 0; j < record.bridged.cavities.size(); ++j)
        for (const Path& p : record.bridged.cavities[j])
            paths.extrusions.push_back({Feature::CavityWall, p, true, 1.0, int(j + 1)});
    Paths zigzag;
    for (Coord y = 400; y < 4000; y += 400) zigzag.push_back({{400, y}, {39600, y}});
    for (const Path& p : clip_lines(zigzag, layer.covers))
        paths.extrusions.push_back({Feature::Cover, p, false, 1.0, 0});
    for (const Path& p : record.bridged.bridges[0].lines)
        paths.extrusions.push_back({Feature::Bridge, p, false, 1.0, 0});
    return paths;
}

// A small XML checker: every tag closes in order, attributes are quoted, nothing is left open.
::testing::AssertionResult well_formed(const std::string& xml) {
    std::vector<std::string> stack;
    size_t i = 0;
    int elements = 0;
    while ((i = xml.find('<', i)) != std::string::npos) {
        const size_t end = xml.find('>', i);
        if (end == std::string::npos) return ::testing::AssertionFailure() << "unclosed '<'";
        std::string tag = xml.substr(i + 1, end - i - 1);
        i = end + 1;
        if (tag.starts_with("?") || tag.starts_with("!--")) continue;
        // Quotes must pair up inside a tag (an unescaped '>' in a value would break this).
        if (std::count(tag.begin(), tag.end(), '"') % 2 != 0)
            return ::testing::AssertionFailure() << "odd quotes in <" << tag << ">";
        if (tag.starts_with("/")) {
            const std::string name = tag.substr(1);
            if (stack.empty() || stack.back() != name)
                return ::testing::AssertionFailure() << "</" << name << "> closes <"
                                                     << (stack.empty() ? "" : stack.back()) << ">";
            stack.pop_back();
            continue;
        }
        ++elements;
        if (tag.ends_with("/")) continue;
        stack.push_back(tag.substr(0, tag.find_first_of(" \t\n")));
    }
    if (!stack.empty())
        return ::testing::AssertionFailure() << "<" << stack.back() << "> left open";
    if (elements == 0) return ::testing::AssertionFailure() << "no element";
    // Text between tags must not hold a raw '&' that is not an entity.
    static const carve::test::Regex bad_amp("&(?!(amp|lt|gt|quot|apos);)");
    if (bad_amp.search(xml)) return ::testing::AssertionFailure() << "raw '&'";
    return ::testing::AssertionSuccess();
}

size_t count(const std::string& text, const std::string& what) {
    size_t n = 0;
    for (size_t i = text.find(what); i != std::string::npos; i = text.find(what, i + 1)) ++n;
    return n;
}

// The `d` attribute of the first element with this class.
std::string path_d(const std::string& svg, const std::string& cls) {
    const size_t at = svg.find("class=\"" + cls + "\"");
    if (at == std::string::npos) return {};
    const size_t d = svg.find(" d=\"", at);
    return svg.substr(d + 4, svg.find('"', d + 4) - d - 4);
}

std::vector<double> numbers(const std::string& d) {
    std::vector<double> out;
    std::string cleaned;
    for (char c : d)
        cleaned += (std::isdigit(static_cast<unsigned char>(c)) || c == '.' || c == '-') ? c : ' ';
    std::istringstream in(cleaned);
    for (double v; in >> v;) out.push_back(v);
    return out;
}

}  // namespace

TEST(Svg, HandMadeLayerIsWellFormedWithOnePathPerCavity) {
    const LayerRecord layer = hand_made_layer();
    const LayerToolpaths paths = hand_made_paths(layer);
    const std::string svg = layer_svg(layer, &paths);
    EXPECT_TRUE(well_formed(svg));
    EXPECT_TRUE(svg.starts_with("<?xml"));
    EXPECT_NE(svg.find("xmlns=\"http://www.w3.org/2000/svg\""), std::string::npos);
    EXPECT_EQ(count(svg, "class=\"cavity\""), 4u);
    for (int j = 1; j <= 4; ++j) {
        EXPECT_NE(svg.find("fill=\"" + cavity_colour(j) +
                           "\" fill-rule=\"nonzero\" data-cavity=\"" + std::to_string(j) + "\""),
                  std::string::npos)
            << j;
    }
    EXPECT_EQ(count(svg, "class=\"outline\""), 1u);
    EXPECT_EQ(count(svg, "class=\"covers\""), 1u);
    EXPECT_EQ(count(svg, "class=\"remainder\""), 1u);
    EXPECT_EQ(count(svg, "class=\"bridge-region\""), 1u);
    EXPECT_EQ(count(svg, "class=\"outer-wall\""), 1u);
    EXPECT_EQ(count(svg, "class=\"cavity-wall\""), 4u);
    EXPECT_EQ(count(svg, "class=\"cover-lines\""), 1u);
    EXPECT_EQ(count(svg, "class=\"bridge-lines\""), 1u);
    EXPECT_NE(svg.find("layer 12, z = 2.50 mm"), std::string::npos);
    EXPECT_NE(svg.find("id=\"legend\""), std::string::npos);
    EXPECT_NE(svg.find("cavity C¹ "), std::string::npos);
    EXPECT_NE(svg.find("cavity C⁴ "), std::string::npos);
    EXPECT_NE(svg.find("remainder V⁴ "), std::string::npos);
    EXPECT_EQ(svg.find("http://", svg.find("xmlns") + 40), std::string::npos);  // nothing fetched
}

TEST(Svg, CavityColoursFollowTheReportAndStayDistinct) {
    EXPECT_EQ(cavity_colour(1), "#e03131");  // red
    EXPECT_EQ(cavity_colour(2), "#1971c2");  // blue
    EXPECT_EQ(cavity_colour(3), "#fcc419");  // yellow
    EXPECT_EQ(cavity_colour(4), "#2f9e44");  // green
    for (int a = 1; a <= 12; ++a)
        for (int b = a + 1; b <= 12; ++b) EXPECT_NE(cavity_colour(a), cavity_colour(b)) << a << b;
}

TEST(Svg, YAxisPointsUp) {
    LayerPartition layer;
    layer.outline = Paths{rect(0, 0, 10000, 20000)};
    const std::string svg = layer_svg(layer, nullptr);
    const std::vector<double> v = numbers(path_d(svg, "outline"));
    ASSERT_EQ(v.size(), 8u);
    // (0,0) then (10000,0), (10000,20000), (0,20000): model y up means picture y down.
    EXPECT_LT(v[0], v[2]);                                  // x grows to the right
    EXPECT_EQ(v[1], v[3]);                                  // same model y, same picture y
    EXPECT_GT(v[1], v[5]);                                  // model y = 0 is below model y = 20 mm
    EXPECT_NEAR((v[1] - v[5]) / (v[2] - v[0]), 2.0, 1e-3);  // aspect kept
    EXPECT_EQ(svg.find("id=\"toolpaths\""), std::string::npos);
    EXPECT_TRUE(well_formed(svg));
}

TEST(Svg, EmptyLayerAndOddTitleStayValid) {
    LayerPartition empty;
    SvgOptions options;
    options.title = "a <b> & \"c\"";
    const std::string svg = layer_svg(empty, nullptr, options);
    EXPECT_TRUE(well_formed(svg));
    EXPECT_NE(svg.find("a &lt;b&gt; &amp; &quot;c&quot;"), std::string::npos);
    options.legend = false;
    EXPECT_TRUE(well_formed(layer_svg(hand_made_layer(), nullptr, options)));
    EXPECT_EQ(layer_svg(hand_made_layer(), nullptr, options).find("id=\"legend\""),
              std::string::npos);
}

TEST(Svg, WellFormedCheckerCatchesMistakes) {
    EXPECT_FALSE(well_formed("<svg><g></svg>"));
    EXPECT_FALSE(well_formed("<svg><path d=\"M0 0/></svg>"));
    EXPECT_FALSE(well_formed("<svg>a & b</svg>"));
    EXPECT_TRUE(well_formed("<?xml version=\"1.0\"?><svg><g/><g></g></svg>"));
}

TEST(Svg, WriterChoosesLayersAndNamesFiles) {
    const std::filesystem::path dir =
        std::filesystem::path(::testing::TempDir()) / "carve_svg_test" / "nested";
    std::filesystem::remove_all(dir.parent_path());
    const LayerToolpaths paths = hand_made_paths(hand_made_layer());

    SvgLayerWriter every = SvgLayerWriter::every(dir.string(), 5);
    for (int i = 12; i >= 0; --i) {  // top down, as the sweep hands them out
        const std::string file = every.add(hand_made_layer(i), &paths);
        EXPECT_EQ(file.empty(), i % 5 != 0) << i;
    }
    ASSERT_EQ(every.written().size(), 3u);
    for (const char* name : {"layer_0000.svg", "layer_0005.svg", "layer_0010.svg"}) {
        std::ifstream in(dir / name);
        ASSERT_TRUE(in) << name;
        std::stringstream text;
        text << in.rdbuf();
        EXPECT_TRUE(well_formed(text.str())) << name;
    }
    EXPECT_FALSE(std::filesystem::exists(dir / "layer_0001.svg"));
    EXPECT_FALSE(std::filesystem::exists(dir / "layer_0000.svg.tmp"));

    SvgLayerWriter listed(dir.string(), {3, 1234});
    EXPECT_TRUE(listed.wants(1234));
    EXPECT_FALSE(listed.wants(4));
    EXPECT_EQ(std::filesystem::path(listed.add(hand_made_layer(1234), nullptr)).filename(),
              "layer_1234.svg");
    EXPECT_EQ(SvgLayerWriter::file_name(12345), "layer_12345.svg");

    EXPECT_EQ(SvgLayerWriter::spread(100, 5), (std::vector<int>{0, 25, 50, 74, 99}));
    EXPECT_EQ(SvgLayerWriter::spread(3, 8), (std::vector<int>{0, 1, 2}));
    EXPECT_TRUE(SvgLayerWriter::spread(0, 8).empty());

    // A directory that cannot be made is a clear error.
    EXPECT_THROW(SvgLayerWriter("/proc/carve_no_such_dir/x", {1}), OutputError);
    std::filesystem::remove_all(dir.parent_path());
}

TEST(Svg, WritesAPictureToLookAt) {
    // Left in the build tree for a person to open: <build>/svg_test_layer.svg.
    const LayerRecord layer = hand_made_layer();
    const LayerToolpaths paths = hand_made_paths(layer);
    const std::string file = "svg_test_layer.svg";
    write_layer_svg(file, layer, &paths);
    std::ifstream in(file);
    ASSERT_TRUE(in);
    std::stringstream text;
    text << in.rdbuf();
    EXPECT_EQ(text.str(), layer_svg(layer, &paths));
}

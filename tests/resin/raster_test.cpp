// Resin raster output: the scanline fill against exact pixel counts, the cured region of
// hand-made layers (shell, thickened cavity outlines, shared walls, bridges), and the PNG files
// and zip archive the writer leaves behind.
#include "resin/raster.hpp"

#include <gtest/gtest.h>
#include <png.h>
#include <zip.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>

#include "base/png.hpp"
#include "carving/carving.hpp"
#include "carving/covers.hpp"
#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"
#include "mesh/mesh.hpp"
#include "slice/slicer.hpp"
#include "support/models.hpp"
#include "support/shapes.hpp"
#include "supports/bridges.hpp"
#include "toolpath/toolpath.hpp"

using namespace carve;
using carve::test::rect_region;

namespace {

constexpr Coord kMm = 1000;

// A 20 mm square slice with no covers: every cavity lies in the wall region.
LayerPartition square_layer(const Settings& st, int index) {
    LayerPartition l;
    l.index = index;
    l.z = (index + 0.5) * st.layer_height;
    l.outline = rect_region(0, 0, 20 * kMm, 20 * kMm);
    l.wall_region = erode(l.outline, st.nozzle_radius());
    l.shell_paths_region = l.wall_region;
    l.carvable = l.wall_region;
    l.remainder = l.carvable;
    return l;
}

LayerPartition centred_cavity(const Settings& st, int index) {
    LayerPartition l = square_layer(st, index);
    l.cavities.push_back(rect_region(5 * kMm, 5 * kMm, 15 * kMm, 15 * kMm));
    l.remainder = subtract(l.carvable, l.cavities[0]);
    return l;
}

int64_t count_white(const std::vector<uint8_t>& image) {
    return std::count(image.begin(), image.end(), uint8_t{255});
}

RasterGrid grid_over(Coord x0, Coord y0, Coord x1, Coord y1, double pixel) {
    RasterGrid g;
    g.origin_x = x0;
    g.origin_y = y0;
    g.pixel = pixel;
    g.width = int((x1 - x0) / pixel);
    g.height = int((y1 - y0) / pixel);
    return g;
}

bool white_at(const std::vector<uint8_t>& image, const RasterGrid& g, double x_um, double y_um) {
    const int col = int((x_um - double(g.origin_x)) / g.pixel);
    const int row = g.height - 1 - int((y_um - double(g.origin_y)) / g.pixel);
    return image[size_t(row) * size_t(g.width) + size_t(col)] == 255;
}

std::filesystem::path fresh_dir(const std::string& name) {
    const auto dir = std::filesystem::temp_directory_path() / ("carve_raster_test_" + name);
    std::filesystem::remove_all(dir);
    return dir;
}

// The 40 mm sphere through every stage up to bridges, layer by layer (members in stage order:
// each holds a reference to the one before).
// Shared model (tests using it skip without it).
constexpr const char* kSphere = "synthetic/sphere_40mm.stl";

struct SphereLayers {
    explicit SphereLayers(const Settings& st)
        : mesh(load_mesh(carve::test::any_model(kSphere), report)),
          slicer(mesh, st.layer_height),
          covers(slicer, st),
          sweep(covers, st),
          bridges(sweep, st) {}
    MeshReport report;
    Mesh mesh;
    TopDownSlicer slicer;
    CarvableStream covers;
    CarvingSweep sweep;
    BridgeStage bridges;
};

}  // namespace

TEST(Rasterize, SquareCoversExactPixels) {
    const RasterGrid g = grid_over(0, 0, 2 * kMm, 2 * kMm, 50);
    std::vector<uint8_t> image;
    rasterize(rect_region(0, 0, kMm, kMm), g, image);
    ASSERT_EQ(image.size(), size_t(40 * 40));
    EXPECT_EQ(count_white(image), 20 * 20);
    // The square is the lower-left quarter: row 0 (top) is empty, the bottom-left pixel is set.
    EXPECT_EQ(image[0], 0);
    EXPECT_EQ(image[size_t(39 * 40)], 255);
}

TEST(Rasterize, HolesAndOverlaps) {
    const RasterGrid g = grid_over(0, 0, 2 * kMm, 2 * kMm, 50);
    std::vector<uint8_t> image;
    // Outer counter-clockwise, hole clockwise: 400 - 100 pixels.
    Paths ring = rect_region(0, 0, kMm, kMm);
    Path hole = rect_region(250, 250, 750, 750)[0];
    std::reverse(hole.begin(), hole.end());
    ring.push_back(hole);
    rasterize(ring, g, image);
    EXPECT_EQ(count_white(image), 400 - 100);
    // Two overlapping counter-clockwise squares fill their union (non-zero winding).
    image.assign(image.size(), 0);
    Paths two = rect_region(0, 0, kMm, kMm);
    two.push_back(rect_region(500, 500, 1500, 1500)[0]);
    rasterize(two, g, image);
    EXPECT_EQ(count_white(image), 400 + 400 - 100);
}

TEST(Rasterize, SlantedEdgesMatchArea) {
    // A triangle: pixel count times pixel area approaches its area.
    const RasterGrid g = grid_over(0, 0, 10 * kMm, 10 * kMm, 50);
    std::vector<uint8_t> image;
    rasterize(Paths{{{0, 0}, {9 * kMm, 1 * kMm}, {3 * kMm, 8 * kMm}}}, g, image);
    const double expected = area(Paths{{{0, 0}, {9 * kMm, 1 * kMm}, {3 * kMm, 8 * kMm}}});
    EXPECT_NEAR(double(count_white(image)) * 50 * 50, expected, 0.01 * expected);
}

TEST(ResinSolid, SquareWithOneCavity) {
    Settings st;
    const LayerPartition l = centred_cavity(st, 0);
    const Paths solid = resin_solid(l, st.line_width(), st.line_width(), st.nozzle_radius());
    // The cavity loses half the minimal wall on its side: 20^2 - 9.6^2 mm^2.
    const double expected_mm2 = 400 - 9.6 * 9.6;
    EXPECT_NEAR(area_mm2(solid), expected_mm2, 0.01 * expected_mm2);

    const RasterGrid g = grid_over(-kMm, -kMm, 21 * kMm, 21 * kMm, 50);
    std::vector<uint8_t> image;
    rasterize(solid, g, image);
    const double pixel_mm2 = 0.05 * 0.05;
    EXPECT_NEAR(double(count_white(image)) * pixel_mm2, expected_mm2, 0.02 * expected_mm2);
    EXPECT_TRUE(white_at(image, g, 2 * kMm, 2 * kMm));     // remainder V^k: solid
    EXPECT_FALSE(white_at(image, g, 10 * kMm, 10 * kMm));  // inside the cavity: empty
    EXPECT_TRUE(white_at(image, g, 4.9 * kMm, 10 * kMm));  // the thickened cavity outline
    EXPECT_FALSE(white_at(image, g, 5.3 * kMm, 10 * kMm));
}

TEST(ResinSolid, TouchingCavitiesKeepAWallBetweenThem) {
    Settings st;
    LayerPartition l = square_layer(st, 0);
    l.cavities.push_back(intersect(l.carvable, rect_region(0, 0, 10 * kMm, 20 * kMm)));
    l.cavities.push_back(intersect(l.carvable, rect_region(10 * kMm, 0, 20 * kMm, 20 * kMm)));
    l.remainder.clear();
    const Paths solid = resin_solid(l, st.line_width(), st.line_width(), st.nozzle_radius());
    // Each half shrinks to 9.4 x 19.2 mm: the outer shell is w wide, the middle wall w too.
    const double expected_mm2 = 400 - 2 * 9.4 * 19.2;
    EXPECT_NEAR(area_mm2(solid), expected_mm2, 0.02 * expected_mm2);
    const RasterGrid g = grid_over(-kMm, -kMm, 21 * kMm, 21 * kMm, 50);
    std::vector<uint8_t> image;
    rasterize(solid, g, image);
    EXPECT_TRUE(white_at(image, g, 10 * kMm, 10 * kMm));
    EXPECT_FALSE(white_at(image, g, 9.5 * kMm, 10 * kMm));
    EXPECT_TRUE(white_at(image, g, 0.2 * kMm, 10 * kMm));  // the outer shell
    EXPECT_NEAR(double(count_white(image)) * 0.05 * 0.05, expected_mm2, 0.04 * expected_mm2);
}

TEST(ResinSolid, BridgesAreSolidStrips) {
    Settings st;
    LayerRecord l = centred_cavity(st, 0);
    Bridge b;
    b.cavity = 1;
    b.region = rect_region(8 * kMm, 8 * kMm, 12 * kMm, 12 * kMm);
    b.lines = {{{5 * kMm, 10 * kMm}, {15 * kMm, 10 * kMm}}};
    l.bridged.bridges.push_back(b);
    const Paths with = resin_solid(l, st.line_width(), st.line_width(), st.nozzle_radius());
    const Paths without =
        resin_solid(centred_cavity(st, 0), st.line_width(), st.line_width(), st.nozzle_radius());
    // A 10 mm line thickened to 0.4 mm, of which 9.6 mm crosses the hollow part.
    EXPECT_NEAR(area_mm2(with) - area_mm2(without), 9.6 * 0.4, 0.3);
    EXPECT_TRUE(point_in_region(Point(10 * kMm, 10 * kMm), with));
}

TEST(RasterWriter, WritesEveryLayerAndTheZip) {
    Settings st;
    const auto dir = fresh_dir("writer");
    const int n = 4;
    BBox2 box;
    box.min_x = 0, box.min_y = 0, box.max_x = 20 * kMm, box.max_y = 20 * kMm, box.empty = false;
    std::vector<int64_t> white;
    {
        RasterWriter writer(dir.string(), st, box);
        // Top down as the sweep delivers them; the top and bottom layers are full squares.
        for (int i = n - 1; i >= 0; --i)
            writer.add_layer(i == 0 || i == n - 1 ? square_layer(st, i) : centred_cavity(st, i));
        writer.finish();
        const RasterGrid& g = writer.grid();
        EXPECT_EQ(g.width, 400 + 8);
        EXPECT_EQ(g.height, 400 + 8);
        ASSERT_EQ(writer.layer_stats().size(), size_t(n));
        for (int i = 0; i < n; ++i) {
            EXPECT_EQ(writer.layer_stats()[i].index, i);
            white.push_back(writer.layer_stats()[i].white_pixels);
        }
    }
    EXPECT_NEAR(double(white[0]), 400 * 400, 400);
    EXPECT_NEAR(double(white[1]) * 0.0025, 400 - 9.6 * 9.6, 0.02 * (400 - 9.6 * 9.6));
    for (int i = 0; i < n; ++i) {
        const auto file = dir / ("layer_0000" + std::to_string(i) + ".png");
        ASSERT_TRUE(std::filesystem::exists(file)) << file;
        // Read it back: 8-bit grayscale, the same white pixel count.
        png_image image{};
        image.version = PNG_IMAGE_VERSION;
        ASSERT_TRUE(png_image_begin_read_from_file(&image, file.c_str()));
        EXPECT_EQ(image.format, uint32_t(PNG_FORMAT_GRAY));
        std::vector<uint8_t> pixels(PNG_IMAGE_SIZE(image));
        ASSERT_TRUE(png_image_finish_read(&image, nullptr, pixels.data(), 0, nullptr));
        EXPECT_EQ(count_white(pixels), white[i]);
        EXPECT_EQ(std::count_if(pixels.begin(), pixels.end(),
                                [](uint8_t v) { return v != 0 && v != 255; }),
                  0);
    }
    EXPECT_TRUE(std::filesystem::exists(dir / "raster.json"));

    int err = 0;
    zip_t* zip = zip_open((dir / "layers.zip").c_str(), ZIP_RDONLY, &err);
    ASSERT_NE(zip, nullptr);
    std::set<std::string> names;
    for (zip_int64_t k = 0; k < zip_get_num_entries(zip, 0); ++k)
        names.insert(zip_get_name(zip, zip_uint64_t(k), 0));
    zip_close(zip);
    EXPECT_EQ(names.size(), size_t(n + 1));
    for (int i = 0; i < n; ++i) EXPECT_TRUE(names.count("layer_0000" + std::to_string(i) + ".png"));
    EXPECT_TRUE(names.count("raster.json"));
    std::filesystem::remove_all(dir);
}

TEST(RasterWriter, ThickerMinimalWall) {
    Settings st;
    const auto dir = fresh_dir("wall");
    BBox2 box;
    box.min_x = 0, box.min_y = 0, box.max_x = 20 * kMm, box.max_y = 20 * kMm, box.empty = false;
    RasterWriter writer(dir.string(), st, box, 0.1, 1.0);  // 0.1 mm pixels, 1 mm walls
    writer.add_layer(centred_cavity(st, 0));
    writer.finish();
    // The cavity shrinks by 0.5 mm on each side: 9 x 9 mm hollow.
    EXPECT_NEAR(double(writer.layer_stats()[0].white_pixels) * 0.01, 400 - 81, 0.02 * 319);
    std::filesystem::remove_all(dir);
}

// The part of a layer's cover band, beyond the outer wall, too thin for cover lines: the FDM
// paths leave it to the walls of the layers above and below, the resin stack cures it.
static double thin_band_mm2(const LayerPartition& layer, const Settings& st) {
    if (layer.covers.empty() || layer.carvable.empty()) return 0;
    const Coord keep_off = st.line_width() - st.line_width() * 15 / 100;  // kCoverOverlap
    const Paths beyond = intersect(layer.covers, erode(layer.wall_region, st.nozzle_radius()));
    const Paths lined = dilate(erode(layer.covers, keep_off), keep_off + st.nozzle_radius());
    return area_mm2(subtract(beyond, lined));
}

// The resin stack and the FDM print paths describe the same walls: per layer, the cured pixels
// outside the remainder's interior against the length of every print path times the line
// width, plus the thin cover bands the FDM paths leave unprinted (the raster cures them). They
// differ at corners, so single layers wander; over the whole object they agree.
TEST(RasterWriter, WallPixelsMatchPrintPathLengths) {
    CARVE_NEED_MODEL(kSphere);
    Settings st;
    // The nested cavities of the widths used before ribs: carved whole (the default since), the
    // sphere's one cavity lines the outer wall on most layers, where the stack cures 1.5 w
    // against the paths' w (median layer 1.28).
    st.whole_width = 4;
    st.whole_width_max = 14;
    SphereLayers sphere(st);
    BridgeStage& bridges = sphere.bridges;
    const double pixel = 50;
    const double pixel_mm2 = (pixel / kMm) * (pixel / kMm);
    double total_pixels_mm2 = 0, total_paths_mm2 = 0;
    std::vector<double> ratios;
    int layers = 0;
    while (auto layer = bridges.next()) {
        ++layers;
        const LayerToolpaths paths = plan_layer(*layer, st);
        double length_mm = thin_band_mm2(layer->partition(), st) / st.nozzle;
        for (const Extrusion& e : paths.extrusions)
            length_mm += length(Paths{e.points}, e.closed) / kMm;
        const Paths solid =
            resin_solid(*layer, st.line_width(), st.line_width(), st.nozzle_radius());
        const Paths walls = subtract(solid, erode(layer->bridged.remainder, st.nozzle_radius()));
        const BBox2 b = bounds(layer->partition().outline);
        const RasterGrid g =
            grid_over(b.min_x - kMm, b.min_y - kMm, b.max_x + kMm, b.max_y + kMm, pixel);
        std::vector<uint8_t> image;
        rasterize(walls, g, image);
        const double pixels_mm2 = double(count_white(image)) * pixel_mm2;
        const double paths_mm2 = length_mm * st.nozzle;
        ASSERT_GT(paths_mm2, 0) << "layer " << layer->partition().index;
        ratios.push_back(pixels_mm2 / paths_mm2);
        total_pixels_mm2 += pixels_mm2;
        total_paths_mm2 += paths_mm2;
    }
    ASSERT_EQ(layers, 200);
    std::sort(ratios.begin(), ratios.end());
    // The stack cures 1.5 w where a cavity meets the outer wall (the shell w, plus the cavity
    // shrunk by half the minimal wall), the paths print w there: the more of the cavities' edge
    // runs along the outer wall, the higher the ratio. 1.10 once narrow parts were carved whole
    // (--whole-width 4), 1.16 once thin cover bands lost their edge loop, 1.20 once parts up to
    // the longest bridge under earlier cavities are carved whole: the stack's code did not
    // change, only the partition and the paths it is compared with.
    EXPECT_NEAR(total_pixels_mm2 / total_paths_mm2, 1.0, 0.25);
    EXPECT_NEAR(ratios[ratios.size() / 2], 1.0, 0.25);  // median layer
    EXPECT_GT(ratios.front(), 0.6);
    EXPECT_LT(ratios.back(),
              2.0);  // 1.89 at whole-width-max 14: a layer where a cavity lines the wall
}

// --raster-pixel: the images cover the same footprint whatever the pixel size, so their sides
// scale with 1 / pixel while the cured area they show stays the same.
TEST(RasterWriter, PixelSizeSetsTheImageSize) {
    Settings st;
    BBox2 box;
    box.min_x = 0, box.min_y = 0, box.max_x = 20 * kMm, box.max_y = 20 * kMm, box.empty = false;
    for (const double pixel_mm : {0.025, 0.05, 0.1, 0.2}) {
        const auto dir = fresh_dir("pixel");
        RasterWriter writer(dir.string(), st, box, pixel_mm);
        writer.add_layer(centred_cavity(st, 0));
        writer.finish();
        const int side = int(std::lround(20 / pixel_mm)) + 8;  // 4 pixels of margin each side
        EXPECT_EQ(writer.grid().width, side) << pixel_mm;
        EXPECT_EQ(writer.grid().height, side) << pixel_mm;
        png_image image{};
        image.version = PNG_IMAGE_VERSION;
        ASSERT_TRUE(png_image_begin_read_from_file(&image, (dir / "layer_00000.png").c_str()));
        EXPECT_EQ(int(image.width), side);
        EXPECT_EQ(int(image.height), side);
        png_image_free(&image);
        // The cured area: the 20 mm square less the 9.6 mm hollow (0.4 mm default wall).
        const double area = double(writer.layer_stats()[0].white_pixels) * pixel_mm * pixel_mm;
        EXPECT_NEAR(area, 400 - 9.6 * 9.6, 20 * 9.6 * pixel_mm) << pixel_mm;
        std::filesystem::remove_all(dir);
    }
}

// --raster-min-wall: the cavity's outline is thickened by half the wall into the cavity, so
// the cured band along a 10 mm square cavity is (outline length 40 mm) x (wall / 2), less the
// four corner squares, whatever the pixel size; within one pixel row along the hollow's edges.
TEST(RasterWriter, WallPixelsFollowWallLengthTimesThickness) {
    Settings st;
    BBox2 box;
    box.min_x = 0, box.min_y = 0, box.max_x = 20 * kMm, box.max_y = 20 * kMm, box.empty = false;
    for (const double pixel_mm : {0.025, 0.05, 0.1}) {
        int64_t full = 0;
        {
            const auto dir = fresh_dir("full");
            RasterWriter writer(dir.string(), st, box, pixel_mm);
            writer.add_layer(square_layer(st, 0));
            writer.finish();
            full = writer.layer_stats()[0].white_pixels;
            std::filesystem::remove_all(dir);
        }
        double previous_band = 0;
        for (const double wall : {0.2, 0.4, 0.8, 1.6}) {
            const auto dir = fresh_dir("band");
            RasterWriter writer(dir.string(), st, box, pixel_mm, wall);
            writer.add_layer(centred_cavity(st, 0));
            writer.finish();
            const double px2 = pixel_mm * pixel_mm;
            const double hollow = double(full - writer.layer_stats()[0].white_pixels) * px2;
            const double band = 100 - hollow;
            const double expected = 40 * (wall / 2) - 4 * (wall / 2) * (wall / 2);
            EXPECT_NEAR(band, expected, 4 * (10 - wall) * pixel_mm / 2 + 1e-9)
                << "pixel " << pixel_mm << " mm, wall " << wall << " mm";
            EXPECT_GT(band, previous_band);
            previous_band = band;
            std::filesystem::remove_all(dir);
        }
    }
}

// On a real model: the wall area the images cure, per layer, does not depend on the pixel size
// (within 3 % over the sampled layers), and stays consistent with the print paths' length x
// line width as in WallPixelsMatchPrintPathLengths.
TEST(RasterWriter, WallAreaOfARealModelDoesNotDependOnPixelSize) {
    CARVE_NEED_MODEL(kSphere);
    Settings st;
    SphereLayers sphere(st);
    BridgeStage& bridges = sphere.bridges;
    const std::vector<double> pixels_um = {25, 50, 100};
    std::vector<double> total_mm2(pixels_um.size(), 0.0);
    double paths_mm2 = 0;
    while (auto layer = bridges.next()) {
        if (layer->partition().index % 20 != 10) continue;
        const LayerToolpaths paths = plan_layer(*layer, st);
        paths_mm2 += thin_band_mm2(layer->partition(), st);
        for (const Extrusion& e : paths.extrusions)
            paths_mm2 += length(Paths{e.points}, e.closed) / kMm * st.nozzle;
        const Paths solid =
            resin_solid(*layer, st.line_width(), st.line_width(), st.nozzle_radius());
        const Paths walls = subtract(solid, erode(layer->bridged.remainder, st.nozzle_radius()));
        const BBox2 b = bounds(layer->partition().outline);
        for (size_t k = 0; k < pixels_um.size(); ++k) {
            const double p = pixels_um[k];
            const RasterGrid g =
                grid_over(b.min_x - kMm, b.min_y - kMm, b.max_x + kMm, b.max_y + kMm, p);
            std::vector<uint8_t> image;
            rasterize(walls, g, image);
            total_mm2[k] += double(count_white(image)) * (p / kMm) * (p / kMm);
        }
    }
    ASSERT_GT(paths_mm2, 0);
    for (size_t k = 1; k < pixels_um.size(); ++k)
        EXPECT_NEAR(total_mm2[k] / total_mm2[0], 1.0, 0.03) << pixels_um[k] << " um";
    EXPECT_NEAR(total_mm2[1] / paths_mm2, 1.0, 0.25);  // as in WallPixelsMatchPrintPathLengths
}

// End to end through the carve executable: --raster-pixel and --raster-min-wall reach the
// images and raster.json.
TEST(RasterCli, PixelAndWallOptionsReachTheStack) {
    CARVE_MODEL(sphere, kSphere);
    const auto run = [&sphere](const std::string& name, const std::string& args) {
        const auto dir = fresh_dir(name);
        std::filesystem::create_directories(dir);
        const std::string cmd = std::string(CARVE_BINARY) + " slice " + sphere +
                                " --scale 0.5 --cavities 2 -q -o " + (dir / "out.gcode").string() +
                                " --raster " + (dir / "stack").string() + " " + args;
        EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
        std::ifstream in(dir / "stack" / "raster.json");
        std::stringstream ss;
        ss << in.rdbuf();
        return nlohmann::json::parse(ss.str());
    };
    const auto fine = run("cli_fine", "--raster-pixel 0.025");
    const auto coarse = run("cli_coarse", "--raster-pixel 0.1 --raster-min-wall 1.2");
    const auto plain = run("cli_plain", "");
    EXPECT_DOUBLE_EQ(fine["pixel_mm"].get<double>(), 0.025);
    EXPECT_DOUBLE_EQ(plain["pixel_mm"].get<double>(), 0.05);  // the documented default
    EXPECT_DOUBLE_EQ(plain["min_wall_mm"].get<double>(), 0.4);
    EXPECT_DOUBLE_EQ(coarse["min_wall_mm"].get<double>(), 1.2);
    EXPECT_DOUBLE_EQ(plain["shell_mm"].get<double>(), 0.4);
    EXPECT_DOUBLE_EQ(coarse["shell_mm"].get<double>(), 1.2);  // the outer wall is cured too
    // A 20 mm sphere: 800 + 8 pixels across at 0.025 mm, 200 + 8 at 0.1 mm (+1 for rounding).
    EXPECT_NEAR(fine["width_px"].get<int>(), 808, 1);
    EXPECT_NEAR(coarse["width_px"].get<int>(), 208, 1);
    // Thicker cavity walls cure more resin.
    int64_t thin = 0, thick = 0;
    for (const auto& v : plain["white_pixels"]) thin += v.get<int64_t>();
    for (const auto& v : coarse["white_pixels"]) thick += v.get<int64_t>();
    EXPECT_GT(double(thick) * 0.01, double(thin) * 0.0025 * 1.05);
    for (const char* d : {"cli_fine", "cli_coarse", "cli_plain"}) fresh_dir(d);  // removes it
}

// A full disk (/dev/full) fails the PNG with libpng's words and the system's reason for the
// caller's one line, and libpng prints nothing of its own ("libpng error: Write Error", twice).
TEST(RasterPng, AFullDiskIsReportedWithItsReasonAndNothingPrinted) {
    std::FILE* full = std::fopen("/dev/full", "wb");
    if (!full) GTEST_SKIP() << "no /dev/full on this machine";
    std::setvbuf(full, nullptr, _IONBF, 0);  // every write reaches the device
    const std::vector<uint8_t> pixels(64 * 64, 255);
    std::string why;
    testing::internal::CaptureStderr();
    const bool ok =
        carve::write_png(full, 64, 64, pixels.data(), carve::PngFormat{1, 6, true}, &why);
    const std::string printed = testing::internal::GetCapturedStderr();
    std::fclose(full);
    EXPECT_FALSE(ok);
    EXPECT_NE(why.find("No space left on device"), std::string::npos) << why;
    EXPECT_EQ(printed, "");
}

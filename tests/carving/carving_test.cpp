// Properties of the carving sweep on every layer of real and synthetic models (report section 3).
#include "carving/carving.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"
#include "mesh/mesh.hpp"
#include "support/models.hpp"
#include "support/sanitizers.hpp"

using namespace carve;

namespace {

std::string model(const std::string& name) {
    return carve::test::any_model(name);
}

struct SweepFigures {
    int layers = 0;
    double carvable_mm3 = 0, remainder_mm3 = 0, model_mm3 = 0;
    std::vector<double> cavity_mm3;
    double worst_partition_error = 0;  // relative area error of the partition, worst layer
    // Area of (C^j_{i+1} grown by r) \ C^j_i once opened by 3 um: Clipper rounds every
    // intersection to the micrometre, so the sweep's V^j and the test's own V^j differ by
    // slivers under a micrometre wide along whole contours (0.01 mm^2 on the sphere); a real
    // overhang is as wide as r.
    double worst_support_violation_mm2 = 0;
    double specks_left_mm2 = 0;  // summed over the slices
    double worst_cover_overlap_mm2 = 0;
    // Tear front: area of cavity pieces that reach beyond dilate(C^j_{i+1}, r + tear) in a
    // component the cavity above already touches, and the widest piece torn where it does not.
    double worst_tear_excess_mm2 = 0;
    double widest_new_tear_mm = 0;
};

// Runs the sweep over a model and checks, layer by layer, the invariants of the partition.
SweepFigures sweep(const std::string& path, Settings settings) {
    MeshReport report;
    Mesh mesh = load_mesh(path, report);
    TopDownSlicer slicer(mesh, settings.layer_height);
    CarvableStream carvable(slicer, settings);
    CarvingSweep carving(carvable, settings);
    SweepFigures f;
    f.model_mm3 = report.volume_mm3;
    f.cavity_mm3.assign(sweep_iterations(settings), 0);
    const Coord r = settings.dilation_per_layer();
    std::optional<LayerPartition> above;
    while (auto layer = carving.next()) {
        ++f.layers;
        const double h = settings.layer_height;
        f.carvable_mm3 += area_mm2(layer->carvable) * h;
        f.remainder_mm3 += area_mm2(layer->remainder) * h;
        // Partition: pairwise disjoint pieces whose union is the carvable region.
        Paths all = layer->remainder;
        double sum = area(layer->remainder);
        for (size_t j = 0; j < layer->cavities.size(); ++j) {
            f.cavity_mm3[j] += area_mm2(layer->cavities[j]) * h;
            sum += area(layer->cavities[j]);
            all = unite(all, layer->cavities[j]);
            f.worst_cover_overlap_mm2 = std::max(
                f.worst_cover_overlap_mm2, area_mm2(intersect(layer->cavities[j], layer->covers)));
        }
        const double whole = area(layer->carvable);
        if (whole > 1e6) {  // above 1 mm^2: smaller slices only carry rounding noise
            f.worst_partition_error =
                std::max({f.worst_partition_error, std::abs(sum - whole) / whole,
                          area(symmetric_difference(all, layer->carvable)) / whole});
        }
        // Self-support: the cavity above, grown by r and clipped to what iteration j could
        // carve here, lies inside the cavity here, but for specks the sweep passes on uncarved
        // (pieces within two line widths and under (w/2)^2, which no wall or fill can use).
        if (above) {
            const double w = double(settings.line_width());
            Paths remainder = layer->carvable;
            for (size_t j = 0; j < layer->cavities.size(); ++j) {
                Paths grown = intersect(dilate(above->cavities[j], r), remainder);
                double violation = 0;
                for (const Paths& piece :
                     components(open(subtract(grown, layer->cavities[j]), 3))) {
                    const BBox2 b = bounds(piece);
                    const bool speck =
                        std::hypot(double(b.max_x - b.min_x), double(b.max_y - b.min_y)) < 2 * w &&
                        std::abs(area(piece)) < 0.25 * w * w;
                    (speck ? f.specks_left_mm2 : violation) += area_mm2(piece);
                }
                f.worst_support_violation_mm2 = std::max(f.worst_support_violation_mm2, violation);
                remainder = subtract(remainder, layer->cavities[j]);
            }
        }
        if (above) {
            // 5 um: the 24-gon's dilations and Clipper's rounding.
            const Coord reach = r + to_units(settings.tear_limit_mm()) + 5;
            for (size_t j = 0; j < layer->cavities.size(); ++j) {
                const Paths& up = above->cavities[j];
                const Paths grown = up.empty() ? Paths{} : dilate(up, reach);
                for (const Paths& piece : components(layer->cavities[j])) {
                    if (!intersect(piece, up).empty()) {
                        f.worst_tear_excess_mm2 =
                            std::max(f.worst_tear_excess_mm2, area_mm2(subtract(piece, grown)));
                    } else {
                        const BBox2 b = bounds(piece);
                        f.widest_new_tear_mm =
                            std::max(f.widest_new_tear_mm,
                                     to_mm(std::max(b.max_x - b.min_x, b.max_y - b.min_y)));
                    }
                }
            }
        }
        above = std::move(layer);
    }
    return f;
}

}  // namespace

TEST(Carving, FigureThreeCubeTwoIterations) {
    CARVE_NEED_MODEL("synthetic/fig3_cube_indent.stl");
    Settings s;
    s.cavities = 2;
    // Torn along its axis as the report does up to 4 mm wide parts (carved whole, the default
    // since ribs hold wide ceilings, C^1 would take it all).
    s.whole_width = 4;
    s.whole_width_max = 14;
    const SweepFigures f = sweep(model("synthetic/fig3_cube_indent.stl"), s);
    EXPECT_EQ(f.layers, 60);
    ASSERT_EQ(f.cavity_mm3.size(), 2u);
    EXPECT_GT(f.cavity_mm3[0], 0.3 * f.carvable_mm3);  // C^1 takes most of the volume
    EXPECT_GT(f.cavity_mm3[1], 0.0);                   // C^2 is seeded in what C^1 left
    EXPECT_LT(f.worst_partition_error, 1e-4);
    EXPECT_LT(f.worst_support_violation_mm2, 0.001);
    EXPECT_LT(f.worst_cover_overlap_mm2, 0.005);  // integer rounding slivers of ~1 um width
}

TEST(Carving, SphereSixIterationsLeavesLittle) {
    CARVE_NEED_MODEL("synthetic/sphere_40mm.stl");
    Settings s;
    s.cavities = 6;
    const SweepFigures f = sweep(model("synthetic/sphere_40mm.stl"), s);
    double carved = 0;
    for (double v : f.cavity_mm3) carved += v;
    EXPECT_NEAR(carved + f.remainder_mm3, f.carvable_mm3, 1e-3 * f.carvable_mm3);
    RecordProperty("remainder_percent_of_volume",
                   std::to_string(100 * f.remainder_mm3 / f.model_mm3));
    std::printf("sphere: V^6 = %.2f %% of the model volume, carvable %.1f %%\n",
                100 * f.remainder_mm3 / f.model_mm3, 100 * f.carvable_mm3 / f.model_mm3);
    EXPECT_LT(f.remainder_mm3, 0.05 * f.model_mm3);
    EXPECT_LT(f.worst_partition_error, 1e-4);
    EXPECT_LT(f.worst_support_violation_mm2, 0.001);
}

TEST(Carving, FandiskEveryLayerIsAnExactSelfSupportingPartition) {
    Settings s;
    const SweepFigures f = sweep(model("fandisk.stl"), s);
    std::printf("fandisk: V^6 = %.2f %% of the model volume; specks left uncarved %.4f %%\n",
                100 * f.remainder_mm3 / f.model_mm3,
                100 * f.specks_left_mm2 * s.layer_height / f.model_mm3);
    EXPECT_EQ(f.layers, 400);
    EXPECT_LT(f.worst_partition_error, 1e-4);
    EXPECT_LT(f.worst_support_violation_mm2, 0.001);
    EXPECT_LT(f.worst_cover_overlap_mm2, 0.005);  // integer rounding slivers of ~1 um width
    EXPECT_LT(f.remainder_mm3, 0.05 * f.model_mm3);
    EXPECT_LT(f.specks_left_mm2 * s.layer_height, 1e-4 * f.model_mm3);
}

TEST(Carving, ZeroCavitiesIsAPlainShell) {
    CARVE_NEED_MODEL("synthetic/tall_box_30x30x80.stl");
    Settings s;
    s.cavities = 0;
    const SweepFigures f = sweep(model("synthetic/tall_box_30x30x80.stl"), s);
    EXPECT_TRUE(f.cavity_mm3.empty());
    EXPECT_NEAR(f.remainder_mm3, f.carvable_mm3, 1e-9);
}

TEST(Carving, CoversKeepTopAndBottomSolid) {
    CARVE_NEED_MODEL("synthetic/tall_box_30x30x80.stl");
    Settings s;
    s.covers = 3;
    MeshReport report;
    Mesh mesh = load_mesh(model("synthetic/tall_box_30x30x80.stl"), report);
    TopDownSlicer slicer(mesh, s.layer_height);
    CarvableStream stream(slicer, s);
    int n = slicer.layer_count(), seen = 0;
    while (auto layer = stream.next()) {
        ++seen;
        const bool near_surface = layer->index < 3 || layer->index >= n - 3;
        EXPECT_EQ(layer->carvable.empty(), near_surface) << "layer " << layer->index;
        // Inside: the carvable region is bounded by the outer wall centreline, s inside.
        if (!near_surface) {
            EXPECT_NEAR(area_mm2(layer->carvable), (30 - 0.4) * (30 - 0.4), 0.5);
        }
    }
    EXPECT_EQ(seen, n);
}

// --solid-below (issue 49): the interior narrower than it is left to the covers, solid, the rest
// carvable as before: a 20 mm square with a 4 mm wide arm keeps the square carvable, and the
// arm only without the option.
TEST(Carving, InteriorNarrowerThanSolidBelowIsNotCarvable) {
    Settings s;
    s.covers = 0;  // the slice's own region alone decides
    const Coord mm = to_units(1.0);
    Path square{{0, 0}, {20 * mm, 0}, {20 * mm, 20 * mm}, {0, 20 * mm}};
    Path arm{{20 * mm, 8 * mm}, {35 * mm, 8 * mm}, {35 * mm, 12 * mm}, {20 * mm, 12 * mm}};
    Slice slice{0, 0.1, unite(Paths{square}, Paths{arm})};
    auto carvable = [&](double solid_below) {
        s.solid_below = solid_below;
        const CoverSlice e = cover_slice(slice, s);
        return carvable_layer(0, {&e}, s);
    };
    const LayerPartition plain = carvable(0);
    const LayerPartition solid = carvable(5);
    const double arm_mm2 = (15 - 0.2) * (4 - 0.4);  // the arm inside the wall's centreline
    EXPECT_NEAR(area_mm2(plain.carvable), (20 - 0.4) * (20 - 0.4) + arm_mm2, 1);
    EXPECT_LT(area_mm2(plain.covers), 0.01);
    // The opening takes at most the square's four corners (rounded to its radius, 2.5 mm:
    // (4 - pi) r^2) besides the arm, which the covers get.
    const double corners_mm2 = (4 - std::acos(-1.0)) * 2.5 * 2.5;
    EXPECT_LE(area_mm2(solid.carvable), (20 - 0.4) * (20 - 0.4) + 0.01);
    EXPECT_GE(area_mm2(solid.carvable), (20 - 0.4) * (20 - 0.4) - corners_mm2 - 0.5);
    EXPECT_NEAR(area_mm2(solid.covers) + area_mm2(solid.carvable), area_mm2(plain.carvable), 0.5);
    const Point mid_arm(28 * mm, 10 * mm), mid_square(10 * mm, 10 * mm);
    EXPECT_TRUE(point_in_region(mid_arm, plain.carvable));
    EXPECT_FALSE(point_in_region(mid_arm, solid.carvable));
    EXPECT_TRUE(point_in_region(mid_arm, solid.covers));
    EXPECT_TRUE(point_in_region(mid_square, solid.carvable));
}

// --solid-below-area (issue 49), PrusaSlicer's solid_infill_below_area: an island of the slice
// smaller than it goes to the covers whole, a larger one is carved as before, and a hole in an
// island counts against its area.
TEST(Carving, IslandSmallerThanSolidBelowAreaIsNotCarvable) {
    Settings s;
    s.covers = 0;
    const Coord mm = to_units(1.0);
    const Path big{{0, 0}, {20 * mm, 0}, {20 * mm, 20 * mm}, {0, 20 * mm}};  // 400 mm2
    const Path small{{30 * mm, 0}, {40 * mm, 0}, {40 * mm, 10 * mm}, {30 * mm, 10 * mm}};  // 100
    const Path hole{{32 * mm, 2 * mm}, {32 * mm, 8 * mm}, {38 * mm, 8 * mm}, {38 * mm, 2 * mm}};
    auto carvable = [&](double limit, const Paths& region) {
        s.solid_below_area = limit;
        const CoverSlice e = cover_slice(Slice{0, 0.1, region}, s);
        return carvable_layer(0, {&e}, s);
    };
    const Paths two{big, small};
    const Point in_big(10 * mm, 10 * mm), in_small(35 * mm, 1 * mm);
    const LayerPartition plain = carvable(0, two);
    EXPECT_TRUE(point_in_region(in_big, plain.carvable));
    EXPECT_TRUE(point_in_region(in_small, plain.carvable));
    const LayerPartition solid = carvable(101, two);
    EXPECT_TRUE(point_in_region(in_big, solid.carvable));
    EXPECT_FALSE(point_in_region(in_small, solid.carvable));
    EXPECT_TRUE(point_in_region(in_small, solid.covers));
    EXPECT_NEAR(area_mm2(solid.carvable), (20 - 0.4) * (20 - 0.4), 0.05);
    EXPECT_NEAR(area_mm2(carvable(99, two).carvable), area_mm2(plain.carvable), 0.05);
    // With a 36 mm2 hole the small island is 64 mm2: under 70, over 60.
    const Paths holed{big, small, hole};
    EXPECT_FALSE(point_in_region(in_small, carvable(70, holed).carvable));
    EXPECT_TRUE(point_in_region(in_small, carvable(60, holed).carvable));
}

// Issue 48: a hole narrower than a line (a sliver void of the man mesh, 0.2 x 0.1 mm where it
// starts) gets its wall, but the cover under it, the hole grown by s, held no line: the wall
// was printed over the cavity. The interior within s + w of such a hole is not carvable, so the
// covers under it and the solid beside its wall hold a line; a hole a line fits in is as before.
TEST(Carving, InteriorBesideAHoleNarrowerThanALineIsNotCarvable) {
    Settings s;
    s.covers = 0;
    const Coord mm = to_units(1.0);
    const Coord sr = s.nozzle_radius(), w = s.line_width();
    auto rect_mm = [&](double x0, double y0, double x1, double y1) {
        return Paths{Path{{to_units(x0), to_units(y0)},
                          {to_units(x1), to_units(y0)},
                          {to_units(x1), to_units(y1)},
                          {to_units(x0), to_units(y1)}}};
    };
    const Path square = rect_mm(0, 0, 20, 20).front();
    auto carvable_with_hole = [&](Coord side) {
        const Coord c = 10 * mm;
        Path hole{{c, c}, {c, c + side}, {c + side, c + side}, {c + side, c}};  // clockwise
        const CoverSlice e = cover_slice(Slice{0, 0.1, Paths{square, hole}}, s);
        return carvable_layer(0, {&e}, s);
    };
    const LayerPartition pin = carvable_with_hole(mm / 5);  // 0.2 mm
    const LayerPartition wide = carvable_with_hole(2 * mm);
    const double inner = (20 - 0.4) * (20 - 0.4);
    // Wide: carvable round the hole's own wall (the hole grown by s).
    EXPECT_NEAR(area_mm2(wide.carvable), inner - area_mm2(dilate(rect_mm(10, 10, 12, 12), sr)),
                0.05);
    // Narrow: a disk of s + w more round it is left to the covers, and a line fits in them.
    const Paths kept = dilate(rect_mm(10, 10, 10.2, 10.2), sr + w);
    EXPECT_NEAR(area_mm2(pin.carvable), inner - area_mm2(kept), 0.05);
    EXPECT_FALSE(erode(pin.covers, w / 2).empty());
    EXPECT_TRUE(intersect(pin.carvable, kept).empty());
}

// The report's conclusion: a tear front limited to r/2 per slice. On the indented cube the
// unlimited seed opens the whole pruned axis (an X across the square) in one slice, and the
// cavity front runs far ahead of the dilation; limited to r/2, every new wall stays within
// r + r/2 of the cavity above (the seed's own half width s included) and new tears start no
// wider than a seed's width plus 2 r/2.
TEST(Carving, TearLimitBoundsHowFastCavitiesOpen) {
    CARVE_NEED_MODEL("synthetic/fig3_cube_indent.stl");
    Settings open;
    open.carving = CarvingScheme::Report;
    open.cavities = 2;
    const SweepFigures free = sweep(model("synthetic/fig3_cube_indent.stl"), open);
    EXPECT_GT(free.widest_new_tear_mm, 3.0);

    EXPECT_GT(free.worst_tear_excess_mm2, 1.0);  // the unlimited tear runs far beyond r + r/2

    Settings limited = open;
    limited.tear_limit = to_mm(limited.dilation_per_layer()) / 2;  // r/2 = 0.1 mm
    const SweepFigures f = sweep(model("synthetic/fig3_cube_indent.stl"), limited);
    EXPECT_LT(f.worst_tear_excess_mm2, 0.001);
    EXPECT_LE(f.widest_new_tear_mm, 2 * (0.1 + 0.2) + 0.1);
    EXPECT_LT(f.worst_partition_error, 1e-4);
    EXPECT_LT(f.worst_support_violation_mm2, 0.001);
    // Opening slower carves less: the uncarved remainder is what the limit costs.
    EXPECT_GT(f.remainder_mm3, free.remainder_mm3);
}

// Issue #23: at the defaults (parts carved whole, no tear limit) the figure-3 cube keeps an
// exact, self-supporting partition and leaves nothing to print solid. The cavity front does not
// stay within r of the one above (its ceilings are whole: ribs hold them, see
// Ribs.FigureThreeCubeHeldEndToEnd), so that is not asserted; the excess is recorded.
TEST(Carving, FigureThreeCubeAtDefaultsIsCarvedWhole) {
    CARVE_NEED_MODEL("synthetic/fig3_cube_indent.stl");
    const Settings s;
    const SweepFigures f = sweep(model("synthetic/fig3_cube_indent.stl"), s);
    RecordProperty("tear_excess_mm2", std::to_string(f.worst_tear_excess_mm2));
    EXPECT_LT(f.worst_partition_error, 1e-4);
    EXPECT_LT(f.worst_support_violation_mm2, 0.001);
    EXPECT_LT(f.remainder_mm3, 0.01 * f.model_mm3);
}

namespace {

// A closed box as a binary STL in the temporary folder; returns its path.
std::string box_stl(const std::string& name, float x1, float y1, float z1) {
    const float v[8][3] = {{0, 0, 0},  {x1, 0, 0},  {x1, y1, 0},  {0, y1, 0},
                           {0, 0, z1}, {x1, 0, z1}, {x1, y1, z1}, {0, y1, z1}};
    const int f[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                          {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
    const std::string path =
        (std::filesystem::temp_directory_path() / (name + std::to_string(getpid()) + ".stl"))
            .string();
    std::FILE* out = std::fopen(path.c_str(), "wb");
    char header[80] = {};
    std::fwrite(header, 1, 80, out);
    const uint32_t n = 12;
    std::fwrite(&n, 4, 1, out);
    for (const auto& t : f) {
        const float normal[3] = {0, 0, 0};
        std::fwrite(normal, 4, 3, out);
        for (int k = 0; k < 3; ++k) std::fwrite(v[t[k]], 4, 3, out);
        const uint16_t attr = 0;
        std::fwrite(&attr, 2, 1, out);
    }
    std::fclose(out);
    return path;
}

}  // namespace

TEST(Carving, NarrowPartIsCarvedWholeByTheFirstCavity) {
    // An 8 mm wide box holds no 10 mm disk: with a 10 mm whole width the first cavity is
    // all of the carvable volume from its top down, and the partition and self-support
    // invariants hold. Torn along its axis instead (whole width 0), the first cavity opens as
    // a strip and grows at 45 degrees, leaving wedges to later cavities.
    const std::string path = box_stl("narrow_box_", 8, 40, 20);
    Settings s;
    s.whole_width = 10.0;
    const SweepFigures whole = sweep(path, s);
    EXPECT_GT(whole.cavity_mm3[0], 0.995 * whole.carvable_mm3);
    EXPECT_LT(whole.worst_partition_error, 1e-3);
    EXPECT_LT(whole.worst_support_violation_mm2, 0.01);
    s.carving = CarvingScheme::Report;
    const SweepFigures torn = sweep(path, s);
    EXPECT_LT(torn.cavity_mm3[0], 0.95 * torn.carvable_mm3);  // 92 % today: the roof wedges
    EXPECT_LT(torn.worst_support_violation_mm2, 0.01);
    std::filesystem::remove(path);
}

// Parts up to the longest bridge are carved whole when what lies under the model's surface of
// them is narrower than the whole width: on the elephant's back and head (dome-like tops) the
// first cavities then take volume that nested rings of later cavities took, and every layer
// is still an exact, self-supporting partition.
TEST(Carving, WidePartUnderANarrowCeilingIsCarvedWhole) {
    SKIP_UNDER_SANITIZERS(
        "Carving.AtTheDefaultWholeWidthLaterIterationsFindNoSlivers and "
        "Carving.PreparedAheadGivesTheSamePartition, whose sweeps carve parts whole too");
    CARVE_MODEL(path, "elephant.stl");
    Settings s;
    s.whole_width = 4;  // the widths of this rule before ribs made every part carved whole
    s.whole_width_max = 14;
    const SweepFigures wide = sweep(path, s);
    EXPECT_LT(wide.worst_partition_error, 1e-3);
    EXPECT_LT(wide.worst_support_violation_mm2, 0.01);
    s.whole_width_max = s.whole_width;  // no part wider than the whole width is carved whole
    const SweepFigures narrow = sweep(path, s);
    const auto later = [](const SweepFigures& f) {
        double v = 0;
        for (size_t j = 2; j < f.cavity_mm3.size(); ++j) v += f.cavity_mm3[j];
        return v;
    };
    std::printf("C^3..C^k: %.0f mm3 (whole up to %.0f mm), %.0f mm3 (up to %.0f mm)\n", later(wide),
                14.0, later(narrow), s.whole_width);
    EXPECT_LT(later(wide), 0.8 * later(narrow));
    EXPECT_NEAR(wide.carvable_mm3, narrow.carvable_mm3, 1e-6 * narrow.carvable_mm3);
}

// At the default whole width every part is carved whole by the first cavity, except under
// what the first iteration left solid in the slice above: the first cavity is then the
// carvable region itself, and later iterations find nothing to carve. (Worked out with the
// booleans against the propagated cavity, it was the region up to Clipper's rounding, and the
// slivers between the two were carved again by later iterations, with walls of their own and
// bridges over them: 0.009 mm3 of second cavity on the elephant, 2.4 mm3 on the cat.)
TEST(Carving, AtTheDefaultWholeWidthLaterIterationsFindNoSlivers) {
    CARVE_MODEL(path, "elephant.stl");
    const SweepFigures f = sweep(path, Settings{});
    ASSERT_GE(f.cavity_mm3.size(), 2u);
    EXPECT_GT(f.cavity_mm3[0], 0.5 * f.carvable_mm3);
    double later = 0;
    for (size_t j = 1; j < f.cavity_mm3.size(); ++j) later += f.cavity_mm3[j];
    EXPECT_EQ(later, 0.0);
    EXPECT_LT(f.worst_partition_error, 1e-3);
    EXPECT_LT(f.worst_support_violation_mm2, 0.01);
}

namespace {

std::vector<LayerPartition> carvable_layers(const std::string& path, const Settings& settings) {
    MeshReport report;
    Mesh mesh = load_mesh(path, report);
    TopDownSlicer slicer(mesh, settings.layer_height);
    CarvableStream carvable(slicer, settings);
    std::vector<LayerPartition> layers;  // top down
    while (auto layer = carvable.next()) layers.push_back(std::move(*layer));
    return layers;
}

// Carves the layers one iteration at a time, as the run's pipeline does, but with every
// layer's prepare() before any carve(), bottom up: never in the sweep's order. Unless `ahead`,
// what prepare() worked out on the guess that every component stays open (and the axes it
// kept) is dropped, so that carve() works everything out itself, as the sweep did in one pass.
// Returns how many preparations made that guess.
int carve_in_halves(std::vector<LayerPartition>& layers, const Settings& settings, bool ahead) {
    int guesses = 0;
    for (int j = 0; j < sweep_iterations(settings); ++j) {
        CarvingSweep stage(settings, j, 1);
        std::vector<IterationPrep> preps(layers.size());
        for (size_t n = layers.size(); n-- > 0;) {
            preps[n] = stage.prepare(layers[n], n > 0 ? &layers[n - 1].carvable : nullptr);
            guesses += preps[n].guessed;
            if (!ahead) {
                preps[n].guessed = false;
                preps[n].parts.clear();
                preps[n].whole.clear();
                preps[n].known = skel::AxisMemo{};
            }
        }
        for (size_t n = 0; n < layers.size(); ++n) stage.carve(layers[n], std::move(preps[n]));
    }
    return guesses;
}

}  // namespace

// The medial axis and the whole-width test worked out for a slice before the slice above is
// carved, on the guess that the cavity above leaves every component open, give what the
// sweep works out once it knows which are: the same partition, vertex for vertex, as the
// one-pass sweep, on the elephant (parts carved whole under narrow ceilings) and fandisk.
TEST(Carving, PreparedAheadGivesTheSamePartition) {
    for (const char* name : {"elephant.stl", "fandisk.stl"}) {
        SCOPED_TRACE(name);
        const std::string path = model(name);
        Settings s;
        std::vector<LayerPartition> ahead = carvable_layers(path, s);
        std::vector<LayerPartition> alone = ahead;
        EXPECT_GT(carve_in_halves(ahead, s, true), 100);
        carve_in_halves(alone, s, false);
        MeshReport report;
        Mesh mesh = load_mesh(path, report);
        TopDownSlicer slicer(mesh, s.layer_height);
        CarvableStream carvable(slicer, s);
        CarvingSweep one_pass(carvable, s);
        size_t n = 0;
        while (auto layer = one_pass.next()) {
            ASSERT_LT(n, ahead.size());
            for (const std::vector<LayerPartition>* run : {&ahead, &alone}) {
                const LayerPartition& l = (*run)[n];
                ASSERT_EQ(l.index, layer->index);
                EXPECT_TRUE(l.cavities == layer->cavities) << "layer " << l.index;
                EXPECT_TRUE(l.remainder == layer->remainder) << "layer " << l.index;
                EXPECT_TRUE(l.uncarved == layer->uncarved) << "layer " << l.index;
                EXPECT_EQ(l.warnings, layer->warnings);
            }
            ++n;
        }
        EXPECT_EQ(n, ahead.size());
    }
}

// Issue #37: the report's scheme (--carving report: every part torn along its medial axis,
// k nested cavities) keeps every layer an exact partition of the carvable region, each cavity
// holding the one above grown by r, on the CC0 models of the repository and on the shared cat
// and skull (skipped, naming the model, without the shared folder); fandisk alone under the
// sanitizers.
TEST(Carving, ReportSchemeIsAnExactSelfSupportingPartitionOnTheModels) {
    for (const std::string& name : carve::test::first_under_sanitizers<std::string>(
             {"fandisk.stl", "elephant.stl", "man.stl", "cat.stl", "skull.stl"})) {
        SCOPED_TRACE(name);
        const std::string path = model(name);
        if (path.empty()) {
            std::printf("skipped %s: not found (shared models folder %s)\n", name.c_str(),
                        carve::test::shared_models_dir().string().c_str());
            continue;
        }
        Settings s;
        s.carving = CarvingScheme::Report;
        const SweepFigures f = sweep(path, s);
        double carved = 0;
        for (double v : f.cavity_mm3) carved += v;
        std::printf("%s, --carving report: C^1..C^6 %.1f %% of the carvable volume, V^6 %.2f %%\n",
                    name.c_str(), 100 * carved / f.carvable_mm3,
                    100 * f.remainder_mm3 / f.carvable_mm3);
        EXPECT_GT(f.cavity_mm3.at(1), 0.0);  // nested: the second cavity carves too
        EXPECT_NEAR(carved + f.remainder_mm3, f.carvable_mm3, 1e-3 * f.carvable_mm3);
        EXPECT_LT(f.worst_partition_error, 1e-3);
        EXPECT_LT(f.worst_support_violation_mm2, 0.01);
        EXPECT_LT(f.worst_cover_overlap_mm2, 0.005);
    }
}

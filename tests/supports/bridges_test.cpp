// Local minima and bridges on constructed slices (report 4.4 and figure 2).
#include "supports/bridges.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <set>
#include <string>

#include "carving/covers.hpp"
#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"
#include "mesh/mesh.hpp"
#include "slice/slicer.hpp"
#include "support/models.hpp"
#include "support/shapes.hpp"

using namespace carve;
using carve::test::distance_to_boundary;
using carve::test::rect;

namespace {

BridgeOptions options() {
    BridgeOptions o;
    o.line_width = 400;
    o.dilation = 200;
    o.max_length = 30000;  // the constructed cavities are 20 mm across
    return o;
}

// Upper cavity slice: the square [lo, hi]^2 with an empty 4 mm hole in the middle of the 20 mm
// frame; the slice below is the whole square grown by r, so the hole vanished there.
struct SlicePair {
    LayerPartition upper, lower;
};
SlicePair vanishing_island(Coord lo, Coord hi) {
    Path hole = rect(8000, 8000, 12000, 12000);
    std::reverse(hole.begin(), hole.end());
    SlicePair p;
    p.upper.carvable = p.lower.carvable = {rect(-5000, -5000, 25000, 25000)};
    p.upper.cavities = {{rect(lo, lo, hi, hi), hole}};
    p.lower.cavities = {dilate({rect(lo, lo, hi, hi)}, 200)};
    return p;
}

// Fandisk carved with nested cavities, several bridged on one slice: parts torn as before ribs
// (carved whole, the default since, fandisk has one cavity). Members in order: each stage
// holds a reference to the one before.
struct FandiskSweep {
    static Settings nested() {
        Settings s;
        s.whole_width = 4;
        s.whole_width_max = 14;
        // Every edge-like minimum bridged too (not only those deeper than the ribs' reach):
        // many slices with bridges in several cavities for these tests to follow.
        s.rib_reach = 0;
        return s;
    }
    FandiskSweep()
        : settings(nested()),
          mesh(load_mesh(carve::test::repo_model("fandisk.stl"), report)),
          slicer(mesh, settings.layer_height),
          carvable(slicer, settings),
          carving(carvable, settings) {}
    Settings settings;
    MeshReport report;
    Mesh mesh;
    TopDownSlicer slicer;
    CarvableStream carvable;
    CarvingSweep carving;
};

}  // namespace

TEST(Bridges, IslandHoleCoveredBelowGetsOneAnchoredBridge) {
    // Upper cavity slice: a 20 mm square with an empty 4 mm hole; the slice below is the whole
    // square grown by r: the hole vanished, so its walls would hang in the air.
    auto [upper, lower] = vanishing_island(0, 20000);
    const BridgedPartition bridged = bridge_layer(upper, &lower, options());

    ASSERT_EQ(bridged.bridges.size(), 1u);
    const Bridge& b = bridged.bridges[0];
    EXPECT_TRUE(b.island);
    EXPECT_EQ(b.cavity, 1);
    EXPECT_TRUE(std::fmod(b.angle_deg, 90.0) == 0.0) << b.angle_deg;  // shortest lines
    // The lines, widened to the line width, cover the hole.
    const Paths printed = dilate_lines(b.lines, 200);
    EXPECT_LT(area(subtract({rect(8000, 8000, 12000, 12000)}, printed)), 0.01 * 16e6);
    // Every line ends on the cavity boundary at both ends (anchored on the walls).
    const Paths outer{rect(0, 0, 20000, 20000)};
    for (const Path& line : b.lines) {
        ASSERT_EQ(line.size(), 2u);
        EXPECT_LT(distance_to_boundary(line.front(), outer), 5.0);
        EXPECT_LT(distance_to_boundary(line.back(), outer), 5.0);
    }
    // The hole is filled in the cavity: no wall is printed around it in this slice.
    EXPECT_TRUE(empty_holes(bridged.cavities[0]).empty());
}

TEST(Bridges, NothingWhenTheSliceBelowHoldsTheHole) {
    auto [upper, lower] = vanishing_island(0, 20000);
    // Below, the hole only shrinks by r: the cavity grows as it should, the walls are supported.
    lower.cavities = {dilate(upper.cavities[0], 200)};
    const BridgedPartition bridged = bridge_layer(upper, &lower, options());
    EXPECT_TRUE(bridged.bridges.empty());
}

TEST(Bridges, NarrowConcavityIsAnEdgeLikeMinimum) {
    // Report figure 2: a narrow notch (0.3 mm < 2r) cut into the cavity's left side vanishes
    // when the cavity is dilated into the slice below.
    const Paths cavity = subtract({rect(0, 0, 20000, 10000)}, {rect(0, 4850, 6000, 5150)});
    LayerPartition upper, lower;
    upper.carvable = lower.carvable = {rect(-1000, -1000, 21000, 11000)};
    upper.cavities = {cavity};
    lower.cavities = {intersect(dilate(cavity, 200), {rect(0, 0, 20000, 10000)})};
    const auto needs =
        unsupported_regions(upper.cavities[0], lower.cavities[0], upper.carvable, options());
    ASSERT_EQ(needs.size(), 1u);
    EXPECT_GT(area(needs[0]), 0.5 * 300 * 6000);
    const BridgedPartition bridged = bridge_layer(upper, &lower, options());
    ASSERT_EQ(bridged.bridges.size(), 1u);
    EXPECT_FALSE(bridged.bridges[0].island);
    // The least total length is one line along the notch, anchored on the walls at both ends
    // of the cavity (15 lines across it would total 150 mm against 20 mm).
    EXPECT_DOUBLE_EQ(bridged.bridges[0].angle_deg, 0.0);
    EXPECT_EQ(bridged.bridges[0].lines.size(), 1u);
}

TEST(Bridges, SpikeAtASharpCornerIsNotAMinimum) {
    // A cavity whose slice below is its exact dilation: only the tiny spikes at reflex corners
    // differ, and they are dropped by the area filter.
    const Paths cavity = {{{0, 0}, {20000, 0}, {20000, 20000}, {10000, 9000}, {0, 20000}}};
    const Paths carvable{rect(-5000, -5000, 25000, 25000)};
    const auto needs = unsupported_regions(cavity, dilate(cavity, 200), carvable, options());
    EXPECT_TRUE(needs.empty());
}

TEST(Bridges, CoversAreNotBridged) {
    // The carvable region stops where the covers start: cavity tops under a cover are spanned
    // by the cover's own solid lines.
    const Paths below{rect(0, 0, 20000, 20000)};
    const auto needs = unsupported_regions({}, below, {}, options());
    EXPECT_TRUE(needs.empty());
}

TEST(Bridges, SpansLongerThanThePrinterBridgesAreLeftOut) {
    // The same island inside a 20 mm cavity, with bridges limited to 10 mm: a 20 mm span would
    // sag more than the 4 mm minimum it holds, so no bridge is made.
    auto [upper, lower] = vanishing_island(0, 20000);
    BridgeOptions o = options();
    o.max_length = 10000;
    const BridgedPartition bridged = bridge_layer(upper, &lower, o);
    EXPECT_TRUE(bridged.bridges.empty());
    EXPECT_EQ(bridged.minima_found, 1);
    EXPECT_EQ(bridged.minima_unsupported, 1);  // counted in the stats
    // With a small cavity around the same minimum the bridge is short and kept.
    auto [small_upper, small_lower] = vanishing_island(6000, 14000);
    const BridgedPartition small_upper_bridged = bridge_layer(small_upper, &small_lower, o);
    EXPECT_EQ(small_upper_bridged.bridges.size(), 1u);
}

TEST(Bridges, MinimaMergeOnlyIntoNearbyPiecesLikeFullBooleans) {
    // Merging the minima into the cavities gives Clipper only the pieces near them: the result
    // must be the full booleans' all the same. Cavity 1 is the frame of the vanishing island
    // plus far pieces (one with a hole); cavity 2 and the remainder each have a piece inside
    // the island's hole (the minimum takes it) and a far piece (left alone).
    auto [upper, lower] = vanishing_island(0, 20000);
    Path far_hole = rect(43000, 3000, 47000, 7000);
    std::reverse(far_hole.begin(), far_hole.end());
    const Paths far1{rect(30000, 0, 34000, 4000), rect(40000, 0, 50000, 10000), far_hole};
    upper.cavities[0].insert(upper.cavities[0].end(), far1.begin(), far1.end());
    upper.cavities.push_back({rect(9000, 9000, 11000, 11000), rect(60000, 0, 62000, 2000)});
    upper.remainder = {rect(8200, 8200, 8800, 8800), rect(70000, 0, 72000, 2000)};
    upper.carvable = lower.carvable = {rect(-5000, -5000, 80000, 25000)};
    lower.cavities = {dilate(unite({rect(0, 0, 20000, 20000)}, far1), 200),
                      dilate({rect(60000, 0, 62000, 2000)}, 200)};
    const LayerPartition original = upper;
    const BridgedPartition bridged = bridge_layer(upper, &lower, options());

    ASSERT_EQ(bridged.bridges.size(), 1u);
    EXPECT_EQ(bridged.bridges[0].cavity, 1);
    const Paths& minimum = bridged.bridges[0].region;
    const auto same = [](const Paths& a, const Paths& b) {
        return std::abs(area(symmetric_difference(a, b))) < 100.0;  // um^2: rounding only
    };
    // The carved slice is only read: the bridged partition is the stage's own.
    EXPECT_EQ(upper.cavities, original.cavities);
    EXPECT_EQ(upper.remainder, original.remainder);
    EXPECT_TRUE(same(bridged.cavities[0], unite(original.cavities[0], minimum)));
    EXPECT_TRUE(same(bridged.cavities[1], subtract(original.cavities[1], minimum)));
    EXPECT_TRUE(same(bridged.remainder, subtract(original.remainder, minimum)));
    // The pieces inside the hole went to cavity 1; the far ones are still there.
    EXPECT_NEAR(area(bridged.cavities[1]), 2000.0 * 2000.0, 100.0);
    EXPECT_NEAR(area(bridged.remainder), 2000.0 * 2000.0, 100.0);
    EXPECT_NEAR(area(bridged.cavities[0]),
                20000.0 * 20000.0 + 4000.0 * 4000.0 + 10000.0 * 10000.0 - 4000.0 * 4000.0, 1000.0);
}

TEST(Bridges, WhatEachIterationLeftFollowsTheMinimaOnARealModel) {
    // The stage moves every minimum into its cavity once for all cavities of a slice, and
    // keeps V^{j-1} = C^j ∪ .. ∪ C^k ∪ V^k up to date for the toolpaths, which read the walls'
    // restriction from it. On fandisk, slice by slice, it must still be that union, and the
    // cavities and the remainder a partition of the carvable region.
    FandiskSweep fandisk;
    BridgeStage bridges(fandisk.carving, fandisk.settings);
    int layers_with_several = 0;
    double worst_union = 0, worst_partition = 0;
    while (auto layer = bridges.next()) {
        std::set<int> bridged;
        for (const Bridge& b : layer->bridged.bridges) bridged.insert(b.cavity);
        if (bridged.empty()) continue;
        layers_with_several += bridged.size() > 1;
        ASSERT_EQ(layer->bridged.uncarved.size(), layer->bridged.cavities.size());
        Paths left = layer->bridged.remainder;  // V^j, from j = k down
        double pieces = area(layer->bridged.remainder);
        for (size_t j = layer->bridged.cavities.size(); j-- > 0;) {
            left = unite(left, layer->bridged.cavities[j]);
            pieces += area(layer->bridged.cavities[j]);
            worst_union =
                std::max(worst_union,
                         std::abs(area(symmetric_difference(layer->bridged.uncarved[j], left))));
        }
        worst_partition =
            std::max({worst_partition, std::abs(pieces - area(layer->partition().carvable)),
                      std::abs(area(symmetric_difference(left, layer->partition().carvable)))});
    }
    EXPECT_GT(layers_with_several, 20);
    // um^2. The sweep's own rounding leaves up to 0.007 mm^2 between V^{j-1} and the union on
    // slices without bridges and 0.012 mm^2 off the partition, the same before the stage was
    // batched; a stale V^{j-1} is off by a whole minimum, at least 4 r^2 = 0.16 mm^2.
    EXPECT_LT(worst_union, 40000.0);
    EXPECT_LT(worst_partition, 40000.0);
    RecordProperty("worst_union_um2", std::to_string(worst_union));
}

TEST(Bridges, TheStageLeavesTheCarvedPartitionAsTheSweepMadeIt) {
    // Two sweeps of fandisk, one read as it comes out, one through the bridge stage: each
    // layer's carved partition must come out of the stage exactly as the sweep made it, also
    // on the slices whose minima the stage joined to their cavities (its own partition).
    FandiskSweep plain, fandisk;
    BridgeStage bridges(fandisk.carving, fandisk.settings);
    int changed = 0;
    while (auto layer = bridges.next()) {
        const std::optional<LayerPartition> swept = plain.carving.next();
        ASSERT_TRUE(swept);
        const LayerPartition& carved = layer->partition();
        ASSERT_EQ(carved.index, swept->index);
        EXPECT_EQ(carved.outline, swept->outline);
        EXPECT_EQ(carved.carvable, swept->carvable);
        EXPECT_EQ(carved.covers, swept->covers);
        EXPECT_EQ(carved.cavities, swept->cavities) << "layer " << carved.index;
        EXPECT_EQ(carved.remainder, swept->remainder) << "layer " << carved.index;
        EXPECT_EQ(carved.uncarved, swept->uncarved) << "layer " << carved.index;
        changed += layer->bridged.cavities != carved.cavities;
    }
    EXPECT_FALSE(plain.carving.next());
    EXPECT_GT(changed, 20);  // the stage did change cavities: in its own record
}

TEST(Bridges, CeilingOverACavityCarvedWholeIsBridgedAcrossItsShortSide) {
    // An 8 x 40 mm part carved whole (CarvingSweep with a whole width): the slice above is all
    // cover, the slice below all cavity. The cover is bridged wall to wall, across the 8 mm
    // side: the least total length cannot choose (every direction totals the area over the
    // spacing), the least sum of squared spans does.
    LayerPartition upper, lower;
    upper.covers = {rect(0, 0, 8000, 40000)};
    lower.carvable = {rect(0, 0, 8000, 40000)};
    lower.cavities = {lower.carvable};
    BridgeOptions o = options();
    o.max_length = 10000;
    const BridgedPartition bridged = bridge_layer(upper, &lower, o);
    ASSERT_EQ(bridged.bridges.size(), 1u);
    const Bridge& b = bridged.bridges[0];
    EXPECT_TRUE(b.cover);
    EXPECT_EQ(bridged.minima_found, 1);
    EXPECT_EQ(bridged.ceilings_found, 1);
    EXPECT_EQ(bridged.minima_unsupported, 0);
    double longest = 0;
    for (const Path& line : b.lines) longest = std::max(longest, length(Paths{line}, false));
    EXPECT_LE(longest, 8000.0 + 5);
    // The lines cover the ceiling but a line width along its ends.
    const Paths printed = dilate_lines(b.lines, 200);
    EXPECT_LT(std::abs(area(subtract(upper.covers, printed))), 0.03 * 8000.0 * 40000.0);
}

TEST(Bridges, CoverOverWallsIsNotBridged) {
    // A cover over a cavity only a line width wide (a seed strip): held by the walls beside
    // it, no bridge.
    LayerPartition upper, lower;
    upper.covers = {rect(0, 0, 20000, 20000)};
    lower.carvable = upper.covers;
    lower.cavities = {{rect(9800, 0, 10200, 20000)}};
    const BridgedPartition bridged = bridge_layer(upper, &lower, options());
    EXPECT_TRUE(bridged.bridges.empty());
    EXPECT_EQ(bridged.minima_found, 0);
}

TEST(Bridges, LongMinimumIsSplitIntoPiecesEachBridgedAcrossItsOwnNarrowSide) {
    // An L-shaped corridor 3.6 mm wide with arms 30 mm long, and in the slice above a 1 mm
    // strip along the middle of both arms (an L-shaped island hole that vanishes below). At
    // one angle some lines run 30 mm along an arm; cut into cells, each piece is bridged
    // across its own arm, 3.6 mm (pieces are bridged only within 4 mm).
    const Paths corridor = unite({rect(0, 0, 30000, 3600)}, {rect(0, 0, 3600, 30000)});
    const Paths strip = unite({rect(1300, 1300, 30000, 2300)}, {rect(1300, 1300, 2300, 30000)});
    LayerPartition upper, lower;
    upper.carvable = lower.carvable = {rect(-5000, -5000, 35000, 35000)};
    upper.cavities = {subtract(corridor, strip)};
    lower.cavities = {corridor};
    BridgeOptions o = options();
    o.max_length = 10000;
    const BridgedPartition bridged = bridge_layer(upper, &lower, o);
    EXPECT_EQ(bridged.minima_found, 1);
    // The corner, where no direction is short, is left out and the minimum counted.
    EXPECT_EQ(bridged.minima_unsupported, 1);
    ASSERT_GE(bridged.bridges.size(), 2u);
    double longest = 0;
    Paths printed;
    for (const Bridge& b : bridged.bridges)
        for (const Path& line : b.lines) {
            longest = std::max(longest, length(Paths{line}, false));
            printed.push_back(line);
        }
    EXPECT_LE(longest, 4000.0);
    // All but the cells about the corner (the strip holds 57 mm^2; 4 mm^2 left today).
    EXPECT_LT(std::abs(area(subtract(strip, dilate_lines(printed, 200)))), 6e6);
}

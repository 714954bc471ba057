// The layer pipeline's filter table against the token: each field's lifetime as the table
// states it (made once, used after, freed at its last use) is checked, and the check finds a
// table that gets one wrong.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "run/layer_pipeline.hpp"

using namespace carve;

namespace {

std::string error_of(const std::vector<LayerPipeline::Filter>& table) {
    const LifetimeError e = lifetime_error(table);
    if (!e.rule) return "";
    return std::string(TokenField::names[e.field]) + ": " + e.rule + " (" + e.filter + ")";
}

std::vector<LayerPipeline::Filter> table() {
    const auto rows = LayerPipeline::filters();
    return {rows.begin(), rows.end()};
}

LayerPipeline::Filter& row(std::vector<LayerPipeline::Filter>& t, const std::string& name) {
    for (LayerPipeline::Filter& f : t)
        if (f.name == name) return f;
    throw std::runtime_error("no filter " + name);
}

}  // namespace

TEST(LayerFilters, TheTableStatesEveryTokenFieldsLifetime) {
    EXPECT_EQ(error_of(table()), "");
    const auto rows = LayerPipeline::filters();
    EXPECT_STREQ(rows.front().name, "slice");
    EXPECT_STREQ(rows.back().name, "writers");
    // The chain, a carving iteration's two halves together: iteration j + 1's seed reads the
    // V^j that iteration j's sweep made.
    const std::vector<std::string> chain{
        "slice",    "chain",       "check",   "erode",    "window",    "covers",   "link",
        "seed C1",  "sweep C1",    "seed C2", "sweep C2", "hold back", "supports", "bridges",
        "rib link", "rib overlap", "ribs",    "paths",    "writers"};
    EXPECT_EQ(LayerPipeline::filter_names(2), chain);
}

TEST(LayerFilters, ATableThatMisstatesALifetimeIsFound) {
    auto t = table();
    row(t, "chain").makes = 0;
    EXPECT_EQ(error_of(t), "slice: used before it is made (check)");

    t = table();
    row(t, "paths").uses |= TokenField::cut;
    EXPECT_EQ(error_of(t), "cut: used after it is freed (paths)");

    t = table();
    row(t, "bridges").makes |= TokenField::record;
    EXPECT_EQ(error_of(t), "record: made by a second filter (bridges)");

    t = table();
    row(t, "erode").frees = 0;
    row(t, "window").frees |= TokenField::slice;
    EXPECT_EQ(error_of(t), "slice: freed after its last use (window)");

    t = table();
    row(t, "rib overlap").frees = 0;
    EXPECT_EQ(error_of(t), "rib_above: kept after its last use (rib overlap)");

    t = table();
    row(t, "paths").makes &= ~uint32_t(TokenField::volumes);
    EXPECT_EQ(error_of(t), "volumes: used before it is made (writers)");
}

// Print presets and the --strong scale (issue 49): --preset strong resolves to the settings
// docs/carve.1 states (the report's carving and 4 shells), options typed on the command line win
// over --strong, and the scale's steps are monotone in material on a small model.
#include "config/presets.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "base/error.hpp"
#include "support/carve_run.hpp"
#include "support/models.hpp"

namespace carve {
namespace {

TEST(Presets, StrongIsStrengthOneWhichIsTheReportsCarvingAndFourShells) {
    Settings s;
    apply_print_preset("strong", s);
    EXPECT_DOUBLE_EQ(s.strength, 1.0);
    apply_strength(s, false, false);
    EXPECT_EQ(s.shells, 4);
    EXPECT_EQ(s.carving, CarvingScheme::Report);
    EXPECT_EQ(s.covers, Settings{}.covers);  // covers stay: measured to pay less than shells
    EXPECT_EQ(s.walls, WallMode::Single);
}

TEST(Presets, TheReportsPresetsAndUnknownNames) {
    Settings a;
    apply_print_preset("3c1s", a);
    EXPECT_EQ(a.covers, 3);
    EXPECT_EQ(a.shells, 1);
    Settings b;
    EXPECT_THROW(apply_print_preset("stronger", b), InputError);
}

TEST(Strength, StepsAddShellsUnderTheReportsCarvingAndZeroChangesNothing) {
    const std::vector<std::pair<double, int>> steps{
        {0.25, 1}, {0.5, 2}, {0.75, 3}, {1.0, 4}, {0.1, 0}};
    for (const auto& [strength, shells] : steps) {
        const StrengthStep step = strength_step(strength);
        EXPECT_EQ(step.shells, shells) << strength;
        EXPECT_EQ(step.carving, CarvingScheme::Report) << strength;
    }
    Settings s;
    s.shells = 2;  // from a profile, say
    apply_strength(s, false, false);
    EXPECT_EQ(s.shells, 2);
    EXPECT_EQ(s.carving, CarvingScheme::Whole);
}

TEST(Strength, OptionsTypedWin) {
    Settings s;
    s.strength = 0.75;
    s.shells = 1;
    apply_strength(s, true, true);
    EXPECT_EQ(s.shells, 1);
    EXPECT_EQ(s.carving, CarvingScheme::Whole);
    apply_strength(s, false, true);
    EXPECT_EQ(s.shells, 3);
    EXPECT_EQ(s.carving, CarvingScheme::Whole);
}

// carve slice fandisk at a quarter of its size with ARGS: its stats.
nlohmann::json slice_stats(const std::string& args) {
    static int n = 0;
    const std::string stem = (test::scratch() / ("s" + std::to_string(++n))).string();
    const test::CarveRun r =
        test::run_carve("slice " + test::repo_model("fandisk.stl") + " --scale 0.25 -q -o " + stem +
                        ".gcode --stats " + stem + ".json " + args);
    EXPECT_EQ(r.status, 0) << args << "\n" << r.err;
    return nlohmann::json::parse(test::read(stem + ".json"), nullptr, false);
}

TEST(Strength, EndToEndThePresetResolvesAndTypedOptionsWin) {
    const nlohmann::json strong = slice_stats("--preset strong");
    ASSERT_TRUE(strong.contains("settings"));
    EXPECT_EQ(strong["settings"]["shells"], 4);
    EXPECT_EQ(strong["settings"]["carving_scheme"], "report");
    EXPECT_EQ(strong["settings"]["strong"], 1.0);
    const nlohmann::json typed = slice_stats("--preset strong --shells 1 --carving whole");
    ASSERT_TRUE(typed.contains("settings"));
    EXPECT_EQ(typed["settings"]["shells"], 1);
    EXPECT_EQ(typed["settings"]["carving_scheme"], "whole");
}

TEST(Strength, StepsAreMonotoneInMaterial) {
    double last = -1;
    for (const char* step : {"0", "0.25", "0.5", "0.75", "1"}) {
        const nlohmann::json stats = slice_stats(std::string("--strong ") + step);
        ASSERT_TRUE(stats.contains("extruded_volume_mm3")) << step;
        const double v = stats["extruded_volume_mm3"].get<double>();
        EXPECT_GT(v, last) << "--strong " << step;
        last = v;
    }
}

// --stats-strength: the stats hold what carve check --strength says of the same G-code, and the
// HTML report shows it and marks the weakest layer in the material plot.
TEST(Strength, StatsAndReportHoldTheStrengthOfTheWrittenGcode) {
    const std::string stem = (test::scratch() / "figures").string();
    const test::CarveRun r = test::run_carve(
        "slice " + test::repo_model("fandisk.stl") + " --scale 0.25 -q --strong 0.5 -o " + stem +
        ".gcode --stats " + stem + ".json --report " + stem + ".html --stats-strength");
    ASSERT_EQ(r.status, 0) << r.err;
    const nlohmann::json stats = nlohmann::json::parse(test::read(stem + ".json"), nullptr, false);
    ASSERT_TRUE(stats.contains("strength"));
    const nlohmann::json& s = stats["strength"];
    EXPECT_FALSE(s.contains("layers"));  // carve check --layers' table, not the stats'
    EXPECT_GT(s["time_s"].get<double>(), 0);
    const test::CarveRun c = test::run_carve("check " + stem + ".gcode --strength --json");
    ASSERT_EQ(c.status, 0) << c.err;
    const nlohmann::json check = nlohmann::json::parse(c.out, nullptr, false)["strength"];
    for (const char* key :
         {"grams", "weakest_section_mm4", "weakest_section_z_mm", "weakest_bond_mm2",
          "weakest_bond_z_mm", "compression_n_per_mm", "shear_n_per_mm"}) {
        ASSERT_TRUE(s[key].is_number()) << key;
        EXPECT_NEAR(s[key].get<double>(), check[key].get<double>(),
                    1e-9 * std::abs(check[key].get<double>()))
            << key;
    }
    EXPECT_GT(s["compression_n_per_mm"].get<double>(), 0);
    EXPECT_EQ(s["finite_elements"]["law"], "linear");
    // The grams follow the run's filament, as the stats' own weight does.
    EXPECT_NEAR(s["grams"].get<double>(), stats["filament_weight_g"].get<double>(),
                0.05 * stats["filament_weight_g"].get<double>());
    const std::string page = test::read(stem + ".html");
    EXPECT_NE(page.find("Stiffness (compression)"), std::string::npos);
    EXPECT_NE(page.find("class=\"weak\""), std::string::npos);
    EXPECT_NE(page.find(">weakest section</text>"), std::string::npos);
    // Without the option neither has it.
    const nlohmann::json plain = slice_stats("--strong 0.5");
    EXPECT_FALSE(plain.contains("strength"));
}

}  // namespace
}  // namespace carve

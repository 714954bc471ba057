// Print presets and the --strong scale (issue 49): --preset strong resolves to the settings
// docs/carve.1 states (ties and 2 shells on a squat model, 4 shells on a slender one), options
// typed on the command line win over --strong, the scale's steps are monotone in material on a
// small model, and --stats-strength puts the strength figures in the stats and the report.
#include "config/presets.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <tuple>
#include <vector>

#include "base/error.hpp"
#include "support/carve_run.hpp"
#include "support/models.hpp"

namespace carve {
namespace {

TEST(Presets, StrongIsTiesAndTwoShellsOnASquatPartFourShellsOnASlenderOne) {
    Settings squat;
    apply_print_preset("strong", squat);
    EXPECT_DOUBLE_EQ(squat.strength, 1.0);
    apply_strength(squat, 2.7, false, false);  // fandisk
    EXPECT_EQ(squat.shells, 2);
    EXPECT_DOUBLE_EQ(squat.tie_spacing, 5.5);
    EXPECT_EQ(squat.carving, CarvingScheme::Whole);  // the scheme stays
    EXPECT_EQ(squat.covers, Settings{}.covers);
    Settings slender;
    apply_print_preset("strong", slender);
    apply_strength(slender, 8.9, false, false);  // man
    EXPECT_EQ(slender.shells, 4);
    EXPECT_DOUBLE_EQ(slender.tie_spacing, 0.0);
    // cat (4.6) and elephant (4.7) are slender: shells measured stiffer there than ties.
    Settings cat;
    apply_print_preset("strong", cat);
    apply_strength(cat, 4.6, false, false);
    EXPECT_EQ(cat.shells, 4);
    EXPECT_DOUBLE_EQ(cat.tie_spacing, 0.0);
}

TEST(Presets, SlendernessIsTheSameAtEveryScale) {
    // A 10 x 10 x 40 box: 40 / sqrt(100) = 4; at twice the size the same.
    EXPECT_DOUBLE_EQ(slenderness(40, 4000), 4.0);
    EXPECT_DOUBLE_EQ(slenderness(80, 32000), 4.0);
    EXPECT_DOUBLE_EQ(slenderness(0, 10), 0.0);
}

TEST(Presets, TheReportsPresetsAndUnknownNames) {
    Settings a;
    apply_print_preset("3c1s", a);
    EXPECT_EQ(a.covers, 3);
    EXPECT_EQ(a.shells, 1);
    Settings b;
    EXPECT_THROW(apply_print_preset("stronger", b), InputError);
}

TEST(Strength, StepsScaleShellsAndTieDensityAndZeroChangesNothing) {
    // {S, shells squat, tie spacing squat, shells slender}
    const std::vector<std::tuple<double, int, double, int>> steps{
        {0.25, 1, 22.0, 1}, {0.5, 1, 11.0, 2}, {0.75, 2, 5.5 / 0.75, 3}, {1.0, 2, 5.5, 4}};
    for (const auto& [strength, shells, spacing, slender_shells] : steps) {
        const StrengthStep squat = strength_step(strength, 2.7);
        EXPECT_EQ(squat.shells, shells) << strength;
        EXPECT_DOUBLE_EQ(squat.tie_spacing_mm, spacing) << strength;
        const StrengthStep slender = strength_step(strength, kSlender);
        EXPECT_EQ(slender.shells, slender_shells) << strength;
        EXPECT_DOUBLE_EQ(slender.tie_spacing_mm, 0.0) << strength;
    }
    Settings s;
    s.shells = 2;  // from a profile, say
    apply_strength(s, 2.7, false, false);
    EXPECT_EQ(s.shells, 2);
    EXPECT_DOUBLE_EQ(s.tie_spacing, 0.0);
}

TEST(Strength, OptionsTypedWin) {
    Settings s;
    s.strength = 0.75;
    s.shells = 1;
    s.tie_spacing = 9;
    apply_strength(s, 2.7, true, true);
    EXPECT_EQ(s.shells, 1);
    EXPECT_DOUBLE_EQ(s.tie_spacing, 9.0);
    apply_strength(s, 2.7, false, true);
    EXPECT_EQ(s.shells, 2);
    EXPECT_DOUBLE_EQ(s.tie_spacing, 9.0);
}

// carve slice fandisk at `scale` (a quarter of its size by default) with ARGS: its stats.
nlohmann::json slice_stats(const std::string& args, const std::string& scale = "0.25") {
    static int n = 0;
    const std::string stem = (test::scratch() / ("s" + std::to_string(++n))).string();
    const test::CarveRun r =
        test::run_carve("slice " + test::repo_model("fandisk.stl") + " --scale " + scale +
                        " -q -o " + stem + ".gcode --stats " + stem + ".json " + args);
    EXPECT_EQ(r.status, 0) << args << "\n" << r.err;
    return nlohmann::json::parse(test::read(stem + ".json"), nullptr, false);
}

TEST(Strength, EndToEndThePresetResolvesAndTypedOptionsWin) {
    const nlohmann::json strong = slice_stats("--preset strong");  // fandisk: squat
    ASSERT_TRUE(strong.contains("settings"));
    EXPECT_EQ(strong["settings"]["shells"], 2);
    EXPECT_EQ(strong["settings"]["ties_mm"], 5.5);
    EXPECT_EQ(strong["settings"]["carving_scheme"], "whole");
    EXPECT_EQ(strong["settings"]["strong"], 1.0);
    const nlohmann::json typed = slice_stats("--preset strong --shells 1 --ties 0");
    ASSERT_TRUE(typed.contains("settings"));
    EXPECT_EQ(typed["settings"]["shells"], 1);
    EXPECT_EQ(typed["settings"]["ties_mm"], 0.0);
}

TEST(Strength, StepsAreMonotoneInMaterial) {
    double last = -1;
    for (const char* step : {"0", "0.25", "0.5", "0.75", "1"}) {
        // At half size: at a quarter the interior is too small for ties 22 and 11 mm apart to
        // differ.
        const nlohmann::json stats = slice_stats(std::string("--strong ") + step, "0.5");
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

// With --cut every plate is its own G-code: each plate's stats hold what carve check --strength
// says of that plate's file.
TEST(Strength, EveryPlateOfACutHoldsTheStrengthOfItsOwnGcode) {
    const std::string stem = (test::scratch() / "cut").string();
    // A 40 x 40 mm bed holds one of the two 18.4 x 9.6 mm pieces with its skirt: two plates.
    const test::CarveRun r = test::run_carve(
        "slice " + test::repo_model("fandisk.stl") + " --scale 0.25 -q --cut 10 --bed 40x40" +
        " -o " + stem + ".gcode --stats " + stem + ".json --stats-strength");
    ASSERT_EQ(r.status, 0) << r.err;
    const nlohmann::json stats = nlohmann::json::parse(test::read(stem + ".json"), nullptr, false);
    ASSERT_TRUE(stats.contains("plates"));
    ASSERT_EQ(stats["plates"].size(), 2u);
    for (const nlohmann::json& plate : stats["plates"]) {
        ASSERT_TRUE(plate.contains("strength")) << plate["plate"];
        const test::CarveRun c =
            test::run_carve("check " + plate["gcode"].get<std::string>() + " --strength --json");
        ASSERT_EQ(c.status, 0) << c.err;
        const nlohmann::json check = nlohmann::json::parse(c.out, nullptr, false)["strength"];
        for (const char* key :
             {"grams", "weakest_section_mm4", "compression_n_per_mm", "shear_n_per_mm"})
            EXPECT_NEAR(plate["strength"][key].get<double>(), check[key].get<double>(),
                        1e-9 * std::abs(check[key].get<double>()))
                << key << " of plate " << plate["plate"];
    }
}

// --ties are their own feature: the stats count them as ties_mm3, and the cavity walls are
// what they are without ties.
TEST(Strength, TiesAreCountedAsTiesNotAsCavityWalls) {
    const nlohmann::json plain = slice_stats("", "0.5");
    const nlohmann::json tied = slice_stats("--ties 5", "0.5");
    ASSERT_TRUE(tied.contains("material_by_feature"));
    const nlohmann::json& m = tied["material_by_feature"];
    ASSERT_TRUE(m.contains("ties_mm3"));
    EXPECT_GT(m["ties_mm3"].get<double>(), 10);
    EXPECT_EQ(plain["material_by_feature"]["ties_mm3"].get<double>(), 0.0);
    EXPECT_NEAR(m["cavity_walls_mm3"].get<double>(),
                plain["material_by_feature"]["cavity_walls_mm3"].get<double>(), 0.01);
}

}  // namespace
}  // namespace carve

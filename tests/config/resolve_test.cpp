// The settings precedence a library user gets from config/resolve.hpp, the same as carve slice's:
// defaults < printer < profile < preset < options, the later of two options winning, --strong
// asking for the model only when it is on and leaving typed shells and ties alone, profile
// choices refused without --load and an option of the other carving scheme refused wherever
// --carving comes.
#include "config/resolve.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "base/error.hpp"
#include "support/scratch.hpp"

namespace carve {
namespace {

const SettingSpec& row(const std::string& option) {
    for (const SettingSpec& spec : setting_table())
        if (option == spec.option) return spec;
    throw std::logic_error("no option --" + option);
}

double no_model() {
    ADD_FAILURE() << "the model was read though --strong is off";
    return 0;
}

TEST(Resolve, EachLevelWinsOverTheOneBeforeAndTheLastOptionOverTheFirst) {
    test::ScratchDir dir("carve-resolve-test-");
    const std::string ini = (dir.path() / "p.ini").string();
    std::ofstream(ini) << "bed_temperature = 70\ntemperature = 205\nlayer_height = 0.25\n";
    GivenSettings given;
    given.printer = "mk3s";
    given.profile_path = ini;
    given.preset = "3c1s";
    given.options = {
        {&row("temperature"), "210"}, {&row("covers"), "4"}, {&row("temperature"), "220"}};
    const Settings s = resolve_settings(given, no_model).settings;
    EXPECT_EQ(s.printer_name, "Prusa i3 MK3S-like");  // the printer's, untouched after it
    EXPECT_DOUBLE_EQ(s.travel_acceleration, 1250);
    EXPECT_EQ(s.bed_temperature, 70);  // the profile's over the printer's
    EXPECT_DOUBLE_EQ(s.layer_height, 0.25);
    EXPECT_EQ(s.shells, 1);                // the preset's
    EXPECT_EQ(s.covers, 4);                // the option's over the preset's
    EXPECT_EQ(s.nozzle_temperature, 220);  // the last option's
    // Nothing given: carve's defaults.
    const Settings d = resolve_settings({}, no_model).settings;
    EXPECT_EQ(d.covers, Settings{}.covers);
    EXPECT_DOUBLE_EQ(d.layer_height, Settings{}.layer_height);
}

TEST(Resolve, StrongReadsTheModelOnceAndLeavesTypedShellsAlone) {
    int asked = 0;
    const auto slender = [&asked] { return ++asked, 8.9; };  // the man's
    GivenSettings strong;
    strong.preset = "strong";
    Settings s = resolve_settings(strong, slender).settings;
    EXPECT_EQ(asked, 1);
    EXPECT_EQ(s.shells, 4);
    EXPECT_DOUBLE_EQ(s.tie_spacing, 0.0);
    strong.options = {{&row("shells"), "1"}};
    s = resolve_settings(strong, [] { return 2.7; }).settings;  // the fandisk's: ties
    EXPECT_EQ(s.shells, 1);
    EXPECT_DOUBLE_EQ(s.tie_spacing, 5.5);
}

TEST(Resolve, ProfileChoicesNeedAProfile) {
    GivenSettings given;
    given.profile.profile_shells = true;
    EXPECT_THROW(resolve_settings(given, no_model), UsageError);
    GivenSettings unknown;
    unknown.printer = "";  // given empty is not generic
    EXPECT_THROW(resolve_settings(unknown, no_model), InputError);
}

TEST(Resolve, AnOptionOfTheOtherSchemeIsRefusedWhereverCarvingComes) {
    GivenSettings given;
    given.options = {{&row("tear-limit"), "0.1"}};
    EXPECT_THROW(resolve_settings(given, no_model), UsageError);
    given.options.push_back({&row("carving"), "report"});
    EXPECT_DOUBLE_EQ(resolve_settings(given, no_model).settings.tear_limit, 0.1);
}

}  // namespace
}  // namespace carve

// PrusaSlicer config bundles: selection of the printer, filament and print presets by name or by
// [presets], `inherits` resolved recursively (cycles and missing parents refused naming the
// section), abstract sections never validated on their own, Debian's vendor bundle, extrusion
// widths, per-layer G-code, and the notes of what the profile sets that carve does not apply.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "base/error.hpp"
#include "config/profiles.hpp"
#include "config/settings.hpp"
#include "gcode/placeholders.hpp"
#include "support/carve_run.hpp"
#include "support/models.hpp"
#include "support/regex.hpp"

namespace fs = std::filesystem;
using namespace carve;
using namespace carve::test;

namespace {

const std::string kBundle = std::string(CARVE_SOURCE_DIR) + "/tests/data/two_printers_bundle.ini";
const std::string kVendor = "/usr/share/PrusaSlicer/profiles/PrusaResearch.ini";

std::string write_ini(const std::string& name, const std::string& text) {
    const fs::path p = scratch() / name;
    std::ofstream(p) << text;
    return p.string();
}

Settings load(const std::string& path, ProfileOptions o = {},
              std::vector<std::string>* notes = nullptr) {
    Settings s;
    std::vector<std::string> n = load_prusa_profile(path, s, o);
    if (notes) *notes = n;
    return s;
}

std::string load_error(const std::string& path, ProfileOptions o = {}) {
    try {
        load(path, o);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

ProfileOptions choose(std::string printer, std::string filament = "", std::string print = "") {
    ProfileOptions o;
    o.choice = {std::move(printer), std::move(filament), std::move(print)};
    return o;
}

bool has(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

}  // namespace

TEST(Bundle, ThePresetsSectionSelectsThePrinter) {
    const Settings s = load(kBundle);
    EXPECT_DOUBLE_EQ(s.bed_x, 250);
    EXPECT_DOUBLE_EQ(s.bed_y, 210);
    EXPECT_TRUE(has(s.start_gcode, "MK3S start")) << s.start_gcode;
    EXPECT_FALSE(has(s.start_gcode, "MINI"));
    EXPECT_DOUBLE_EQ(s.retract_length, 0.8);  // the MINI's 3.2 is not read
    EXPECT_FALSE(s.firmware_retraction);
    EXPECT_EQ(s.profile_values.at("printer_settings_id"), "Test MK3S");
    EXPECT_EQ(s.profile_values.at("filament_settings_id"), "\"Test PLA\"");

    const Settings mini = load(kBundle, choose("Test MINI"));
    EXPECT_DOUBLE_EQ(mini.bed_x, 180);
    EXPECT_TRUE(has(mini.start_gcode, "MINI start"));
    EXPECT_DOUBLE_EQ(mini.retract_length, 3.2);
    EXPECT_TRUE(mini.firmware_retraction);
}

TEST(Bundle, TheSelectedPrinterDrivesTheGcode) {
    const std::string model = repo_model("fandisk.stl");
    for (const auto& [args, start, other, bed] :
         {std::tuple{std::string(""), "; MK3S start", "; MINI start",
                     "; bed_shape = 0x0,250x0,250x210,0x210"},
          std::tuple{std::string("--printer-profile 'Test MINI'"), "; MINI start", "; MK3S start",
                     "; bed_shape = 0x0,180x0,180x180,0x180"}}) {
        const fs::path out = scratch() / "bundle.gcode";
        const CarveRun r =
            run_carve("slice " + model + " -o " + out.string() +
                      " --scale 0.25 --cavities 1 -q --load " + kBundle + " " + args);
        ASSERT_EQ(r.status, 0) << r.err;
        const std::string g = read(out);
        EXPECT_TRUE(has(g, std::string("G28 ") + start + "\n")) << args;
        EXPECT_FALSE(has(g, std::string("G28 ") + other + "\n")) << args;
        EXPECT_TRUE(has(g, bed)) << args;
    }
}

TEST(Bundle, InheritsIsResolvedRecursivelyAndInOrder) {
    // Test PLA <- *PLA* <- *common*: each level's keys over its parent's.
    const Settings s = load(kBundle);
    EXPECT_EQ(s.nozzle_temperature, 210);              // *PLA* over *common*'s 200
    EXPECT_EQ(s.first_layer_nozzle_temperature, 212);  // *PLA*
    EXPECT_EQ(s.bed_temperature, 65);                  // *common*, two levels up
    EXPECT_DOUBLE_EQ(s.filament_density, 1.24);        // its own, over *common*'s 0
    // inherits = *PLA*; *fast*: the later parent wins.
    const Settings fast = load(kBundle, choose("", "Test PLA fast"));
    EXPECT_EQ(fast.nozzle_temperature, 230);
    EXPECT_EQ(fast.first_layer_nozzle_temperature, 212);
    // The print preset's parent: perimeters and widths.
    EXPECT_DOUBLE_EQ(s.layer_height, 0.2);
    EXPECT_DOUBLE_EQ(s.travel_speed, 170);
    EXPECT_DOUBLE_EQ(s.extrusion_width, 0.5);  // perimeter_extrusion_width over extrusion_width
    EXPECT_TRUE(s.wipe);                       // from *common printer*
}

TEST(Bundle, CyclesAndMissingParentsNameTheSection) {
    const std::string cycle =
        write_ini("cycle.ini",
                  "[print:a]\ninherits = b\n[print:b]\ninherits = c\n[print:c]\ninherits = a\n"
                  "[presets]\nprint = a\n");
    const std::string e = load_error(cycle);
    EXPECT_TRUE(has(e, "inherits itself")) << e;
    EXPECT_TRUE(has(e, "[print:a] -> [print:b] -> [print:c] -> [print:a]")) << e;
    const std::string self = write_ini("self.ini", "[printer:p]\ninherits = p\n");
    EXPECT_TRUE(has(load_error(self), "[printer:p]")) << load_error(self);

    const std::string missing =
        write_ini("missing.ini", "[filament:x]\ninherits = *gone*\ntemperature = 200\n");
    const std::string m = load_error(missing);
    EXPECT_TRUE(has(m, "[filament:x] inherits '*gone*'")) << m;
    EXPECT_TRUE(has(m, "missing.ini:2:")) << m;
}

TEST(Bundle, AbstractSectionsAreNotValidatedOnTheirOwn) {
    // *common* holds filament_density = 0, which Test PLA overrides: no error.
    EXPECT_EQ(load_error(kBundle), "");
    // A preset that inherits the bad value is refused, naming where it was written and which
    // preset took it.
    const std::string bad = write_ini(
        "abstract.ini",
        "[filament:*common*]\nfilament_density = 0\n[filament:Bad]\ninherits = *common*\n");
    const std::string e = load_error(bad);
    EXPECT_TRUE(has(e,
                    "abstract.ini:2: [filament:*common*] (inherited by [filament:Bad]) "
                    "profile key 'filament_density'"))
        << e;
    // An abstract section cannot be selected.
    const std::string a = load_error(kBundle, choose("", "*PLA*"));
    EXPECT_TRUE(has(a, "[filament:*PLA*] is abstract")) << a;
}

TEST(Bundle, WithoutASelectionTheErrorListsTheNames) {
    const std::string two =
        write_ini("two.ini",
                  "[printer:Alpha]\nbed_shape = 0x0,100x0,100x100,0x100\n[printer:*base*]\n"
                  "[printer:Beta]\nbed_shape = 0x0,200x0,200x200,0x200\n");
    const std::string e = load_error(two);
    EXPECT_TRUE(has(e, "--printer-profile NAME from: Alpha, Beta")) << e;
    EXPECT_FALSE(has(e, "*base*")) << e;
    const std::string unknown = load_error(two, choose("Gamma"));
    EXPECT_TRUE(has(unknown, "no [printer:Gamma]")) << unknown;
    EXPECT_TRUE(has(unknown, "Alpha, Beta")) << unknown;
    EXPECT_DOUBLE_EQ(load(two, choose("Beta")).bed_x, 200);
    // The command line says so too, with exit status 1 (bad input).
    const CarveRun r = run_carve("slice " + repo_model("fandisk.stl") + " -o " +
                                 (scratch() / "none.gcode").string() + " --load " + two);
    EXPECT_EQ(r.status, 1);
    EXPECT_TRUE(has(r.err, "Alpha, Beta")) << r.err;
}

TEST(Bundle, PrusaResearchVendorBundleMk3sWithPrusamentPla) {
    if (!fs::exists(kVendor)) GTEST_SKIP() << kVendor << " not installed (prusa-slicer package)";
    std::vector<std::string> notes;
    const Settings s =
        load(kVendor, choose("Original Prusa i3 MK3S & MK3S+", "Prusament PLA"), &notes);
    EXPECT_DOUBLE_EQ(s.bed_x, 250);
    EXPECT_DOUBLE_EQ(s.bed_y, 210);
    EXPECT_DOUBLE_EQ(s.nozzle, 0.4);
    EXPECT_EQ(s.nozzle_temperature, 215);  // Prusament PLA's own temperature
    EXPECT_EQ(s.first_layer_nozzle_temperature, 215);
    EXPECT_EQ(s.bed_temperature, 60);
    EXPECT_DOUBLE_EQ(s.filament_density, 1.24);
    EXPECT_EQ(s.flavor, GcodeFlavor::Marlin);
    EXPECT_DOUBLE_EQ(s.extrusion_width, 0.45);
    EXPECT_EQ(s.profile_values.at("printer_model"), "MK3S");
    const ExpandedGcode g = expand_custom_gcode(s.start_gcode, s);
    EXPECT_TRUE(has(g.text, "M862.3 P \"MK3S\" ; printer model check")) << g.text;
    EXPECT_TRUE(has(g.text, "M862.1 P0.4")) << g.text;
    EXPECT_TRUE(has(g.text, "M109 S215")) << g.text;
    EXPECT_TRUE(has(g.text, "M190 S60")) << g.text;
    const ExpandedGcode f = expand_custom_gcode(s.start_filament_gcode, s);
    EXPECT_TRUE(has(f.text, "M900 K")) << f.text;  // linear advance
    EXPECT_TRUE(has(s.before_layer_gcode, "G92 E0")) << s.before_layer_gcode;
    // Defaults reach the printer's default_print_profile.
    EXPECT_TRUE(has(s.profile_values.at("print_settings_id"), "@MK3"));
    ASSERT_EQ(notes.size(), 2u);
    // Cooling is read (src/gcode/cooling), so it is no longer named; infill settings are.
    EXPECT_TRUE(has(notes[1], "fill_density")) << notes[1];
    EXPECT_FALSE(has(notes[1], "max_fan_speed")) << notes[1];
}

TEST(Profile, ExtrusionWidthPercentIsOfTheNozzle) {
    const Settings s =
        load(write_ini("pct.ini", "nozzle_diameter = 0.6\nextrusion_width = 112.5%\n"));
    EXPECT_NEAR(s.extrusion_width, 0.675, 1e-12);
    EXPECT_EQ(s.line_width(), to_units(0.675));
    const Settings p =
        load(write_ini("per.ini",
                       "nozzle_diameter = 0.4\nextrusion_width = 0.45\nperimeter_extrusion_width = "
                       "110%\nexternal_perimeter_extrusion_width = 0.44\n"));
    EXPECT_NEAR(p.extrusion_width, 0.44, 1e-12);  // perimeters first: 110 % of 0.4
    // 0 means automatic in PrusaSlicer: carve keeps the nozzle's width.
    const Settings z = load(write_ini("zero.ini", "extrusion_width = 0\n"));
    EXPECT_DOUBLE_EQ(z.width_mm(), 0.4);
    const std::string e = load_error(write_ini("badw.ini", "extrusion_width = 900%\n"));
    EXPECT_TRUE(has(e, "profile key 'extrusion_width'")) << e;
}

TEST(Profile, LayerGcodeIsExpandedForEveryLayer) {
    const std::string ini = write_ini(
        "layers.ini",
        "use_relative_e_distances = 0\n"
        "before_layer_gcode = ;BEFORE [layer_num]\\nG92 E0\n"
        "layer_gcode = ;AFTER [layer_num] {layer_z}\n"
        "start_filament_gcode = \"M900 K0.05 ; LA\"\nend_filament_gcode = \"; filament end\"\n");
    const fs::path out = scratch() / "layers.gcode";
    const CarveRun r = run_carve("slice " + repo_model("fandisk.stl") + " -o " + out.string() +
                                 " --scale 0.25 --cavities 1 -q --load " + ini);
    ASSERT_EQ(r.status, 0) << r.err;
    std::ifstream in(out);
    std::string line, prev_layer;
    int layers = 0, before = 0, after = 0, start_fil = -1, g21 = -1, n = 0;
    double last_e_after_reset = -1;
    bool reset = false;
    const carve::test::Regex e_word(R"( E([-0-9.]+))");
    std::vector<std::string> m;
    while (std::getline(in, line)) {
        ++n;
        if (line == "M900 K0.05 ; LA") start_fil = n;
        if (line == "G21 ; millimetres") g21 = n;
        if (line.rfind(";LAYER:", 0) == 0) prev_layer = line.substr(7), ++layers;
        if (line.rfind(";BEFORE ", 0) == 0) {
            EXPECT_EQ(line, ";BEFORE " + std::to_string(layers)) << "before layer " << layers;
            ++before;
            reset = true;
        }
        if (line.rfind(";AFTER ", 0) == 0) {
            std::istringstream ss(line.substr(7));
            std::string num;
            double z = 0;
            ss >> num >> z;
            EXPECT_EQ(num, prev_layer);
            EXPECT_NEAR(z, 0.2 * (std::stoi(prev_layer) + 1), 1e-6) << line;
            ++after;
        }
        // Absolute E restarts from 0 after the G92 E0: the first extrusion of the layer is small.
        if (reset && line.rfind("G1 X", 0) == 0 && e_word.search(line, &m)) {
            last_e_after_reset = std::stod(m[1]);
            EXPECT_LT(last_e_after_reset, 5.0) << line;
            reset = false;
        }
    }
    EXPECT_GT(layers, 10);
    EXPECT_EQ(before, layers);
    EXPECT_EQ(after, layers);
    EXPECT_GT(start_fil, 0);
    EXPECT_LT(start_fil, g21);  // after the start G-code, before carve's own setup
    EXPECT_TRUE(has(read(out), "; filament end\n"));
    // carve check reads the same material from it as carve wrote.
    const CarveRun c = run_carve("check " + out.string() + " --json");
    EXPECT_EQ(c.status, 0) << c.err;
}

TEST(Profile, OneNoteNamesTheIgnoredKeysAndOneTheCarvingStructure) {
    std::vector<std::string> notes;
    Settings s = load(kBundle, {}, &notes);
    ASSERT_EQ(notes.size(), 2u);
    // Carve's own covers and shells hold; the note lists what the profile asked for.
    EXPECT_EQ(s.covers, 2);
    EXPECT_EQ(s.shells, 0);
    EXPECT_TRUE(has(notes[0], "top_solid_layers = 6, bottom_solid_layers = 4, perimeters = 2"))
        << notes[0];
    EXPECT_TRUE(has(notes[0], "--profile-shells"));
    // By name, not a count; keys set to zero and keys that do not change the print are not.
    EXPECT_TRUE(has(notes[1], "keys that change the print and carve ignores: fill_density"))
        << notes[1];
    EXPECT_FALSE(has(notes[1], "filament_max_volumetric_speed")) << notes[1];  // not selected
    EXPECT_FALSE(carve::test::Regex("ignored [0-9]+ keys").search(notes[1])) << notes[1];

    ProfileOptions shells;
    shells.profile_shells = true;
    notes.clear();
    s = load(kBundle, shells, &notes);
    EXPECT_EQ(s.covers, 6);
    EXPECT_EQ(s.shells, 1);
    ASSERT_EQ(notes.size(), 1u);

    notes.clear();
    load(write_ini("quiet.ini",
                   "temperature = 230\nwipe_tower = 1\nraft_layers = 0\n"
                   "some_future_key = x\nexternal_perimeter_speed = 50%\n"),
         {}, &notes);
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_TRUE(has(notes[0], "carve ignores: external_perimeter_speed (50%)")) << notes[0];
    EXPECT_FALSE(has(notes[0], "raft_layers"));
}

TEST(Bundle, DeepAndDiamondInheritanceStaysBounded) {
    // 40 levels, each inheriting the next one twice over (a diamond): resolved once per section.
    std::string diamond = "[print:p0]\nlayer_height = 0.1\n";
    for (int i = 1; i <= 40; ++i)
        diamond += "[print:p" + std::to_string(i) + "]\ninherits = p" + std::to_string(i - 1) +
                   "; p" + std::to_string(i - 1) + "\n";
    diamond += "[presets]\nprint = p40\n";
    EXPECT_DOUBLE_EQ(load(write_ini("diamond.ini", diamond)).layer_height, 0.1);
    // Deeper than 64 levels: refused with the section named, not a stack overflow.
    std::string deep = "[print:q0]\n";
    for (int i = 1; i <= 100; ++i)
        deep += "[print:q" + std::to_string(i) + "]\ninherits = q" + std::to_string(i - 1) + "\n";
    deep += "[presets]\nprint = q100\n";
    const std::string e = load_error(write_ini("deep.ini", deep));
    EXPECT_TRUE(has(e, "levels deep")) << e;
    EXPECT_TRUE(has(e, "[print:q")) << e;
}

// Hostile input (issue #22): each class of input that once destroyed a file, crashed, hung or
// wrote dangerous G-code, run through the carve executable or the stage it reached. Every case
// must end within seconds with a clear one-line message and the documented exit status, and
// leave no output or temporary behind. No timings are asserted.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zip.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <thread>

#include "base/atomic_file.hpp"
#include "base/errors.hpp"
#include "base/linear_regex.hpp"
#include "base/numbers.hpp"
#include "base/output_paths.hpp"
#include "config/profiles.hpp"
#include "config/setting_table.hpp"
#include "gcode/placeholders.hpp"
#include "mesh/mesh.hpp"
#include "support/carve_run.hpp"
#include "support/models.hpp"
#include "support/regex.hpp"
#include "support/stl_boxes.hpp"

namespace fs = std::filesystem;
using namespace carve;
using namespace carve::test;

namespace {

// A small closed model of the test's own (a 20 x 20 x 6 mm box as ASCII STL), so that the
// suite needs nothing outside the repository.
std::string small_model() {
    const fs::path p = scratch() / "hostile_box.stl";
    if (!fs::exists(p)) {
        const double v[8][3] = {{0, 0, 0}, {20, 0, 0}, {20, 20, 0}, {0, 20, 0},
                                {0, 0, 6}, {20, 0, 6}, {20, 20, 6}, {0, 20, 6}};
        const int f[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                              {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
        std::ofstream out(p);
        out << "solid box\n";
        for (const auto& t : f) {
            out << "facet normal 0 0 0\nouter loop\n";
            for (int k : t) out << "vertex " << v[k][0] << ' ' << v[k][1] << ' ' << v[k][2] << "\n";
            out << "endloop\nendfacet\n";
        }
        out << "endsolid box\n";
    }
    return p.string();
}
const std::string kSmall = small_model();

// A fresh folder of this test's own inside the scratch folder.
fs::path folder(const std::string& name) {
    const fs::path d = scratch() / name;
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

void write(const fs::path& p, const std::string& text) {
    std::ofstream out(p, std::ios::binary);
    out << text;
}

// Every entry of `dir` except the ones named in `keep`.
std::vector<std::string> extra_files(const fs::path& dir, const std::vector<std::string>& keep) {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir)) {
        const std::string n = e.path().filename().string();
        if (std::find(keep.begin(), keep.end(), n) == keep.end()) out.push_back(n);
    }
    return out;
}

// Status `status`, exactly one line on stderr starting "carve: " and containing `needle`.
void expect_one_line(const CarveRun& r, int status, const std::string& needle,
                     const std::string& what) {
    EXPECT_EQ(r.status, status) << what << ": " << r.err;
    EXPECT_EQ(lines(r.err), 1) << what << ": " << r.err;
    EXPECT_EQ(r.err.rfind("carve: ", 0), 0u) << what << ": " << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << what << ": " << r.err;
    EXPECT_LT(r.err.size(), 400u) << what << ": " << r.err;
}

}  // namespace

// --- data loss and devices

TEST(HostileOutputs, AnOutputThatIsTheInputOrAnotherOutputIsRefused) {
    const fs::path d = folder("same");
    fs::create_directories(d / "sub");
    fs::copy_file(kSmall, d / "M.stl");
    const std::string original = read(d / "M.stl");
    const std::string m = (d / "M.stl").string();
    const std::string other = (d / "sub" / ".." / "." / "M.stl").string();
    const std::string g = (d / "a.gcode").string(), j = (d / "a.json").string();
    for (const std::string& args : std::initializer_list<std::string>{
             "-o " + m, "-o " + other, "-o " + g + " --stats " + m, "-o " + g + " --report " + m,
             "-o " + g + " --stats " + g, "-o " + g + " --report " + j + " --stats " + j,
             "-o " + g + " --report " + (d / "sub" / ".." / "a.gcode").string()}) {
        const CarveRun r = run_carve("slice " + m + " -q --cavities 1 " + args);
        expect_one_line(r, kExitOutput, "same file", args);
        EXPECT_EQ(read(d / "M.stl"), original) << args;
        EXPECT_EQ(extra_files(d, {"M.stl", "sub"}), std::vector<std::string>{}) << args;
    }
    // The profile is an input too.
    write(d / "p.ini", "layer_height = 0.2\n");
    const CarveRun r = run_carve("slice " + m + " -q --load " + (d / "p.ini").string() + " -o " +
                                 g + " --stats " + (d / "p.ini").string());
    expect_one_line(r, kExitOutput, "same file", "--stats = --load");
    EXPECT_EQ(read(d / "p.ini"), "layer_height = 0.2\n");
}

TEST(HostileOutputs, DevicesAndSpecialFilesAreNeverWritten) {
    for (const std::string& dev :
         std::initializer_list<std::string>{"/dev/null", "/dev/full", "/dev/stdout"}) {
        for (const std::string& opt :
             std::initializer_list<std::string>{"-o", "--stats", "--report"}) {
            const std::string args =
                opt == "-o" ? "-o " + dev
                            : "-o " + (scratch() / "dev.gcode").string() + " " + opt + " " + dev;
            const CarveRun r = run_carve("slice " + kSmall + " -q --cavities 1 " + args);
            expect_one_line(r, kExitOutput, dev, args);
            EXPECT_FALSE(fs::exists(scratch() / "dev.gcode")) << args;
        }
    }
    struct stat st {};
    ASSERT_EQ(stat("/dev/null", &st), 0);
    EXPECT_TRUE(S_ISCHR(st.st_mode));  // still the device, whoever ran the test
    // A FIFO is a special file too (it would block a writer forever).
    const fs::path fifo = folder("fifo") / "out.gcode";
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    const CarveRun r = run_carve("slice " + kSmall + " -q -o " + fifo.string());
    expect_one_line(r, kExitOutput, "not a regular file", "fifo");
}

TEST(HostileOutputs, AnOutputNameNearTheFileSystemLimitIsWritten) {
    const fs::path d = folder("long");
    const std::string name = std::string(245, 'g') + ".gcode";  // 251 of NAME_MAX's 255
    const CarveRun r = run_carve("slice " + kSmall + " -q --cavities 1 -o " + (d / name).string());
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(extra_files(d, {name}), std::vector<std::string>{});
}

TEST(HostileOutputs, AFailedWriteOfStandardOutputIsAnError) {
    const std::string cmd = std::string(CARVE_BINARY) + " info " + kSmall + " --json >/dev/full";
    const int raw = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(raw));
    EXPECT_EQ(WEXITSTATUS(raw), kExitOutput);
    const std::string help = std::string(CARVE_BINARY) + " --help >/dev/full 2>/dev/null";
    const int h = std::system(help.c_str());
    EXPECT_EQ(WEXITSTATUS(h), kExitOutput);
}

// --- numbers: NaN, infinity, huge, hexadecimal, text

TEST(HostileNumbers, OptionsThatAreNotFiniteDecimalsInRangeAreRefused) {
    const fs::path g = scratch() / "num.gcode";
    for (const std::string& opt : std::initializer_list<std::string>{"--filament-diameter nan",
                                                                     "--travel-speed nan",
                                                                     "--retract-length nan",
                                                                     "--nozzle nan",
                                                                     "--max-overhang nan",
                                                                     "--layer-height inf",
                                                                     "--layer-height -inf",
                                                                     "--nozzle 1e20",
                                                                     "--layer-height 0.001",
                                                                     "--nozzle 0.001",
                                                                     "--temperature 0x10",
                                                                     "--bed 0x100x0x100",
                                                                     "--bed nanx100",
                                                                     "--layer-height abc",
                                                                     "--max-vertices-per-layer -1",
                                                                     "--threads 1.5",
                                                                     "--covers 1e9",
                                                                     "--scale 0",
                                                                     "--svg-every nan",
                                                                     "--raster-pixel 0x1",
                                                                     "--cavities 0x3",
                                                                     "--timeout nan",
                                                                     "--bed-temperature 99999"}) {
        const CarveRun r = run_carve("slice " + kSmall + " -q -o " + g.string() + " " + opt);
        const std::string name = opt.substr(0, opt.find(' '));
        expect_one_line(r, kExitBadInput, name, opt);
        EXPECT_FALSE(fs::exists(g)) << opt;
    }
    for (const std::string& opt : std::initializer_list<std::string>{
             "--support-radius nan", "--far-radius inf", "--filament-diameter 0x2"}) {
        const CarveRun r = run_carve("check " + kSmall + " " + opt);
        expect_one_line(r, kExitBadInput, opt.substr(0, opt.find(' ')), opt);
    }
}

TEST(HostileNumbers, UnknownOptionsAreUsageErrors) {
    const CarveRun r = run_carve("slice " + kSmall + " -o x.gcode --frobnicate");
    expect_one_line(r, kExitUsage, "frobnicate", "--frobnicate");
    const CarveRun none = run_carve("");
    EXPECT_EQ(none.status, kExitUsage);
    const CarveRun missing = run_carve("slice " + kSmall);
    EXPECT_EQ(missing.status, kExitUsage) << missing.err;
}

TEST(HostileNumbers, ProfileValuesAreBoundedAndNamed) {
    const fs::path d = folder("profiles");
    const fs::path g = d / "out.gcode";
    for (const std::string& line : std::initializer_list<std::string>{
             "nozzle_diameter = 1e20", "nozzle_diameter = nan", "temperature = 99999",
             "temperature = -40", "first_layer_bed_temperature = -2147483648",
             "bed_temperature = 1e300", "travel_speed = nan", "travel_speed = 0",
             "retract_length = nan", "retract_length = -1", "layer_height = 0.001",
             "filament_diameter = inf", "retract_speed = 0x20", "bed_shape = 0x0,0x1e9,1e9x1e9",
             "bed_shape = 0x0,0x0x1,100x100", "retract_before_travel = nan",
             "machine_max_acceleration_extruding = -5", "first_layer_speed = nan"}) {
        write(d / "p.ini", line + "\n");
        const CarveRun r = run_carve("slice " + kSmall + " -q -o " + g.string() + " --load " +
                                     (d / "p.ini").string());
        const std::string key = line.substr(0, line.find(' '));
        EXPECT_EQ(r.status, kExitBadInput) << line << ": " << r.err;
        EXPECT_NE(r.err.find(key == "bed_shape" ? "bed" : key), std::string::npos)
            << line << ": " << r.err;
        EXPECT_EQ(lines(r.err), 1) << line << ": " << r.err;
        const size_t named = r.err.find("profile key");
        EXPECT_TRUE(named == std::string::npos ||
                    r.err.find("profile key", named + 1) == std::string::npos)
            << "the key is named once: " << r.err;
        EXPECT_FALSE(fs::exists(g)) << line;
    }
}

TEST(HostileNumbers, EveryTableEntryStatesARangeThatHoldsItsDefault) {
    const Settings defaults;
    for (const SettingSpec& spec : setting_table()) {
        const std::string help = spec.help;
        if (spec.text()) {
            // Its own parser takes the default back, and the help states it (or "none").
            Settings again;
            EXPECT_NO_THROW(spec.set(again, spec.text_value(defaults), "test")) << spec.option;
            const std::string shown = spec.text_value(defaults);
            EXPECT_NE(help.find("[" + (shown.empty() ? std::string("none") : shown)),
                      std::string::npos)
                << spec.option << ": " << help;
            continue;
        }
        const double v = spec.get(defaults);
        EXPECT_TRUE(v >= spec.min && v <= spec.max) << spec.option << spec.ini_key;
        EXPECT_LT(spec.min, spec.max) << spec.option;
        // The help's [default] begins with the default itself (one declaration, one value); a
        // switch's help speaks of what giving it does ([off]: not given).
        if (!help.empty() && !spec.is_switch()) {
            EXPECT_NE(help.find("[" + plain_number(v)), std::string::npos)
                << spec.option << ": " << help;
        }
    }
    EXPECT_NO_THROW(validate_settings(defaults));
}

TEST(HostileNumbers, StrictDecimals) {
    EXPECT_EQ(parse_decimal("0.25"), 0.25);
    EXPECT_EQ(parse_decimal("+2"), 2.0);
    EXPECT_EQ(parse_decimal("-1e-3"), -0.001);
    for (const char* bad : {"", "nan", "NaN", "inf", "-inf", "infinity", "0x10", "1e400", "1,5",
                            " 1", "1 ", "1.5mm", "--1", "+"})
        EXPECT_FALSE(parse_decimal(bad).has_value()) << bad;
    EXPECT_EQ(range_problem("5", 0, 10, true, "C"), "");
    EXPECT_NE(range_problem("5.5", 0, 10, true, "C").find("whole"), std::string::npos);
    EXPECT_NE(range_problem("-1", 0, 1e9, true, "vertices").find("from 0 to 1000000000"),
              std::string::npos);
}

// --- heat-up

namespace {

// Index of the first line that extrudes (G1 with a positive E after the start), or npos.
// The wait lines are those before it.
bool waits_before_first_extrusion(const std::string& gcode, bool& nozzle, bool& bed) {
    nozzle = bed = false;
    std::istringstream in(gcode);
    std::string line;
    static const carve::test::Regex extrude(R"(^G1 X[-0-9.]+ Y[-0-9.]+ E[0-9.]+)");
    while (std::getline(in, line)) {
        const std::string code = line.substr(0, line.find(';'));
        if (extrude.search(code)) return true;
        if (code.rfind("M109 S", 0) == 0 && std::atof(code.c_str() + 6) > 0) nozzle = true;
        if (code.rfind("M190 S", 0) == 0 && std::atof(code.c_str() + 6) > 0) bed = true;
    }
    return false;
}

}  // namespace

TEST(HostileHeatUp, NoExtrusionBeforeAWaitForBothTemperatures) {
    const fs::path d = folder("heat");
    const fs::path g = d / "out.gcode";
    for (const std::string& start : std::initializer_list<std::string>{
             "{if 1 > 2}M190 S60\\nM109 S200{endif}\\nG28",  // heating only in a false branch
             "{if 1 > 2}M190 S60\\nM109 S200\\nG28",         // an unbalanced {if}
             "; M109 S200 and M190 S60 in a comment\\nG28",  // a comment heats nothing
             "M109 S0\\nM190 S0\\nG28",                      // nor a wait for 0
             "{if 1 < 2}M190 S[first_layer_bed_temperature]\\nM109 "
             "S[first_layer_temperature]{endif}",
             "M190 S{first_layer_bed_temperature[0]}\\nM109 S{first_layer_temperature[0]}\\nG28"}) {
        write(d / "p.ini", "start_gcode = " + start + "\n");
        const CarveRun r = run_carve("slice " + kSmall + " -q --cavities 1 -o " + g.string() +
                                     " --load " + (d / "p.ini").string());
        ASSERT_EQ(r.status, 0) << start << ": " << r.err;
        bool nozzle = false, bed = false;
        EXPECT_TRUE(waits_before_first_extrusion(read(g), nozzle, bed)) << start;
        EXPECT_TRUE(nozzle) << start;
        EXPECT_TRUE(bed) << start;
    }
    // When the expanded start G-code heats, carve adds no second wait of its own.
    write(d / "p.ini",
          "start_gcode = M190 S[first_layer_bed_temperature]\\nM109 S[first_layer_temperature]\n");
    ASSERT_EQ(run_carve("slice " + kSmall + " -q --cavities 1 -o " + g.string() + " --load " +
                        (d / "p.ini").string())
                  .status,
              0);
    const std::string text = read(g);
    EXPECT_EQ(text.find("; wait for nozzle"), std::string::npos);
    EXPECT_EQ(text.find("; wait for bed"), std::string::npos);
}

// --- the expression engine

TEST(HostilePlaceholders, DeepAndLongExpressionsAreReportedNotRecursedInto) {
    const Settings s;
    for (const std::string& expr : std::initializer_list<std::string>{
             std::string(200000, '(') + "1" + std::string(200000, ')'),
             std::string(200000, '-') + "1", std::string(100000, '!') + "1",
             "min(" + std::string(50000, '(') + "1", std::string(70000, '1')}) {
        const ExpandedGcode e = expand_custom_gcode("G1 X{" + expr + "}\nG28\n", s);
        EXPECT_FALSE(e.unresolved.empty());
        EXPECT_NE(e.text.find("G28"), std::string::npos);
        EXPECT_EQ(e.text.find("\nG1 X"), std::string::npos);  // the line became a comment
        for (const std::string& u : e.unresolved) EXPECT_LT(u.size(), 300u);
    }
    // A {if} whose condition is refused is false; its body does not reach the printer.
    const ExpandedGcode e =
        expand_custom_gcode("{if " + std::string(5000, '(') + "1}M109 S999{endif}\n", s);
    EXPECT_EQ(e.text.find("M109"), std::string::npos);
}

TEST(HostilePlaceholders, RegexConditionsRunInLinearTime) {
    Settings s;
    // PrusaSlicer's own condition on real, long printer notes.
    s.profile_values["printer_notes"] = std::string(100000, 'x') +
                                        " PRINTER_VENDOR_PRUSA3D PRINTER_MODEL_MK3S " +
                                        std::string(50000, 'y');
    ExpandedGcode e = expand_custom_gcode(
        "{if printer_notes=~/.*PRINTER_VENDOR_PRUSA3D.*/}M117 prusa{else}M117 other{endif}\n"
        "{if printer_notes=~/.*PRINTER_MODEL_MK(2.5|3).*/ and printer_notes!~/.*MINI.*/}"
        "M117 mk3{endif}\n",
        s);
    EXPECT_NE(e.text.find("M117 prusa"), std::string::npos) << e.text;
    EXPECT_NE(e.text.find("M117 mk3"), std::string::npos) << e.text;
    EXPECT_TRUE(e.unresolved.empty());
    // Patterns that make a backtracking matcher take exponential time, on 10^5 characters.
    s.profile_values["printer_notes"] = std::string(100000, 'a');
    for (const char* re : {"(a*)*b", "(a|aa)*c", "(a+)+$b", "((a*)*)*(b|c)", "(.*a){20}b"}) {
        e = expand_custom_gcode(std::string("{if printer_notes=~/") + re + "/}M117 yes{endif}\n",
                                s);
        EXPECT_EQ(e.text.find("M117 yes"), std::string::npos) << re;
    }
    // A 20,000-character class is refused with a reason, not a stack overflow; a 200,000 one
    // is over the length of a tag.
    e = expand_custom_gcode("{if printer_notes=~/[" + std::string(20000, 'a') + "]/}x{endif}\n", s);
    ASSERT_FALSE(e.unresolved.empty());
    EXPECT_NE(e.unresolved[0].find("regex"), std::string::npos) << e.unresolved[0];
    EXPECT_EQ(e.text.find('x'), std::string::npos);
    e = expand_custom_gcode("{if printer_notes=~/[" + std::string(200000, 'a') + "]/}x{endif}\n",
                            s);
    EXPECT_FALSE(e.unresolved.empty());
    EXPECT_EQ(e.text.find('x'), std::string::npos);
}

TEST(LinearRegex, AgreesWithStdRegexOnSmallRandomCases) {
    std::mt19937 rng(22);
    const std::string atoms[] = {"a", "b", ".", "[ab]", "[^a]", "(a|b)", "(ab|a)", "\\d", "x"};
    const std::string ops[] = {"", "", "*", "+", "?", "{2}", "{1,3}", "{2,}"};
    int compared = 0;
    for (int i = 0; i < 3000; ++i) {
        std::string pattern;
        const int n = 1 + static_cast<int>(rng() % 5);
        for (int k = 0; k < n; ++k) pattern += atoms[rng() % 9] + ops[rng() % 8];
        if (rng() % 4 == 0) pattern = "(" + pattern + ")|" + atoms[rng() % 9];
        std::string text;
        const int len = static_cast<int>(rng() % 7);
        for (int k = 0; k < len; ++k) text += "ab1x"[rng() % 4];
        const LinearRegex mine(pattern);
        const bool expected = carve::test::Regex(pattern).match(text);
        EXPECT_EQ(mine.full_match(text), expected) << "/" << pattern << "/ on '" << text << "'";
        ++compared;
    }
    EXPECT_EQ(compared, 3000);
    EXPECT_TRUE(LinearRegex("^a.c$").full_match("abc"));
    EXPECT_TRUE(LinearRegex("\\.\\*\\/").full_match(".*/"));
    for (const char* bad : {"(", "a)", "[a", "*a", "a{2,1}", "a{5000}", "(?=a)", "\\1"})
        EXPECT_THROW(LinearRegex{bad}, std::invalid_argument) << bad;
    EXPECT_THROW(LinearRegex(std::string(100, '(') + "a" + std::string(100, ')')),
                 std::invalid_argument);
}

// --- loaders: zip bombs, nesting, text STL variants

namespace {

// A 3MF whose model part is `model` (deflated by libzip).
void write_3mf(const fs::path& path, const std::string& model) {
    int err = 0;
    zip_t* z = zip_open(path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &err);
    ASSERT_NE(z, nullptr);
    // libzip keeps the buffer until zip_close: it lives in a static here.
    static std::string keep;
    keep = model;
    zip_source_t* src = zip_source_buffer(z, keep.data(), keep.size(), 0);
    ASSERT_GE(zip_file_add(z, "3D/3dmodel.model", src, ZIP_FL_OVERWRITE), 0);
    ASSERT_EQ(zip_close(z), 0);
}

const char* kTetra =
    "<vertices><vertex x=\"0\" y=\"0\" z=\"0\"/><vertex x=\"10\" y=\"0\" z=\"0\"/>"
    "<vertex x=\"0\" y=\"10\" z=\"0\"/><vertex x=\"0\" y=\"0\" z=\"10\"/></vertices>"
    "<triangles><triangle v1=\"0\" v2=\"2\" v3=\"1\"/><triangle v1=\"0\" v2=\"1\" v3=\"3\"/>"
    "<triangle v1=\"1\" v2=\"2\" v3=\"3\"/><triangle v1=\"0\" v2=\"3\" v3=\"2\"/></triangles>";

}  // namespace

TEST(HostileLoaders, AZipBombIsRefusedBeforeItInflates) {
    SKIP_UNDER_ULIMIT_V();
    const fs::path d = folder("bomb");
    // 64 MB of blanks in a valid model: deflates about a thousand times.
    std::string model =
        "<?xml version=\"1.0\"?><model unit=\"millimeter\"><resources>"
        "<object id=\"1\"><mesh>" +
        std::string(kTetra) + "</mesh></object></resources>";
    model += std::string(64 << 20, ' ');
    model += "<build><item objectid=\"1\"/></build></model>";
    write_3mf(d / "bomb.3mf", model);
    model.clear();
    model.shrink_to_fit();
    ASSERT_LT(fs::file_size(d / "bomb.3mf"), 1u << 20);
    // 400 MB of address space is more than carve needs to refuse it, less than inflating it
    // and scanning it would take with the copies made on the way.
    const CarveRun r = run_carve("info " + (d / "bomb.3mf").string(), "ulimit -v 1000000;");
    expect_one_line(r, kExitBadInput, "inflate", "zip bomb");
}

TEST(HostileLoaders, NestedComponentCopiesAreCapped) {
    SKIP_UNDER_ULIMIT_V();
    const fs::path d = folder("nest");
    std::string model =
        "<?xml version=\"1.0\"?><model unit=\"millimeter\"><resources>"
        "<object id=\"1\"><mesh>" +
        std::string(kTetra) + "</mesh></object>";
    for (int k = 2; k <= 31; ++k)  // object k holds two copies of object k-1: 2^30 tetrahedra
        model += fmt::format(
            "<object id=\"{}\"><components><component objectid=\"{}\"/>"
            "<component objectid=\"{}\" transform=\"1 0 0 0 1 0 0 0 1 0.001 0 0\"/>"
            "</components></object>",
            k, k - 1, k - 1);
    model += "</resources><build><item objectid=\"31\"/></build></model>";
    write_3mf(d / "nest.3mf", model);
    ASSERT_LT(fs::file_size(d / "nest.3mf"), 4096u);
    const CarveRun r = run_carve("info " + (d / "nest.3mf").string(), "ulimit -v 1000000;");
    expect_one_line(r, kExitBadInput, "100000", "nested components");
}

TEST(HostileLoaders, AsciiStlWithAByteOrderMarkOrCarriageReturnsIsAsciiStl) {
    const fs::path d = folder("text_stl");
    CARVE_MODEL(ascii_path, "bad/ascii_cube.stl");
    const std::string ascii = read(ascii_path);
    std::string cr = ascii;
    std::replace(cr.begin(), cr.end(), '\n', '\r');
    write(d / "bom.stl", "\xEF\xBB\xBF" + ascii);
    write(d / "cr.stl", cr);
    for (const char* f : {"bom.stl", "cr.stl"}) {
        MeshReport report;
        EXPECT_NO_THROW(load_mesh((d / f).string(), report)) << f;
        EXPECT_EQ(report.format, "ASCII STL") << f;
        EXPECT_EQ(report.triangles_read, 12u) << f;
    }
    // Text that starts like ASCII STL and is not: no talk of 808 million triangles.
    write(d / "notstl.stl", "solid x\n" + std::string(200, 'z') + "\n");
    const CarveRun r = run_carve("info " + (d / "notstl.stl").string());
    EXPECT_EQ(r.status, kExitBadInput);
    EXPECT_EQ(r.err.find("triangles"), std::string::npos) << r.err;  // no "808 million"
    EXPECT_NE(r.err.find("ASCII"), std::string::npos) << r.err;
}

TEST(HostileLoaders, CheckReadsAPipe) {
    const fs::path g = scratch() / "pipe.gcode";
    ASSERT_EQ(run_carve("slice " + kSmall + " -q --cavities 1 -o " + g.string()).status, 0);
    const std::string cmd = "cat " + g.string() + " | " + CARVE_BINARY +
                            " check /dev/stdin --json >" + (scratch() / "pipe.json").string() +
                            " 2>" + (scratch() / "pipe.err").string();
    const int raw = std::system(cmd.c_str());
    EXPECT_EQ(WEXITSTATUS(raw), 0) << read(scratch() / "pipe.err");
    EXPECT_NE(read(scratch() / "pipe.json").find("extruded_volume_mm3"), std::string::npos);
}

// A profile that cannot seek (a pipe) is read as a file is: its values are applied and bounded
// (it used to be dropped without a word, the size check's seek having failed the stream).
TEST(HostileLoaders, ProfileFromAPipeIsRead) {
    const fs::path g = scratch() / "pipe_profile.gcode", err = scratch() / "pipe_profile.err";
    auto run = [&](const std::string& line) {
        const std::string cmd = "printf '" + line + "\\n' | " + CARVE_BINARY + " slice " + kSmall +
                                " -q --cavities 1 -o " + g.string() +
                                " --load /dev/stdin >/dev/null 2>" + err.string();
        const int raw = std::system(cmd.c_str());
        return WIFEXITED(raw) ? WEXITSTATUS(raw) : 128;
    };
    EXPECT_EQ(run("temperature = 99999"), kExitBadInput);
    EXPECT_NE(read(err).find("temperature"), std::string::npos) << read(err);
    EXPECT_FALSE(fs::exists(g));
    ASSERT_EQ(run("temperature = 231"), 0) << read(err);
    EXPECT_NE(read(g).find("\nM104 S231"), std::string::npos);  // after the first layer
}

// --- interruption, leftovers and concurrent runs

namespace {

pid_t spawn_carve(const std::vector<std::string>& args) {
    const pid_t pid = fork();
    if (pid == 0) {
        if (!std::freopen("/dev/null", "w", stdout) || !std::freopen("/dev/null", "w", stderr))
            _exit(126);
        exec_carve(args);
    }
    return pid;
}

}  // namespace

TEST(HostileInterruption, SignalsRemoveEveryOutputAndTemporary) {
    // Every signal that ends carve by default and can be caught (SIGQUIT and SIGUSR1 once left
    // temporaries of several MB, issue #38).
    for (const int sig :
         {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2, SIGPIPE, SIGALRM, SIGXCPU}) {
        const fs::path d = folder("signal");
        const std::string model = repo_model("elephant.stl");
        test::RunningCarve run = test::start_carve(
            {"slice", model, "-o", (d / "o.gcode").string(), "--stats", (d / "o.json").string(),
             "--report", (d / "r.html").string(), "--svg-layers", (d / "svg").string(),
             "--svg-every", "20", "--raster", (d / "raster").string(), "--raster-pixel", "0.5"});
        ASSERT_GT(run.pid, 0);
        kill(run.pid, sig);
        const int status = run.wait();
        if (WIFEXITED(status)) GTEST_SKIP() << "carve finished before the signal";
        EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sig) << status;
        EXPECT_EQ(extra_files(d, {}), std::vector<std::string>{}) << "signal " << sig;
    }
}

TEST(HostileInterruption, TheNextRunRemovesWhatAKilledRunLeft) {
    const fs::path d = folder("stale");
    // A process that has ended: its pid names nobody now.
    const pid_t dead = fork();
    if (dead == 0) _exit(0);
    waitpid(dead, nullptr, 0);
    const std::string stale = fmt::format(".carve-tmp-{}-AbCdEf", dead);
    write(d / stale, "half a G-code");
    fs::create_directories(d / fmt::format(".carve-tmp-{}-dir123", dead));
    write(d / fmt::format(".carve-tmp-{}-dir123", dead) / "layer_0001.svg", "<svg");
    // One of a live process (this test) is left alone, and so is a file that only looks alike.
    const std::string live = fmt::format(".carve-tmp-{}-LiVe00", getpid());
    write(d / live, "in use");
    write(d / "carve-tmp-notours", "mine");
    const CarveRun r =
        run_carve("slice " + kSmall + " -q --cavities 1 -o " + (d / "o.gcode").string());
    ASSERT_EQ(r.status, 0) << r.err;
    auto left = extra_files(d, {});
    std::sort(left.begin(), left.end());
    std::vector<std::string> expected{live, "carve-tmp-notours", "o.gcode"};
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(left, expected);
}

TEST(HostileInterruption, AFailedRunLeavesNoneOfItsSideOutputs) {
    const fs::path d = folder("failed_side");
    // The report's folder does not exist: everything else was complete when it failed.
    const CarveRun r =
        run_carve("slice " + kSmall + " -q --cavities 1 -o " + (d / "o.gcode").string() +
                  " --stats " + (d / "o.json").string() + " --svg-layers " + (d / "svg").string() +
                  " --raster " + (d / "raster").string() + " --raster-pixel 0.5 --report " +
                  (d / "missing" / "r.html").string());
    EXPECT_EQ(r.status, kExitOutput) << r.err;
    EXPECT_EQ(extra_files(d, {}), std::vector<std::string>{});
    // A full disk (here a file size limit) in the middle of the raster stack: same.
    const CarveRun full = run_carve(
        "slice " + kSmall + " -q --cavities 1 -o " + (d / "o.gcode").string() + " --raster " +
            (d / "raster").string() + " --raster-pixel 0.05 --svg-layers " + (d / "svg").string(),
        "ulimit -f 64;");
    EXPECT_EQ(full.status, kExitOutput) << full.err;
    EXPECT_EQ(extra_files(d, {}), std::vector<std::string>{});
}

TEST(HostileInterruption, TwoRunsSharingAReportPathDoNotCollide) {
    const fs::path d = folder("shared_report");
    const std::string report = (d / "r.html").string();
    std::vector<pid_t> pids;
    for (int k = 0; k < 2; ++k)
        pids.push_back(
            spawn_carve({"slice", kSmall, "-q", "--cavities", "1", "-o",
                         (d / fmt::format("o{}.gcode", k)).string(), "--report", report}));
    for (pid_t p : pids) {
        int status = 0;
        waitpid(p, &status, 0);
        EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
    }
    const std::string html = read(report);
    EXPECT_NE(html.find("</html>"), std::string::npos);
    auto left = extra_files(d, {});
    std::sort(left.begin(), left.end());
    EXPECT_EQ(left, (std::vector<std::string>{"o0.gcode", "o1.gcode", "r.html"}));
}

TEST(HostileInterruption, TimeoutEndsTheRunAndRemovesItsOutputs) {
    const fs::path d = folder("timeout");
    const CarveRun r =
        run_carve("slice " + repo_model("elephant.stl") + " -q -o " + (d / "o.gcode").string() +
                  " --report " + (d / "r.html").string() + " --timeout 0.3");
    expect_one_line(r, kExitBadInput, "--timeout", "timeout");
    EXPECT_EQ(extra_files(d, {}), std::vector<std::string>{});
}

// --- the writer itself

TEST(AtomicWriter, NothingAppearsUntilCommitAndNothingStaysOnError) {
    const fs::path d = folder("atomic");
    const std::string target = (d / "x.txt").string();
    {
        AtomicFile f(target);
        f.write("hello");
        EXPECT_FALSE(fs::exists(target));
        EXPECT_EQ(extra_files(d, {}).size(), 1u);  // the temporary
    }
    EXPECT_EQ(extra_files(d, {}), std::vector<std::string>{});
    write_file_atomically(target, "one");
    EXPECT_EQ(read(target), "one");
    {
        OutputGroup group;
        write_file_atomically(target, "two", &group);
        EXPECT_EQ(read(target), "one");  // held back
        group.commit_all();
    }
    EXPECT_EQ(read(target), "two");
    {
        OutputGroup group;
        write_file_atomically(target, "three", &group);
    }  // never committed: dropped
    EXPECT_EQ(read(target), "two");
    EXPECT_EQ(extra_files(d, {}), std::vector<std::string>{"x.txt"});
    EXPECT_THROW(AtomicFile("/dev/null"), OutputError);
    EXPECT_THROW(AtomicFile((d / "no" / "such" / "x").string()), OutputError);
}

TEST(AtomicWriter, OutputPathsAreComparedAsFiles) {
    const fs::path d = folder("paths");
    fs::create_directories(d / "sub");
    write(d / "in.stl", "x");
    const std::string in = (d / "in.stl").string();
    EXPECT_THROW(check_output_paths({{in, "model"}}, {{(d / "sub/../in.stl").string(), "-o"}}),
                 OutputError);
    EXPECT_THROW(check_output_paths({{in, "model"}}, {{(d / "a").string(), "-o"},
                                                      {(d / "sub/../a").string(), "--stats"}}),
                 OutputError);
    fs::create_hard_link(d / "in.stl", d / "hard.stl");
    EXPECT_THROW(check_output_paths({{in, "model"}}, {{(d / "hard.stl").string(), "-o"}}),
                 OutputError);
    EXPECT_NO_THROW(check_output_paths(
        {{in, "model"}},
        {{(d / "a").string(), "-o"}, {(d / "b").string(), "--stats"}, {"", "--report"}}));
}

// --- runaway work and memory

// A binary STL of n random triangles in a cube `size` mm wide: no two share an edge.
static std::string soup_stl(uint32_t n, unsigned seed, float size) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0, size);
    std::string stl(80, '\0');
    stl.reserve(84 + 50 * size_t(n));
    stl.append(reinterpret_cast<const char*>(&n), 4);
    for (uint32_t t = 0; t < n; ++t) {
        float f[12] = {0, 0, 0};
        for (int k = 3; k < 12; ++k) f[k] = u(rng);
        stl.append(reinterpret_cast<const char*>(f), sizeof f);
        stl.append(2, '\0');
    }
    return stl;
}

TEST(HostileWork, ATriangleSoupIsRefusedBeforeSlicing) {
    const fs::path d = folder("soup");
    write(d / "soup.stl", soup_stl(5000, 7, 50));
    const CarveRun r =
        run_carve("slice " + (d / "soup.stl").string() + " -q -o " + (d / "o.gcode").string());
    expect_one_line(r, kExitBadInput, "triangle soup", "soup");
    EXPECT_EQ(extra_files(d, {"soup.stl"}), std::vector<std::string>{});
}

// A soup of 300,000 triangles (900,000 distinct points, 15 MB of binary STL) is refused
// within 200 MB of address space. Before the loader streamed the file, welded through 4-byte
// slots and refused the soup as soon as its edges were counted, it needed about 296 MB: the
// whole file, a table of 16-byte slots and a record of some 120 bytes for each of the
// 300,000 one-triangle shells. carve needs about 118 MB for it now and 25 MB for a cube.
TEST(HostileWork, ALargeTriangleSoupIsRefusedWithinBoundedMemory) {
    SKIP_UNDER_ULIMIT_V();
    const fs::path d = folder("big_soup");
    write(d / "soup.stl", soup_stl(300000, 11, 100));
    const CarveRun r =
        run_carve("slice " + (d / "soup.stl").string() + " -q -o " + (d / "o.gcode").string(),
                  "ulimit -v 200000; ulimit -c 0;");
    expect_one_line(r, kExitBadInput,
                    "not a solid: its 300000 triangles have 900000 distinct corners or more",
                    "big soup");
    EXPECT_NE(r.err.find("(a triangle soup)"), std::string::npos) << r.err;
    EXPECT_EQ(extra_files(d, {"soup.stl"}), std::vector<std::string>{});
}

// From 2 million facets a binary STL soup is counted in eighths before it is welded: 2.2
// million random triangles (110 MB) are refused within 200 MB of address space, where welding
// them whole needed over 250 MB (a 10-million-triangle soup peaked at 1.30 GB, now 105 MB:
// bench/results/soup_memory.md).
TEST(HostileWork, AHugeTriangleSoupIsRefusedBeforeItIsWelded) {
    SKIP_UNDER_ULIMIT_V();
    const fs::path d = folder("huge_soup");
    write(d / "soup.stl", soup_stl(2200000, 13, 100));
    const CarveRun r =
        run_carve("slice " + (d / "soup.stl").string() + " -q -o " + (d / "o.gcode").string(),
                  "ulimit -v 200000; ulimit -c 0;");
    expect_one_line(r, kExitBadInput, "over 2.25 a triangle", "huge soup");
    EXPECT_NE(r.err.find("(a triangle soup)"), std::string::npos) << r.err;
    fs::remove(d / "soup.stl");
    EXPECT_EQ(extra_files(d, {}), std::vector<std::string>{});
}

TEST(HostileWork, AnAddressSpaceLimitIsReportedNotACrash) {
    SKIP_UNDER_ULIMIT_V();
    const fs::path d = folder("ulimit");
    for (const char* limit : {"65000", "75000"}) {
        const CarveRun r =
            run_carve("slice " + repo_model("elephant.stl") + " -q -o " + (d / "o.gcode").string(),
                      std::string("ulimit -v ") + limit + "; ulimit -c 0;");
        EXPECT_TRUE(r.status == 0 || r.status == kExitInternal) << limit << ": " << r.status;
        if (r.status != 0) {
            EXPECT_NE(r.err.find("out of memory"), std::string::npos) << r.err;
            EXPECT_EQ(extra_files(d, {}), std::vector<std::string>{});
        }
        fs::remove(d / "o.gcode");
    }
}

// The scale-times-size guard counts lines of the width printed (--extrusion-width may be far
// under the nozzle), and a resin stack refuses images no screen has before drawing any.
TEST(HostileWork, SizeGuardsCountTheLinesAndPixelsPrinted) {
    const fs::path d = folder("size_guards");
    std::vector<test::StlTriangle> t;
    test::add_box(t, 0, 0, 0, 100, 100, 2);
    const std::string plate = test::write_stl("size_guard_plate.stl", t).string();
    const fs::path g = d / "out.gcode";
    // 10 m across at 0.05 mm lines: 200,000 of them (by the 3 mm nozzle only 3,333).
    CarveRun r = run_carve("slice " + plate + " -q --no-bed-check --scale 100 --nozzle 3 " +
                           "--extrusion-width 0.05 --layer-height 0.05 -o " + g.string());
    expect_one_line(r, kExitBadInput, "line widths across", "thin lines");
    EXPECT_FALSE(fs::exists(g));
    // 60 mm at 0.005 mm pixels: 12,000 x 12,000.
    r = run_carve("slice " + kSmall + " -q --scale 3 --raster " + (d / "stack").string() +
                  " --raster-pixel 0.005 -o " + g.string());
    expect_one_line(r, kExitBadInput, "--raster-pixel", "raster pixels");
    EXPECT_FALSE(fs::exists(g));
    EXPECT_FALSE(fs::exists(d / "stack"));
}

TEST(HostileWork, AModelFileOverTheSizeLimitIsRefusedBeforeItIsRead) {
    SKIP_UNDER_ULIMIT_V();
    const fs::path d = folder("huge");
    { std::ofstream(d / "huge.stl").put('s'); }
    fs::resize_file(d / "huge.stl", std::uintmax_t(600) << 20);  // sparse: no disk used
    const CarveRun r = run_carve("info " + (d / "huge.stl").string(), "ulimit -v 200000;");
    expect_one_line(r, kExitBadInput, "512 MB", "huge model");
}

// --- carve check, copies and custom G-code: the bounds docs/limits.md once listed as missing

// carve check reads lines as they come, so a file without line ends is refused instead of held
// whole; its --mesh gets the soup refusal of carve slice; a header's filament diameter has the
// option's range, and the option wins over it; --timeout ends a check that waits on a pipe.
TEST(HostileCheck, LongLinesSoupsHeadersAndTimeoutsAreBounded) {
    const fs::path d = folder("check_bounds");
    write(d / "one_line.gcode", std::string(3 << 20, 'G'));
    CarveRun r = run_carve("check " + (d / "one_line.gcode").string());
    expect_one_line(r, kExitBadInput, "line longer than 1 MB", "one line");

    const fs::path g = d / "box.gcode";
    ASSERT_EQ(run_carve("slice " + kSmall + " -q --cavities 1 -o " + g.string()).status, 0);
    write(d / "soup.stl", soup_stl(5000, 7, 50));
    r = run_carve("check " + g.string() + " --mesh " + (d / "soup.stl").string());
    expect_one_line(r, kExitBadInput, "triangle soup", "check --mesh soup");

    write(d / "odd.gcode", "; filament_diameter = 0.001\nG1 X1 Y1 E1\n");
    r = run_carve("check " + (d / "odd.gcode").string());
    expect_one_line(r, kExitBadInput, "filament diameter 0.001 mm is outside 0.5 to 5", "header");
    r = run_carve("check " + (d / "odd.gcode").string() + " --json --filament-diameter 2.85");
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("\"filament_diameter_source\": \"option\""), std::string::npos) << r.out;

    // A FIFO nobody writes to: opening it waits for ever.
    const fs::path fifo = d / "never.gcode";
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    const auto t0 = std::chrono::steady_clock::now();
    r = run_carve("check " + fifo.string() + " --timeout 0.5");
    EXPECT_EQ(r.status, kExitBadInput) << r.err;
    EXPECT_NE(r.err.find("--timeout"), std::string::npos) << r.err;
    // Not a timing assertion: only that the run ended at all (it would wait for ever).
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(60));
}

// --copies multiplies the mesh: without the bed check (which used to be the only stop) the
// placed triangles are capped as a 3MF's are, before room for the copies is reserved.
TEST(HostileWork, CopiesAreCappedWithoutTheBedCheck) {
    const fs::path d = folder("copies_cap");
    std::vector<test::StlTriangle> t;
    for (int i = 0; i < 80; ++i)  // 80 x 80 small boxes: 76,800 triangles
        for (int j = 0; j < 80; ++j) test::add_box(t, i, j, 0, i + 0.5f, j + 0.5f, 1);
    const std::string many = test::write_stl("copies_cap_boxes.stl", t).string();
    const CarveRun r = run_carve("slice " + many + " -q --no-bed-check --copies 400 -o " +
                                 (d / "o.gcode").string());
    expect_one_line(r, kExitBadInput, "over the limit of 20000000", "copies");
    EXPECT_EQ(extra_files(d, {}), std::vector<std::string>{});
}

// A placeholder may stand for a value of megabytes: the expansion is bounded as it grows, and
// layer G-code, expanded on every layer, is bounded in total. A long run of blanks in it is not
// a problem for the G92 E0 scan either.
TEST(HostilePlaceholders, ExpansionIsBoundedAsItGrows) {
    Settings s;
    s.profile_values["notes"] = std::string(1 << 20, 'x');
    EXPECT_NO_THROW(expand_custom_gcode("; [notes]\n", s));
    EXPECT_THROW(expand_custom_gcode("; [notes][notes][notes][notes][notes]\n", s), InputError);
    EXPECT_THROW(expand_custom_gcode("{notes}{notes}{notes}{notes}{notes}\n", s), InputError);

    const fs::path d = folder("layer_gcode_cap");
    const fs::path g = d / "o.gcode";
    // 1 MB of comment on each of the box's 30 layers, then 2 MB on each of 40.
    auto run = [&](size_t bytes, const std::string& layer) {
        write(d / "p.ini", "layer_gcode = ;" + std::string(bytes, ' ') + "G92 E0\n");
        return run_carve("slice " + kSmall + " -q --cavities 1 --layer-height " + layer +
                         " --load " + (d / "p.ini").string() + " -o " + g.string());
    };
    CarveRun r = run(1 << 20, "0.2");
    EXPECT_EQ(r.status, 0) << r.err;
    fs::remove(g);
    r = run(2 << 20, "0.15");
    expect_one_line(r, kExitBadInput, "more than 64 MB", "layer gcode");
    EXPECT_EQ(extra_files(d, {"p.ini"}), std::vector<std::string>{});
}

// Valid XML with character references (&#48; is '0', &#x30; too) was refused as "a vertex
// without a valid x" (issue #38).
TEST(HostileLoaders, XmlCharacterReferencesAreRead) {
    const fs::path d = folder("xml_refs");
    std::string tetra = kTetra;
    tetra.replace(tetra.find("x=\"10\""), 6, "x=\"1&#48;\"");
    tetra.replace(tetra.find("y=\"10\""), 6, "y=\"1&#x30;\"");
    const std::string model =
        "<?xml version=\"1.0\"?><model unit=\"millimeter\"><resources>"
        "<object id=\"1\" name=\"A&amp;B\"><mesh>" +
        tetra + "</mesh></object></resources><build><item objectid=\"1\"/></build></model>";
    write_3mf(d / "refs.3mf", model);
    const CarveRun r = run_carve("info " + (d / "refs.3mf").string() + " --json");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("\"size_mm\": [\n    10.0,\n    10.0,\n    10.0\n  ]"), std::string::npos)
        << r.out;
}

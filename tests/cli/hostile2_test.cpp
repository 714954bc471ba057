// Hostile input, round two (issue #38): G-code injected through names, prints beyond the
// machine, `carve check` bounded by its input, figures beyond the machine's range, and the
// leftovers and messages of round one. Every input is made by the test. No timings asserted.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "base/errors.hpp"
#include "gcode/safe_text.hpp"
#include "support/carve_run.hpp"
#include "support/stl_boxes.hpp"

namespace fs = std::filesystem;
using namespace carve;
using namespace carve::test;
using namespace std::string_literals;

namespace {

// For /bin/sh: the whole text in single quotes, which keep newlines and control characters.
std::string quoted(const std::string& s) {
    std::string out = "'";
    for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

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

std::vector<std::string> split_lines(const std::string& text) {
    std::vector<std::string> out;
    size_t at = 0;
    while (at < text.size()) {
        const size_t end = text.find('\n', at);
        out.push_back(text.substr(at, end == std::string::npos ? std::string::npos : end - at));
        if (end == std::string::npos) break;
        at = end + 1;
    }
    return out;
}

// A control character other than the tab and the line feed that ends each line: what a
// firmware could read as the end of a line, or of the file.
bool has_control(const std::string& line) {
    for (char c : line) {
        const unsigned char u = static_cast<unsigned char>(c);
        if ((u < 0x20 && c != '\t') || u == 0x7f) return true;
    }
    return false;
}

// A box of w x d x h mm as a binary STL in `dir` named `name`.
fs::path box(const fs::path& dir, const std::string& name, float w, float d, float h) {
    std::vector<StlTriangle> t;
    add_box(t, 0, 0, 0, w, d, h);
    const fs::path made = write_stl("box_tmp.stl", t);
    const fs::path p = dir / name;
    fs::rename(made, p);
    return p;
}

}  // namespace

// --- G-code injection

TEST(HostileNames, SafeTextKeepsTheReadablePartOnOneLine) {
    EXPECT_EQ(comment_text("a\nM104 S300\r\0b\x1b\x7f\tc"s), "a\\nM104 S300\\r\\0b\\x1b\\x7f\tc");
    EXPECT_EQ(comment_text("caf\xc3\xa9 ; plain"), "caf\xc3\xa9 ; plain");
    EXPECT_EQ(label_text("my part (2)\n;M104"), "my_part__2___M104");
    EXPECT_EQ(label_text(""), "object");
}

TEST(HostileNames, AFileNameCannotEndAHeaderCommentOrStartACommand) {
    const fs::path d = folder("names");
    const std::string evil = "evil\nM104 S300\r\x01M300 S9\x1b;\x7f.stl";
    const fs::path model = box(d, evil, 20, 20, 2);
    for (const char* printer : {"mk3s", "klipper"}) {
        const fs::path g = d / fmt::format("out-{}.gcode", printer);
        const CarveRun r =
            run_carve("slice " + quoted(model.string()) + " -q --cavities 1 " +
                      "--copies 2 --printer " + std::string(printer) + " -o " + g.string());
        ASSERT_EQ(r.status, 0) << r.err;
        const std::string text = read(g);
        int model_lines = 0;
        for (const std::string& line : split_lines(text)) {
            EXPECT_FALSE(has_control(line)) << printer << ": " << line;
            EXPECT_NE(line.rfind("M104 S300", 0), 0u) << printer;
            EXPECT_NE(line.rfind("M300 S9", 0), 0u) << printer;
            if (line.rfind("; model = ", 0) == 0) {
                ++model_lines;
                // The file's name only, readable, on its line.
                EXPECT_EQ(line, "; model = evil\\nM104 S300\\r\\x01M300 S9\\x1b;\\x7f.stl");
            }
            // A label inside a command holds nothing a parser could split on.
            for (const std::string cmd :
                 {"M486 A", "EXCLUDE_OBJECT_DEFINE NAME=", "EXCLUDE_OBJECT_START NAME="})
                if (line.rfind(cmd, 0) == 0) {
                    const std::string name =
                        line.substr(cmd.size(), line.find(' ', cmd.size()) - cmd.size());
                    EXPECT_EQ(name, label_text(name)) << line;
                    EXPECT_EQ(name.rfind("evil_M104_S300__M300_S9__", 0), 0u) << line;
                }
        }
        EXPECT_EQ(model_lines, 1) << printer;
        EXPECT_EQ(text.find(d.string()), std::string::npos) << "the folder is in the G-code";
    }
}

TEST(HostileNames, ProfileTextStaysOnItsCommentLine) {
    const fs::path d = folder("profile_text");
    const fs::path model = box(d, "m.stl", 20, 20, 2);
    // A value with a form feed and a NUL, and a placeholder that cannot be expanded on a line
    // with a carriage return: the configuration block and the "could not expand" comment.
    write(d / "p.ini",
          "layer_gcode = ;x\x0c\x0bM104 S300\x00\\n\n"
          "before_layer_gcode = [no_such_key]\rM104 S301\\n\n"s);
    const fs::path g = d / "o.gcode";
    const CarveRun r = run_carve("slice " + model.string() + " -q --cavities 1 --load " +
                                 (d / "p.ini").string() + " -o " + g.string());
    ASSERT_EQ(r.status, 0) << r.err;
    bool in_config = false;
    for (const std::string& line : split_lines(read(g))) {
        if (line == "; prusaslicer_config = begin") in_config = true;
        if (in_config || line.rfind("; carve: could not expand", 0) == 0) {
            EXPECT_FALSE(has_control(line)) << line;
        }
        EXPECT_NE(line.rfind("M104 S301", 0), 0u);
    }
    EXPECT_TRUE(in_config);
}

// --- nothing printed beyond the machine

// 310 mm: over every preset's height (the highest, 250).
TEST(HostileMachine, ATowerTallerThanThePrinterIsRefusedOnEveryPreset) {
    const fs::path d = folder("tower");
    const fs::path tower = box(d, "tower.stl", 10, 10, 310);
    for (const char* printer : {"generic", "mk3s", "ender3", "klipper"}) {
        const fs::path g = d / "t.gcode";
        const CarveRun r = run_carve("slice " + tower.string() + " -q --printer " +
                                     std::string(printer) + " -o " + g.string());
        EXPECT_EQ(r.status, kExitBadInput) << printer << ": " << r.err;
        EXPECT_EQ(lines(r.err), 1) << printer << ": " << r.err;
        EXPECT_NE(r.err.find("310.0 mm tall"), std::string::npos) << printer << ": " << r.err;
        EXPECT_FALSE(fs::exists(g)) << printer;
    }
    // PrusaSlicer's key in a profile, and the option.
    write(d / "p.ini", "max_print_height = 210\nbed_shape = 0x0,500x0,500x500,0x500\n");
    const fs::path g = d / "t.gcode";
    CarveRun r = run_carve("slice " + tower.string() + " -q --printer klipper --load " +
                           (d / "p.ini").string() + " -o " + g.string());
    EXPECT_EQ(r.status, kExitBadInput) << r.err;
    EXPECT_NE(r.err.find("than the 210 mm"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(g));
    const fs::path small = box(d, "small.stl", 10, 10, 3);
    fs::remove(g);
    r = run_carve("slice " + small.string() + " -q --cavities 1 --max-print-height 2 -o " +
                  g.string());
    EXPECT_EQ(r.status, kExitBadInput) << r.err;
    EXPECT_NE(r.err.find("max-print-height"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(g));
    r = run_carve("slice " + small.string() + " -q --cavities 1 --max-print-height 3 -o " +
                  g.string());
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(fs::exists(g));
}

// --- carve check bounded by its input

namespace {

// `carve ARGS` in a child whose address space is capped at `mb` megabytes; uncapped in the
// sanitizer build, where nothing runs under `ulimit -v` (the figures and messages are still
// checked there, the cap in the normal build).
CarveRun run_capped(const std::string& args, int mb) {
#if defined(CARVE_TEST_ASAN)
    (void)mb;
    return run_carve(args);
#else
    return run_carve(args, fmt::format("ulimit -v {};", mb * 1024));
#endif
}

}  // namespace

TEST(HostileCheck, NumbersInTheFileDoNotSetItsMemory) {
    const fs::path d = folder("check_numbers");
    // A 0.2 mm layer, a move to z = -1e9 and back: once a layer a billion mm thick.
    write(d / "deep.gcode",
          "G90\nM83\nG1 Z0.2 F600\nG1 X10 Y10 E1\nG1 Z-1e9\nG1 X20 E1\nG1 Z0.4\nG1 X10 E1\n");
    // Relative moves that add up to infinity, and a NaN after it.
    write(d / "inf.gcode", "G91\nM83\nG1 Z0.2 E0\nG1 X1 E1\nG1 Z1e308\nG1 Z1e308\nG1 X1 E1\n");
    // Extrusion of 1e300 mm.
    write(d / "e.gcode", "G90\nM83\nG1 Z0.2\nG1 X10 Y10 E1e300\nG1 X20 E1e300\n");
    for (const char* name : {"deep.gcode", "inf.gcode", "e.gcode"}) {
        const CarveRun r = run_capped("check " + (d / name).string() + " --timeout 60", 400);
        EXPECT_EQ(r.status, kExitBadInput) << name << ": " << r.err;
        EXPECT_EQ(lines(r.err), 1) << name << ": " << r.err;
        EXPECT_NE(r.err.find("line "), std::string::npos) << name << ": " << r.err;
        EXPECT_EQ(r.err.find("nan"), std::string::npos) << name << ": " << r.err;
        EXPECT_EQ(r.err.find("internal"), std::string::npos) << name << ": " << r.err;
    }
    // A dwell and a feed rate that would make the time infinite: finite figures.
    write(d / "time.gcode",
          "G90\nM83\nG1 Z0.2 F600\nG1 X10 Y10 E1\nG4 S1e300\nG4 S1e300\n"
          "G1 X20 E1 F0.0000000001\nG1 X10 E1 F0.0000000001\n");
    const CarveRun r = run_capped("check " + (d / "time.gcode").string() + " --json", 400);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.out.find("null"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("inf"), std::string::npos) << r.out;
}

TEST(HostileCheck, LayersInMidAirHang) {
    const fs::path d = folder("check_mid_air");
    // A 10 mm square drawn on every layer: on the bed, then the same square 15 mm above the
    // last layer printed.
    auto square = [](double z) {
        return fmt::format(
            "G1 Z{:.2f}\nG1 X10 Y10\nG1 X20 Y10 E1\nG1 X20 Y20 E1\nG1 X10 Y20 E1\n"
            "G1 X10 Y10 E1\n",
            z);
    };
    std::string text = "G90\nM83\nG1 F1200\n";
    for (int i = 1; i <= 5; ++i) text += square(0.2 * i);
    write(d / "held.gcode", text);
    write(d / "gap.gcode", text + square(16.0));
    write(d / "off_bed.gcode", "G90\nM83\nG1 F1200\n" + square(10.2) + square(10.4));
    auto far_hanging = [&](const std::string& name) {
        const CarveRun r = run_carve("check " + (d / name).string() + " --json");
        EXPECT_EQ(r.status, 0) << name << ": " << r.err;
        const size_t at = r.out.find("\"far_unsupported_area_mm2\":");
        if (at == std::string::npos) return -1.0;
        return std::stod(r.out.substr(at + 27));
    };
    EXPECT_NEAR(far_hanging("held.gcode"), 0, 1e-9);
    // A 10 mm square of about 0.45 mm lines: some 18 mm2 of footprint, all of it hanging.
    EXPECT_GT(far_hanging("gap.gcode"), 10);
    EXPECT_GT(far_hanging("off_bed.gcode"), 10);
}

TEST(HostileCheck, CarriageReturnLineEndsAreLineEnds) {
    const fs::path d = folder("check_cr");
    std::string text = "G90\nM83\nG1 F1200\n";
    for (int i = 1; i <= 5; ++i)
        text += fmt::format("G1 Z{:.1f}\nG1 X10 Y10\nG1 X20 Y10 E1\nG1 X20 Y20 E1\n", 0.2 * i);
    std::string cr = text, crlf;
    std::replace(cr.begin(), cr.end(), '\n', '\r');
    for (char c : text) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
    write(d / "lf.gcode", text);
    write(d / "cr.gcode", cr);
    write(d / "crlf.gcode", crlf);
    const std::string lf = run_carve("check " + (d / "lf.gcode").string() + " --json").out;
    EXPECT_NE(lf.find("\"layers\": 5"), std::string::npos) << lf;
    for (const char* name : {"cr.gcode", "crlf.gcode"}) {
        const CarveRun r = run_carve("check " + (d / name).string() + " --json");
        EXPECT_EQ(r.status, 0) << name << ": " << r.err;
        EXPECT_EQ(r.out, lf) << name;
    }
}

TEST(HostileCheck, ManyZReversalsAreReadInBoundedMemory) {
    const fs::path d = folder("check_reversals");
    std::string text = "G90\nM83\nG1 F6000\n";
    for (int i = 0; i < 20000; ++i)
        text += fmt::format("G1 Z{}\nG1 X10 Y10\nG1 X12 Y10 E0.1\n", i % 2 ? "0.4" : "0.2");
    write(d / "rev.gcode", text);
    const CarveRun r = run_capped("check " + (d / "rev.gcode").string() + " --json", 400);
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("\"z_reversals\": 9999"), std::string::npos) << r.out.substr(0, 200);
}

// --- figures beyond the machine's range

TEST(HostileFigures, ComputedTemperaturesBeyondRangeAreRefusedNamingTheKey) {
    const fs::path d = folder("figures");
    const fs::path model = box(d, "m.stl", 20, 20, 2);
    const fs::path g = d / "o.gcode";
    write(d / "computed.ini", "layer_gcode = M104 S{layer_num*1000}\n");
    CarveRun r = run_carve("slice " + model.string() + " -q --cavities 1 --load " +
                           (d / "computed.ini").string() + " -o " + g.string());
    EXPECT_EQ(r.status, kExitBadInput) << r.err;
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("layer_gcode"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("nozzle temperature"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(g));
    write(d / "fan.ini", "before_layer_gcode = M106 S{300+layer_num}\n");
    r = run_carve("slice " + model.string() + " -q --cavities 1 --load " +
                  (d / "fan.ini").string() + " -o " + g.string());
    EXPECT_EQ(r.status, kExitBadInput) << r.err;
    EXPECT_NE(r.err.find("before_layer_gcode"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(g));
    // Written as it stands in the profile: passed through, with a note.
    write(d / "verbatim.ini", "end_gcode = M104 S600\\nM140 S0\\n\n");
    r = run_carve("slice " + model.string() + " --cavities 1 --load " +
                  (d / "verbatim.ini").string() + " -o " + g.string());
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("note: end_gcode: 'M104 S600' sets a nozzle temperature of 600"),
              std::string::npos)
        << r.err;
    EXPECT_NE(read(g).find("\nM104 S600\n"), std::string::npos);
}

// --- names that select nothing

TEST(HostileNames, EmptyOrUnknownPrinterNamesAreRefused) {
    const fs::path d = folder("printer_names");
    const fs::path model = box(d, "m.stl", 20, 20, 2);
    const fs::path g = d / "o.gcode";
    for (const std::string& name : {std::string("''"), std::string("nosuch")}) {
        const CarveRun r =
            run_carve("slice " + model.string() + " -q --printer " + name + " -o " + g.string());
        EXPECT_EQ(r.status, kExitBadInput) << name << ": " << r.err;
        EXPECT_NE(r.err.find("unknown printer"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(g));
    }
    write(d / "flat.ini", "layer_height = 0.2\n");
    const CarveRun r =
        run_carve("slice " + model.string() + " -q --load " + (d / "flat.ini").string() +
                  " --printer-profile 'Original Prusa i3 MK3S' -o " + g.string());
    EXPECT_EQ(r.status, kExitBadInput) << r.err;
    EXPECT_NE(r.err.find("selects nothing"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(g));
}

// A NUL in a broken file's token ended the message there ("... found '"): every message is
// printed whole, the NUL and other control bytes written as \xNN, on one line.
TEST(HostileNames, ANulInAMessageIsShownNotAnEnd) {
    const fs::path d = folder("nul_message");
    write(d / "nul.stl", "solid t\n facet normal 0 0 1\n  outer lo\0op\x01\n"s);
    const fs::path g = d / "o.gcode";
    const CarveRun r = run_carve("slice " + (d / "nul.stl").string() + " -q -o " + g.string());
    EXPECT_EQ(r.status, kExitBadInput) << r.err;
    EXPECT_NE(r.err.find("found 'lo\\x00op\\x01'"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(g));
    EXPECT_EQ(printable_message("a\0b\tc\x7f"s), "a\\x00b\tc\\x7f");
}

// --- work bounded by the input

// Refused at the limit: the string once doubled to 1 GB before the check (1,040 MB peak).
TEST(HostileWork, DevZeroIsRefusedAtTheSizeLimit) {
    if (!fs::exists("/usr/bin/time")) GTEST_SKIP() << "/usr/bin/time (GNU time) is missing";
    const fs::path d = folder("dev_zero");
    const fs::path g = d / "z.gcode", rss = d / "rss.txt";
    const CarveRun r =
        run_carve("slice /dev/zero -q -o " + g.string(), "/usr/bin/time -f %M -o " + rss.string());
    EXPECT_EQ(r.status, kExitBadInput) << r.err;
    EXPECT_NE(r.err.find("larger than 512 MB"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(g));
    // Peak resident kB: the 512 MB read, not twice it (AddressSanitizer's own memory comes on
    // top of it in the sanitizer build: the bound is the normal build's).
#if defined(CARVE_TEST_ASAN)
    return;
#endif
    const std::string kb = read(rss);
    ASSERT_FALSE(kb.empty());
    EXPECT_LT(std::stol(kb.substr(kb.find_last_of("\n", kb.size() - 2) + 1)), 800L * 1024) << kb;
}

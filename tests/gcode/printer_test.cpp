// A print that starts, sticks and ends right (issue #36), read the way the machines read it:
// the firmware (a temperature is reached when M190/M109 waited for it, and an extrusion before
// that is refused, as Klipper's "Extrude below minimum temp"), Moonraker's metadata parser
// (moonraker/components/file_manager/metadata.py, PrusaSlicer's rules: the object height from
// ";BEFORE_LAYER_CHANGE" and the next line's ";<z>", else the highest "G1 Z.. F.." of the last
// MiB; filament_type, filament_settings_id, filament_colour from the configuration block), and
// PrusaSlicer's G-code viewer (;TYPE:Custom, ;TYPE:Skirt/Brim).
#include <gtest/gtest.h>
#include <stdlib.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "support/carve_run.hpp"
#include "support/gcode_slices.hpp"
#include "support/models.hpp"
#include "support/regex.hpp"
#include "support/stl_boxes.hpp"

namespace fs = std::filesystem;
using carve::test::read;
using carve::test::run_carve;
using carve::test::scratch;
using carve::test::small_part;

namespace {

constexpr size_t kMiB = 1 << 20;

std::string slice(const std::string& model, const std::string& args, const std::string& name,
                  int want_status = 0, std::string* err = nullptr) {
    return carve::test::slice_text(model, args, name, want_status, err);
}
using carve::test::lines_of;

using carve::test::words;

// The extruder's E as the firmware follows it: absolute or relative (M82 / M83), reset by G92.
struct EAxis {
    bool relative = false;
    double e = 0;
    // Reads the modes and resets of any command; for a move, the E it adds (0 without an E).
    double step(const std::string& cmd, std::map<char, double>& w) {
        if (cmd == "M83") relative = true;
        if (cmd == "M82") relative = false;
        if (cmd == "G92" && w.count('E')) e = w['E'];
        if ((cmd != "G1" && cmd != "G0") || !w.count('E')) return 0;
        const double de = relative ? w['E'] : w['E'] - e;
        e = relative ? e + w['E'] : w['E'];
        return de;
    }
};

std::string fandisk() {
    return carve::test::repo_model("fandisk.stl");
}

double model_height(const std::string& model) {
    const carve::test::CarveRun r = run_carve("info " + model + " --json");
    const nlohmann::json j = nlohmann::json::parse(r.out);
    return j["size_mm"][2].get<double>();
}

// What the firmware knows when the first extrusion comes: the temperatures waited for (M190 /
// M109 with S or R above 0, Klipper's TEMPERATURE_WAIT), the line of that extrusion.
struct Start {
    double bed_waited = 0, nozzle_waited = 0;
    int first_extrusion = -1;
};

Start read_start(const std::string& g) {
    Start s;
    EAxis axis;
    int n = 0;
    for (const std::string& l : lines_of(g)) {
        ++n;
        if (l.empty() || l[0] == ';') continue;
        std::map<char, double> w = words(l);
        const std::string cmd = l.substr(0, l.find_first_of(" ;"));
        if (cmd == "M190") s.bed_waited = std::max(w['S'], w['R']);
        if (cmd == "M109") s.nozzle_waited = std::max(w['S'], w['R']);
        // A lower target lets the nozzle cool: what was waited for no longer holds (Klipper's
        // heater drops below min_extrude_temp and refuses the extrusion).
        if (cmd == "M104" && w['S'] < s.nozzle_waited) s.nozzle_waited = 0;
        if (axis.step(cmd, w) > 0 && (w.count('X') || w.count('Y'))) {
            s.first_extrusion = n;
            return s;
        }
    }
    return s;
}

// Moonraker's PrusaSlicer parse_object_height over the last MiB: the largest ";<z>" on the
// line after ";BEFORE_LAYER_CHANGE" or the one after that; else the largest "G1 Z<z> F".
double moonraker_height(const std::string& g, bool comments_only, bool moves_only) {
    const std::string footer = g.size() > kMiB ? g.substr(g.size() - kMiB) : g;
    const std::vector<std::string> l = lines_of(footer);
    double best = -1;
    if (!moves_only)
        for (size_t i = 0; i + 1 < l.size(); ++i) {
            if (l[i] != ";BEFORE_LAYER_CHANGE") continue;
            static const carve::test::Regex z(R"(^;(\d+\.?\d*))");
            std::vector<std::string> m;
            for (size_t k = i + 1; k <= i + 2 && k < l.size(); ++k)
                if (z.search(l[k], &m)) {
                    best = std::max(best, std::stod(m[1]));
                    break;
                }
        }
    if (best >= 0 || comments_only) return best;
    // Moonraker's regex G1\sZ([0-9]*\.?[0-9]+)\sF, read by hand (a regex over a megabyte is
    // most of this test's time under the sanitizers).
    const auto space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
    const auto digit = [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; };
    for (size_t at = footer.find("G1"); at != std::string::npos; at = footer.find("G1", at + 1)) {
        size_t i = at + 2;
        if (i + 1 >= footer.size() || !space(footer[i]) || footer[i + 1] != 'Z') continue;
        const size_t from = i += 2;
        while (i < footer.size() && digit(footer[i])) ++i;
        size_t digits_from = from;  // the [0-9]+ part: after the point if there is one
        if (i < footer.size() && footer[i] == '.') {
            digits_from = ++i;
            while (i < footer.size() && digit(footer[i])) ++i;
        }
        if (i == digits_from || i + 1 >= footer.size() || !space(footer[i]) || footer[i + 1] != 'F')
            continue;
        best = std::max(best, std::stod(footer.substr(from, i - from)));
    }
    return best;
}

// The text between the last ";TYPE:Custom" and the configuration: the end G-code.
std::string end_part(const std::string& g) {
    const size_t at = g.rfind(";TYPE:Custom");
    return at == std::string::npos ? "" : g.substr(at, g.find("; filament used", at) - at);
}

// The extrusions of one layer as polylines, by ;TYPE: (a travel or a change of type ends one).
struct Polyline {
    std::string type;
    std::vector<std::pair<double, double>> points;
};

std::vector<Polyline> layer_polylines(const std::string& g, int layer) {
    std::vector<Polyline> out;
    int at = -1;
    std::string type;
    bool drawing = false;
    EAxis axis;
    double x = 0, y = 0;
    for (const std::string& l : lines_of(g)) {
        if (l.rfind(";LAYER:", 0) == 0) at = std::stoi(l.substr(7)), drawing = false;
        if (l.rfind(";TYPE:", 0) == 0) type = l.substr(6), drawing = false;
        if (l.empty() || l[0] == ';') continue;
        const std::string cmd = l.substr(0, l.find_first_of(" ;"));
        std::map<char, double> w = words(l);
        const double de = axis.step(cmd, w);
        if (cmd != "G1" && cmd != "G0") continue;
        const double nx = w.count('X') ? w['X'] : x, ny = w.count('Y') ? w['Y'] : y;
        const bool moves = nx != x || ny != y;
        if (moves && de > 0 && at == layer) {
            if (!drawing) out.push_back({type, {{x, y}}});
            out.back().points.emplace_back(nx, ny);
            drawing = true;
        } else if (moves) {
            drawing = false;
        }
        x = nx, y = ny;
    }
    return out;
}

double segment_distance(std::pair<double, double> p, std::pair<double, double> a,
                        std::pair<double, double> b) {
    const double dx = b.first - a.first, dy = b.second - a.second;
    const double len2 = dx * dx + dy * dy;
    double t = len2 > 0 ? ((p.first - a.first) * dx + (p.second - a.second) * dy) / len2 : 0;
    t = std::clamp(t, 0.0, 1.0);
    return std::hypot(p.first - a.first - t * dx, p.second - a.second - t * dy);
}

// The least distance between the centrelines of two sets of polylines, mm.
double distance(const std::vector<Polyline>& a, const std::vector<Polyline>& b) {
    double best = 1e18;
    auto one_way = [&](const std::vector<Polyline>& from, const std::vector<Polyline>& to) {
        for (const Polyline& p : from)
            for (const auto& q : p.points)
                for (const Polyline& o : to)
                    for (size_t i = 1; i < o.points.size(); ++i)
                        best = std::min(best, segment_distance(q, o.points[i - 1], o.points[i]));
    };
    one_way(a, b);
    one_way(b, a);
    return best;
}

std::vector<Polyline> of_type(const std::vector<Polyline>& all, const std::string& type) {
    std::vector<Polyline> out;
    for (const Polyline& p : all)
        if (p.type == type) out.push_back(p);
    return out;
}

}  // namespace

// Every preset heats the bed and the nozzle and waits for both before the first extrusion
// (the mk3s's intro line included), whatever its start macro does with the parameters.
TEST(PrinterStart, EveryPresetWaitsForBedAndNozzleBeforeTheFirstExtrusion) {
    for (const std::string printer : {"generic", "mk3s", "ender3", "klipper"}) {  // NOLINT
        const std::string g =
            slice(small_part(), "--cavities 1 --printer " + printer + " --thumbnails 8x8", printer);
        const Start s = read_start(g);
        ASSERT_GT(s.first_extrusion, 0) << printer;
        EXPECT_EQ(s.bed_waited, 60) << printer;
        EXPECT_EQ(s.nozzle_waited, 215) << printer;
        // The start G-code is typed as custom for the viewers, and so is the end.
        const size_t custom = g.find("\n;TYPE:Custom\n");
        ASSERT_NE(custom, std::string::npos) << printer;
        EXPECT_LT(custom, g.find("\n;LAYER:0\n")) << printer;
        EXPECT_GT(g.rfind("\n;TYPE:Custom\n"), g.rfind("\n;LAYER:")) << printer;
    }
    // Klipper: the waits come before PRINT_START, which the stock macros need.
    const std::string k = slice(small_part(), "--cavities 1 --printer klipper", "klipper2");
    EXPECT_LT(k.find("\nM190 S60"), k.find("\nPRINT_START"));
    EXPECT_LT(k.find("\nM109 S215"), k.find("\nPRINT_START"));
    // A start G-code that waits itself is not doubled (PrusaSlicer's rule).
    const fs::path ini = scratch() / "waits.ini";
    std::ofstream(ini) << "start_gcode = M190 S[first_layer_bed_temperature]\\nM109 "
                          "S[first_layer_temperature]\\nG28\n";
    const std::string own = slice(small_part(), "--cavities 1 --load " + ini.string(), "own");
    EXPECT_EQ(own.find("wait for bed"), std::string::npos);
    EXPECT_EQ(own.find("wait for nozzle"), std::string::npos);
    EXPECT_EQ(read_start(own).bed_waited, 60);
}

// Klipper runs a macro's body where the file calls it. The stock PRINT_START of Klipper's
// config/kit-voron2-250mm.cfg reads no parameters and turns the hot end off while the bed heats;
// the file must wait for the nozzle again after it, as PrusaSlicer's does (M109 after the start
// G-code). Before, klippy stopped at the first extrusion: "Extrude below minimum temp".
TEST(PrinterStart, KlipperWaitsForTheNozzleAfterAStockPrintStartThatTurnsItOff) {
    const std::string voron_print_start =
        "M117 Homing...\nG28\nG1 Z20 F3000\nM117 Preheat (Print)\nM104 S0\n";
    const std::string g = slice(small_part(), "--cavities 1 --printer klipper", "klipper_voron");
    std::string run;  // the file as Klipper executes it, the macro expanded
    for (const std::string& l : lines_of(g))
        run += l.rfind("PRINT_START", 0) == 0 ? voron_print_start : l + "\n";
    const Start s = read_start(run);
    ASSERT_GT(s.first_extrusion, 0);
    EXPECT_EQ(s.bed_waited, 60);
    EXPECT_EQ(s.nozzle_waited, 215);
    // A start G-code that waits for the nozzle itself is not followed by another wait.
    const fs::path ini = scratch() / "klipper_own.ini";
    std::ofstream(ini) << "gcode_flavor = klipper\nstart_gcode = PRINT_START\\nM109 "
                          "S[first_layer_temperature]\n";
    const std::string own = slice(small_part(), "--cavities 1 --load " + ini.string(), "k_own");
    EXPECT_EQ(own.find("wait for nozzle"), std::string::npos);
}

// The mk3s's intro line ends at Z 0.2 on the bed's edge: the nozzle retracts and lifts before
// it travels to the part, and the end G-code lifts it clear of the part and presents the bed.
TEST(PrinterStart, Mk3sRetractsAndLiftsAfterTheIntroLineAndEndsClearOfThePart) {
    const std::string g = slice(small_part(), "--cavities 1 --printer mk3s", "mk3s_ends");
    const std::vector<std::string> l = lines_of(g);
    size_t intro = 0;
    for (size_t i = 0; i < l.size(); ++i)
        if (l[i].find("; intro line") != std::string::npos) intro = i;
    ASSERT_GT(intro, 0u);
    bool retracted = false;
    double z = 0.2;
    for (size_t i = intro + 1; i < l.size(); ++i) {
        std::map<char, double> w = words(l[i]);
        if (l[i].rfind("G1 E-", 0) == 0) retracted = true;
        if (w.count('Z')) z = w['Z'];
        if ((l[i].rfind("G0 ", 0) == 0 || l[i].rfind("G1 ", 0) == 0) && (w.count('X'))) {
            EXPECT_TRUE(retracted) << l[i];
            EXPECT_GE(z, 0.4 - 1e-9) << l[i];
            break;
        }
    }
    const std::string end = end_part(g);
    static const carve::test::Regex lift(R"(\nG1 Z([0-9.]+) F)");
    std::vector<std::string> m;
    ASSERT_TRUE(lift.search(end, &m)) << end;
    EXPECT_NEAR(std::stod(m[1]), std::min(12.0 + 49, 210.0), 1e-6);
    EXPECT_NE(end.find("G1 X0 Y200"), std::string::npos);  // the bed forward
    // The generic end lifts 10 mm clear, within the printer's height.
    const std::string generic = end_part(slice(small_part(), "--cavities 1", "generic_end"));
    ASSERT_TRUE(lift.search(generic, &m)) << generic;
    EXPECT_NEAR(std::stod(m[1]), 22, 1e-6);
    const std::string low =
        end_part(slice(small_part(), "--cavities 1 --max-print-height 20", "generic_low"));
    ASSERT_TRUE(lift.search(low, &m)) << low;
    EXPECT_NEAR(std::stod(m[1]), 20, 1e-6);
}

// The height Moonraker shows is the model's, by either of its rules, on every model of the
// repository and every preset; every layer's Z move states its feed.
TEST(PrinterHosts, MoonrakerFindsTheModelsHeight) {
    for (const std::string& name : carve::test::first_under_sanitizers<std::string>(
             {"fandisk.stl", "elephant.stl", "man.stl"})) {
        const std::string model = carve::test::repo_model(name);
        const double height = model_height(model);
        for (const std::string printer : {"generic", "klipper"}) {  // NOLINT
            const std::string g = slice(model, "--cavities 1 --printer " + printer, "h" + name);
            // Within half a layer: the top layer is printed where the slices end.
            EXPECT_NEAR(moonraker_height(g, true, false), height, 0.1 + 1e-9) << name << printer;
            // The fallback, on the layers alone (an end G-code may lift with a feed, as
            // PrusaSlicer's own does: then the comments are what Moonraker reads).
            const std::string layers = g.substr(0, g.rfind("\n;TYPE:Custom\n"));
            EXPECT_NEAR(moonraker_height(layers, false, true), height, 0.1 + 1e-9)
                << name << printer;
        }
    }
}

// Jerk as M205 X Y Z E for PrusaSlicer's MK3S profile (not M205 J, which its firmware ignores),
// the filament and printer in the configuration block, M73 Q/S for the stealth mode, and the
// default thumbnails of PrusaSlicer's MK3S profile and of the klipper preset.
TEST(PrinterHosts, ProfileJerkFilamentStealthAndThumbnails) {
    const std::string ini = std::string(CARVE_SOURCE_DIR) + "/tests/data/prusa_mk3s.ini";
    const std::string g = slice(small_part(), "--cavities 1 --load " + ini, "mk3s_ini");
    EXPECT_NE(g.find("\nM205 X8 Y8 Z0.4 E4.5"), std::string::npos);
    EXPECT_EQ(g.find("\nM205 J"), std::string::npos);
    EXPECT_NE(g.find("\n; filament_type = PLA\n"), std::string::npos);
    EXPECT_NE(g.find("\n; filament_settings_id = \"Prusament PLA\"\n"), std::string::npos);
    EXPECT_NE(g.find("\n; filament_colour = #FF8000\n"), std::string::npos);
    EXPECT_NE(g.find("\n; printer_model = MK3S\n"), std::string::npos);
    EXPECT_NE(g.find("\nM73 Q0 S"), std::string::npos);  // the profile's silent_mode = 1
    EXPECT_NE(g.find("; thumbnail begin 160x120"), std::string::npos);
    const std::string mk3s = slice(small_part(), "--cavities 1 --printer mk3s", "mk3s_hosts");
    EXPECT_NE(mk3s.find("\nM73 Q100 S0\n"), std::string::npos);
    EXPECT_NE(mk3s.find("; thumbnail begin 220x124"), std::string::npos);
    EXPECT_NE(mk3s.find("\n; printer_model = MK3S\n"), std::string::npos);
    const std::string klipper = slice(small_part(), "--cavities 1 --printer klipper", "kl_hosts");
    EXPECT_NE(klipper.find("; thumbnail begin 400x300"), std::string::npos);
    EXPECT_EQ(klipper.find("\nM73 Q"), std::string::npos);
    EXPECT_EQ(slice(small_part(), "--cavities 1", "plain").find("; thumbnail begin"),
              std::string::npos);
}

// The skirt (one loop by default, PrusaSlicer's) and the brim lie on the first layer around the
// part at the distances asked, typed Skirt/Brim, printed before the part; the skirt rises
// --skirt-height layers.
TEST(PrinterFirstLayer, SkirtAndBrimLieAroundThePartAtTheirDistances) {
    constexpr double w = 0.4;
    {
        const std::string g = slice(small_part(), "--cavities 1", "skirt_default");
        const std::vector<Polyline> l0 = layer_polylines(g, 0);
        const std::vector<Polyline> skirt = of_type(l0, "Skirt/Brim");
        const std::vector<Polyline> wall = of_type(l0, "External perimeter");
        ASSERT_EQ(skirt.size(), 1u);
        ASSERT_FALSE(wall.empty());
        EXPECT_EQ(l0.front().type, "Skirt/Brim");
        // Centreline to centreline: the gap and half a line on each side.
        EXPECT_NEAR(distance(skirt, wall), 6 + w, 0.08);
        EXPECT_TRUE(of_type(layer_polylines(g, 1), "Skirt/Brim").empty());
    }
    const std::string g = slice(small_part(),
                                "--cavities 1 --brim-width 2 --skirts 2 --skirt-distance 3 "
                                "--skirt-height 3",
                                "brim");
    const std::vector<Polyline> l0 = layer_polylines(g, 0);
    const std::vector<Polyline> wall = of_type(l0, "External perimeter");
    std::vector<Polyline> loops = of_type(l0, "Skirt/Brim");
    // Two skirt loops, then the brim's five (2 mm of 0.4 mm lines), outermost first.
    ASSERT_EQ(loops.size(), 7u);
    const std::vector<Polyline> skirt(loops.begin(), loops.begin() + 2);
    const std::vector<Polyline> brim(loops.begin() + 2, loops.end());
    EXPECT_NEAR(distance({brim.back()}, wall), 0.1 + w, 0.02);  // brim_separation 0.1
    EXPECT_NEAR(distance({brim.front()}, wall), 0.1 + 4.5 * w + w / 2, 0.03);
    // The skirt 3 mm from the brim's outside edge.
    EXPECT_NEAR(distance({skirt[1]}, {brim.front()}), 3 + w, 0.06);
    EXPECT_NEAR(distance({skirt[0]}, {skirt[1]}), w, 0.02);
    EXPECT_EQ(of_type(layer_polylines(g, 2), "Skirt/Brim").size(), 2u);
    EXPECT_TRUE(of_type(layer_polylines(g, 3), "Skirt/Brim").empty());
    // From a profile too, under PrusaSlicer's keys.
    const fs::path ini = scratch() / "skirt.ini";
    std::ofstream(ini) << "skirts = 0\nbrim_width = 1\n";
    std::string err;
    const std::vector<Polyline> p = of_type(
        layer_polylines(
            slice(small_part(), "--cavities 1 --load " + ini.string(), "brim_ini", 0, &err), 0),
        "Skirt/Brim");
    EXPECT_EQ(p.size(), 2u);
    EXPECT_EQ(err.find("brim_width"), std::string::npos) << err;
    EXPECT_EQ(err.find("skirts"), std::string::npos) << err;
}

// A skirt or brim that would leave the bed is refused with one line, and no file is written.
TEST(PrinterFirstLayer, SkirtOrBrimOffTheBedIsAnError) {
    std::string err;
    slice(small_part(), "--cavities 1 --bed 38x32", "offbed", 1, &err);
    EXPECT_NE(err.find("skirt reaches"), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_FALSE(fs::exists(scratch() / "offbed.gcode"));
    slice(small_part(), "--cavities 1 --bed 38x32 --skirts 0 --brim-width 5", "offbed2", 1, &err);
    EXPECT_NE(err.find("brim reaches"), std::string::npos) << err;
    slice(small_part(), "--cavities 1 --bed 38x32 --skirts 0", "onbed", 0);
}

// With --copies, each copy's brim is its own unless they touch.
TEST(PrinterFirstLayer, BrimsOfCopiesJoinOnlyWhereTheyTouch) {
    std::vector<carve::test::StlTriangle> t;
    carve::test::add_box(t, 0, 0, 0, 20, 14, 4);
    const std::string box = carve::test::write_stl("brim_box.stl", t).string();
    auto brims = [&](const std::string& args, const std::string& name) {
        const std::vector<Polyline> l0 =
            layer_polylines(slice(box, "--skirts 0 --copies 2 --brim-width 2 " + args, name), 0);
        return of_type(l0, "Skirt/Brim");
    };
    EXPECT_EQ(brims("--copy-gap 6", "apart").size(), 10u);      // five loops around each
    EXPECT_EQ(brims("--copy-gap 0.5", "touching").size(), 5u);  // five around both
}

// --pause-at writes the flavour's pause before the first layer whose top reaches each height.
TEST(PrinterPause, PauseAtWritesTheCommandBeforeTheRightLayer) {
    for (const std::string printer : {"generic", "klipper"}) {  // NOLINT
        const std::string g =
            slice(small_part(), "--cavities 1 --printer " + printer + " --pause-at 2.1,10",
                  "pause" + printer);
        const std::string command = printer == "klipper" ? "PAUSE" : "M600";
        std::vector<int> before;  // the layer each pause comes in, before its first move
        int layer = -1;
        bool moved = false;
        for (const std::string& l : lines_of(g)) {
            if (l.rfind(";LAYER:", 0) == 0) layer = std::stoi(l.substr(7)), moved = false;
            // An X/Y move: the park before the command retracts and lifts (printers2_test).
            if ((l.rfind("G0 ", 0) == 0 || l.rfind("G1 ", 0) == 0) &&
                (l.find(" X") != std::string::npos || l.find(" Y") != std::string::npos))
                moved = true;
            if (l == command) {
                EXPECT_FALSE(moved) << printer;
                before.push_back(layer);
            }
        }
        // Layer i's top is 0.2 (i + 1): 2.1 is reached by layer 10 (2.2), 10 by layer 49.
        EXPECT_EQ(before, (std::vector<int>{10, 49})) << printer;
    }
    std::string err;
    slice(small_part(), "--pause-at 10,x", "pause_bad", 1, &err);
    EXPECT_NE(err.find("--pause-at"), std::string::npos) << err;
}

namespace {

// What the G-code says of each layer's extrusions: the Z they are printed at (G1 Z as written),
// the filament they feed, and for each ;WIDTH the filament per mm of path.
struct LayerMoves {
    std::map<int, std::vector<double>> z;  // the Zs extruded at, by layer
    double e_total = 0;                    // filament fed by moves in X/Y, mm
    double max_flow = 0;                   // the largest ;WIDTH x ;HEIGHT x F / 60, mm^3/s
    int extrusions = 0;
    std::map<std::string, double> e_per_mm_layer0;  // by ;WIDTH on layer 0
};

LayerMoves read_moves(const std::string& g) {
    LayerMoves m;
    int layer = -1;
    EAxis axis;
    double x = 0, y = 0, z = 0, f = 0, width = 0, height = 0;
    std::string width_text;
    for (const std::string& l : lines_of(g)) {
        if (l.rfind(";LAYER:", 0) == 0) layer = std::stoi(l.substr(7));
        if (l.rfind(";WIDTH:", 0) == 0) width = std::stod(l.substr(7)), width_text = l.substr(7);
        if (l.rfind(";HEIGHT:", 0) == 0) height = std::stod(l.substr(8));
        if (l.empty() || l[0] == ';') continue;
        const std::string cmd = l.substr(0, l.find_first_of(" ;"));
        std::map<char, double> w = words(l);
        const double de = axis.step(cmd, w);
        if (cmd != "G1" && cmd != "G0") continue;
        if (w.count('F')) f = w['F'];
        if (w.count('Z')) z = w['Z'];
        const double nx = w.count('X') ? w['X'] : x, ny = w.count('Y') ? w['Y'] : y;
        const double len = std::hypot(nx - x, ny - y);
        if (len > 0 && de > 0 && layer >= 0) {
            std::vector<double>& zs = m.z[layer];
            if (std::find(zs.begin(), zs.end(), z) == zs.end()) zs.push_back(z);
            m.e_total += de;
            m.max_flow = std::max(m.max_flow, width * height * f / 60);
            ++m.extrusions;
            if (layer == 0 && len > 1) m.e_per_mm_layer0[width_text] = de / len;
        }
        x = nx, y = ny;
    }
    return m;
}

// The bounding box of a layer's polylines of one type, as x0, y0, x1, y1; wall_box: its outer
// wall's (the centreline).
std::array<double, 4> type_box(const std::string& g, int layer, const std::string& type) {
    std::array<double, 4> b{1e9, 1e9, -1e9, -1e9};
    for (const Polyline& p : of_type(layer_polylines(g, layer), type))
        for (const auto& [x, y] : p.points)
            b = {std::min(b[0], x), std::min(b[1], y), std::max(b[2], x), std::max(b[3], y)};
    return b;
}

std::array<double, 4> wall_box(const std::string& g, int layer) {
    return type_box(g, layer, "External perimeter");
}

std::string flat_box() {
    std::vector<carve::test::StlTriangle> t;
    carve::test::add_box(t, 0, 0, 0, 20, 14, 3);
    return carve::test::write_stl("first_layer_box.stl", t).string();
}

constexpr double kFilamentArea = 3.14159265358979 * 0.875 * 0.875;

}  // namespace

// --first-layer-height: the first layer is printed at its height and every later layer stands
// on it at the layer height; its E per mm follows its own height and width
// (--first-layer-extrusion-width), the others' theirs. --z-offset shifts every Z written.
TEST(PrinterFirstLayer, FirstLayerHeightWidthAndZOffset) {
    const std::string box = flat_box();
    const LayerMoves plain = read_moves(slice(box, "--skirts 0", "fl_plain"));
    const std::string g = slice(box, "--skirts 0 --first-layer-height 0.3", "fl_03");
    const LayerMoves m = read_moves(g);
    // 3 mm: 0.3, then 0.5 .. 2.9 (the 14th layer's middle, 2.8, is under the top; 3.0's is not).
    ASSERT_EQ(m.z.size(), 14u);
    for (const auto& [layer, zs] : m.z) {
        ASSERT_EQ(zs.size(), 1u) << layer;
        EXPECT_NEAR(zs[0], 0.3 + 0.2 * layer, 1e-9) << layer;
    }
    EXPECT_NE(g.find("\n;Z:0.300\n;HEIGHT:0.300\n;LAYER:0\n"), std::string::npos);
    EXPECT_NE(g.find("\n;Z:0.500\n;HEIGHT:0.200\n;LAYER:1\n"), std::string::npos);
    EXPECT_NE(g.find("\n; first_layer_height = 0.3\n"), std::string::npos);
    EXPECT_EQ(plain.z.size(), 15u);
    EXPECT_NEAR(plain.z.at(0)[0], 0.2, 1e-9);

    const LayerMoves shifted =
        read_moves(slice(box, "--skirts 0 --first-layer-height 0.3 --z-offset 0.15", "fl_zoff"));
    ASSERT_EQ(shifted.z.size(), m.z.size());
    for (const auto& [layer, zs] : shifted.z) EXPECT_NEAR(zs[0], m.z.at(layer)[0] + 0.15, 1e-9);
    // The end G-code's lift counts the offset once ({z_offset+...}).
    const std::string low = slice(box, "--skirts 0 --z-offset -0.05", "fl_zneg");
    EXPECT_NEAR(read_moves(low).z.at(0)[0], 0.15, 1e-9);
    EXPECT_NE(low.find("\nG1 Z12.95 F600 ; lift clear"), std::string::npos);

    // E per mm of the outer wall (flow 1) on layer 0: its own width x height over the
    // filament's section.
    const LayerMoves wide = read_moves(slice(
        box, "--skirts 0 --first-layer-height 0.3 --first-layer-extrusion-width 0.5", "fl_w"));
    ASSERT_TRUE(wide.e_per_mm_layer0.count("0.500"));
    EXPECT_NEAR(wide.e_per_mm_layer0.at("0.500"), 0.5 * 0.3 / kFilamentArea, 2e-4);
    ASSERT_TRUE(plain.e_per_mm_layer0.count("0.400"));
    EXPECT_NEAR(plain.e_per_mm_layer0.at("0.400"), 0.4 * 0.2 / kFilamentArea, 2e-4);
}

// --extrusion-multiplier scales every E; the footer's filament follows.
TEST(PrinterFlow, ExtrusionMultiplierScalesEveryE) {
    const std::string plain = slice(small_part(), "--cavities 1", "em_plain");
    const std::string less =
        slice(small_part(), "--cavities 1 --extrusion-multiplier 0.9", "em_09");
    const LayerMoves a = read_moves(plain), b = read_moves(less);
    EXPECT_EQ(a.extrusions, b.extrusions);
    EXPECT_NEAR(b.e_total / a.e_total, 0.9, 1e-4);
    // The moves themselves are the same: only their E differs.
    EXPECT_EQ(a.z, b.z);
}

// --max-volumetric-speed: no extruding move's width x height x speed exceeds the cap (read as
// a viewer reads it: ;WIDTH, ;HEIGHT and F), and the estimate grows with the slower moves.
TEST(PrinterFlow, MaxVolumetricSpeedCapsEveryExtrusion) {
    const std::string plain = slice(small_part(), "--cavities 1", "mv_plain");
    const std::string capped = slice(small_part(), "--cavities 1 --max-volumetric-speed 2", "mv_2");
    const LayerMoves a = read_moves(plain), b = read_moves(capped);
    EXPECT_GT(a.max_flow, 4);
    EXPECT_LE(b.max_flow, 2 + 1e-9);
    EXPECT_GT(b.max_flow, 1.9);
    static const carve::test::Regex time(R"(\n;TIME:(\d+)\n)");
    std::vector<std::string> ta, tb;
    ASSERT_TRUE(time.search(plain, &ta));
    ASSERT_TRUE(time.search(capped, &tb));
    EXPECT_GT(std::stod(tb[1]), 1.1 * std::stod(ta[1]));
    // The filament's own cap from a profile holds when lower than the print's.
    const fs::path ini = scratch() / "cap.ini";
    std::ofstream(ini) << "max_volumetric_speed = 3\nfilament_max_volumetric_speed = 1.5\n";
    EXPECT_LE(
        read_moves(slice(small_part(), "--cavities 1 --load " + ini.string(), "mv_ini")).max_flow,
        1.5 + 1e-9);
}

// --elephant-foot-compensation shrinks the first layer's outer wall by its amount on every
// side and leaves the second's; --xy-size-compensation grows every layer's.
TEST(PrinterFirstLayer, ElephantFootAndXySizeCompensation) {
    const std::string box = flat_box();
    const std::string plain = slice(box, "--skirts 0", "ef_plain");
    const std::string foot = slice(box, "--skirts 0 --elephant-foot-compensation 0.3", "ef_03");
    const std::string grown = slice(box, "--skirts 0 --xy-size-compensation 0.2", "xy_02");
    const std::array<double, 4> p0 = wall_box(plain, 0), p1 = wall_box(plain, 1),
                                pt = wall_box(plain, 14);
    const std::array<double, 4> f0 = wall_box(foot, 0), f1 = wall_box(foot, 1);
    const std::array<double, 4> g0 = wall_box(grown, 0), g1 = wall_box(grown, 1),
                                gt = wall_box(grown, 14);
    EXPECT_NEAR(p0[2] - p0[0], 20 - 0.4, 0.01);  // the wall's centreline, half a line in
    for (int k = 0; k < 4; ++k) {
        const double out = k < 2 ? -1 : 1;  // outwards on this side
        EXPECT_NEAR(f0[k], p0[k] - out * 0.3, 0.01) << k;
        EXPECT_NEAR(f1[k], p1[k], 1e-9) << k;
        EXPECT_NEAR(g0[k], p0[k] + out * 0.2, 0.01) << k;
        EXPECT_NEAR(g1[k], p1[k] + out * 0.2, 0.01) << k;
        EXPECT_NEAR(gt[k], pt[k] + out * 0.2, 0.01) << k;
    }
}

// The same keys in a PrusaSlicer profile give the very G-code the options give, and none of
// them is named as ignored.
TEST(PrinterFirstLayer, ProfileKeysGiveTheOptionsGcode) {
    const fs::path ini = scratch() / "first_layer.ini";
    // A first layer's width in % is of the first layer's height (PrusaSlicer's ratio_over).
    std::ofstream(ini) << "first_layer_height = 0.25\nfirst_layer_extrusion_width = 200%\n"
                          "extrusion_multiplier = 0.95\nmax_volumetric_speed = 0\n"
                          "filament_max_volumetric_speed = 4\nelefant_foot_compensation = 0.2\n"
                          "xy_size_compensation = 0.05\nz_offset = 0.1\n";
    std::string err;
    const std::string from_ini =
        slice(small_part(), "--cavities 1 --load " + ini.string(), "fl_ini", 0, &err);
    const std::string from_options = slice(small_part(),
                                           "--cavities 1 --first-layer-height 0.25 "
                                           "--first-layer-extrusion-width 0.5 "
                                           "--extrusion-multiplier 0.95 --max-volumetric-speed 4 "
                                           "--elephant-foot-compensation 0.2 "
                                           "--xy-size-compensation 0.05 --z-offset 0.1",
                                           "fl_options");
    ASSERT_FALSE(from_ini.empty());
    EXPECT_TRUE(from_ini == from_options);
    EXPECT_EQ(err.find("ignores"), std::string::npos) << err;
    for (const char* key : {"; z_offset = 0.1", "; extrusion_multiplier = 0.95",
                            "; elefant_foot_compensation = 0.2", "; max_volumetric_speed = 4"})
        EXPECT_NE(from_ini.find(std::string("\n") + key + "\n"), std::string::npos) << key;
}

// Nonsense is refused with one line and no file: negative or too high a first layer (PrusaSlicer
// refuses one higher than the nozzle), a multiplier of 0, a negative cap, a Z offset that puts
// the first layer into the bed, the same from a profile.
TEST(PrinterFirstLayer, BadValuesAreRefused) {
    const std::string box = flat_box();
    const std::vector<std::pair<std::string, std::string>> bad = {
        {"--first-layer-height -0.1", "--first-layer-height"},
        {"--first-layer-height 0.5", "nozzle"},
        {"--first-layer-height 0.001", "too thin"},
        {"--first-layer-height 0.35 --first-layer-extrusion-width 0.3", "line width"},
        {"--extrusion-multiplier 0", "--extrusion-multiplier"},
        {"--extrusion-multiplier -1", "--extrusion-multiplier"},
        {"--max-volumetric-speed -1", "--max-volumetric-speed"},
        {"--max-volumetric-speed 0.01", "too low"},
        {"--elephant-foot-compensation -0.1", "--elephant-foot-compensation"},
        {"--xy-size-compensation 9", "--xy-size-compensation"},
        {"--z-offset -0.2", "into the bed"},
        {"--first-layer-extrusion-width 0.01", "too thin"},
    };
    int n = 0;
    for (const auto& [args, says] : bad) {
        std::string err;
        const std::string name = "bad" + std::to_string(n++);
        slice(box, args, name, 1, &err);
        EXPECT_NE(err.find(says), std::string::npos) << args << ": " << err;
        EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << args << ": " << err;
        EXPECT_FALSE(fs::exists(scratch() / (name + ".gcode"))) << args;
    }
    for (const std::string line :  // NOLINT
         {"first_layer_height = 0.6", "extrusion_multiplier = 0", "z_offset = -1",
          "filament_max_volumetric_speed = -2"}) {
        const fs::path ini = scratch() / "bad_first_layer.ini";
        std::ofstream(ini) << line << "\n";
        std::string err;
        slice(box, "--load " + ini.string(), "bad_ini", 1, &err);
        EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << line << ": " << err;
        EXPECT_FALSE(fs::exists(scratch() / "bad_ini.gcode")) << line;
    }
}

// The run's material figures (the stats' material by feature, summed from the paths) follow the
// real first layer and the multiplier: they add up to what the G-code extrudes, as at the
// defaults.
TEST(PrinterFlow, MaterialFiguresFollowTheFirstLayerAndTheMultiplier) {
    setenv("SOURCE_DATE_EPOCH", "1767225600", 1);
    auto figures = [](const std::string& args, const std::string& name) {
        const fs::path out = scratch() / (name + ".gcode"), json = scratch() / (name + ".json");
        const carve::test::CarveRun r =
            run_carve("slice " + fandisk() + " -o " + out.string() + " -q --skirts 0 --stats " +
                      json.string() + " " + args);
        EXPECT_EQ(r.status, 0) << r.err;
        const nlohmann::json j = nlohmann::json::parse(read(json));
        double by_feature = 0;
        for (const auto& [k, v] : j["material_by_feature"].items())
            if (v.is_number()) by_feature += v.get<double>();
        return std::pair{by_feature, j["extruded_volume_mm3"].get<double>()};
    };
    const auto [plain_features, plain] = figures("", "mf_plain");
    const auto [features, extruded] = figures(
        "--first-layer-height 0.3 --first-layer-extrusion-width 0.6 --extrusion-multiplier 0.9",
        "mf_first");
    EXPECT_NEAR(plain_features, plain, 1e-3 * plain);
    EXPECT_NEAR(features, extruded, 1e-3 * extruded);
    EXPECT_LT(extruded, 0.92 * plain);
}

// --raft-layers: the raft's layers come first, its first at the first layer's height, typed as
// supports (the top one as their interface); the model's first layer is a normal layer
// raft_contact_distance above the raft's top, and every later layer stands on it. The raft
// reaches raft_expansion beyond the model (its first layer raft_first_layer_expansion more),
// nothing of it hangs by `carve check`'s measure, its material is counted apart, and the
// --pause-at heights stay the model's.
TEST(PrinterRaft, RaftLayersLieUnderTheModelAndTheModelStartsAboveTheGap) {
    const std::string box = flat_box();
    const fs::path stats = scratch() / "raft.json";
    const std::string g =
        slice(box,
              "--skirts 0 --raft-layers 3 --first-layer-height 0.3 --pause-at 1 --stats " +
                  stats.string(),
              "raft");
    const LayerMoves m = read_moves(g);
    // 3 raft layers, then the box's 15 layers of 0.2 mm (its first is no first layer).
    ASSERT_EQ(m.z.size(), 18u);
    const double raft_z[] = {0.3, 0.5, 0.7};
    for (const auto& [layer, zs] : m.z) {
        ASSERT_EQ(zs.size(), 1u) << layer;
        const double want = layer < 3 ? raft_z[layer] : 0.7 + 0.1 + 0.2 * (layer - 2);
        EXPECT_NEAR(zs[0], want, 1e-9) << layer;
    }
    EXPECT_NE(g.find("\n;Z:0.300\n;HEIGHT:0.300\n;LAYER:0\n"), std::string::npos);
    // The model's first layer is a layer height, as PrusaSlicer states it (its flow fills the
    // 0.1 mm gap under it too).
    EXPECT_NE(g.find("\n;Z:1.000\n;HEIGHT:0.200\n;LAYER:3\n"), std::string::npos);
    EXPECT_NE(g.find("\n;Z:1.200\n;HEIGHT:0.200\n;LAYER:4\n"), std::string::npos);
    EXPECT_NE(g.find("\n;LAYER_COUNT:18\n"), std::string::npos);
    for (int layer = 0; layer < 3; ++layer) {
        for (const Polyline& p : layer_polylines(g, layer))
            EXPECT_TRUE(p.type == "Support material" ||
                        (layer == 2 && p.type == "Support material interface"))
                << layer << ": " << p.type;
    }
    EXPECT_FALSE(of_type(layer_polylines(g, 2), "Support material interface").empty());
    EXPECT_FALSE(of_type(layer_polylines(g, 3), "External perimeter").empty());
    // The raft's outer loop (centreline half a line inside its edge) around the model's outer
    // wall (half a line inside the model): 1.5 mm out, the first layer 3 mm more.
    const std::array<double, 4> wall = wall_box(g, 3);
    const std::array<double, 4> base = type_box(g, 0, "Support material");
    const std::array<double, 4> upper = type_box(g, 1, "Support material");
    for (int k = 0; k < 4; ++k) {
        const double out = k < 2 ? -1 : 1;
        EXPECT_NEAR((base[k] - wall[k]) * out, 4.5, 0.05) << k;
        EXPECT_NEAR((upper[k] - wall[k]) * out, 1.5, 0.05) << k;
    }
    // The pause at 1 mm of the model: its layer 4 (top 1.0 above the model's bottom), the
    // print's layer 7.
    const size_t pause = g.find("\n;PAUSE_AT 1\n");
    ASSERT_NE(pause, std::string::npos);
    EXPECT_LT(g.find("\n;LAYER:7\n"), pause);
    EXPECT_GT(g.find("\n;LAYER:8\n"), pause);
    // Nothing hangs, and the model sits on the raft where the check places it by itself.
    const fs::path file = scratch() / "raft.gcode";
    const carve::test::CarveRun check =
        run_carve("check " + file.string() + " --mesh " + box + " --strict --json");
    EXPECT_EQ(check.status, 0) << check.out << check.err;
    const nlohmann::json j = nlohmann::json::parse(check.out);
    // The raft's layers have no slice of the model to be far from: the farthest extrusion
    // outside it is a number for the model's layers alone (it was "inf", null in JSON).
    ASSERT_TRUE(j["max_outside_model_mm"].is_number()) << j["max_outside_model_mm"];
    EXPECT_LT(j["max_outside_model_mm"].get<double>(), 0.5);
    // Its Z less its ;HEIGHT: above the raft's top by the gap, where carve put it.
    EXPECT_NEAR(j["mesh_offset_mm"][2].get<double>(), 0.8, 1e-6);
    EXPECT_LT(j["hanging_inside_mm2"].get<double>() + j["hanging_overhang_mm2"].get<double>() +
                  j["hanging_support_mm2"].get<double>(),
              0.01)
        << check.out;
    // The raft's material apart from the model's, and in the print's.
    const nlohmann::json s = nlohmann::json::parse(read(stats));
    const double raft_mm3 = s["material_by_feature"]["raft_mm3"].get<double>();
    EXPECT_GT(raft_mm3, 3 * 20 * 14 * 0.2 * 0.4);  // three layers, the upper ones sparse
    EXPECT_NEAR(m.e_total * kFilamentArea, s["extruded_volume_mm3"].get<double>(), 1.0);
    // Against the box without a raft: the raft, and the 0.1 mm more of the first layer over
    // at most the box's area and its walls.
    const LayerMoves plain = read_moves(slice(box, "--skirts 0", "raft_none"));
    const double more = (m.e_total - plain.e_total) * kFilamentArea;
    EXPECT_GT(more, raft_mm3);
    EXPECT_LT(more, raft_mm3 + 0.1 * 20 * 14 * 1.1);
}

// The skirt goes around the raft's first layer; PrusaSlicer's keys set the raft from a
// profile; a raft that leaves the bed, or lifts the model above the printer's height, is
// refused.
TEST(PrinterRaft, SkirtProfileKeysAndLimits) {
    constexpr double w = 0.4;
    const std::string box = flat_box();
    const std::string g = slice(box, "--raft-layers 2", "raft_skirt");
    const std::vector<Polyline> l0 = layer_polylines(g, 0);
    const std::vector<Polyline> skirt = of_type(l0, "Skirt/Brim");
    const std::vector<Polyline> raft = of_type(l0, "Support material");
    ASSERT_EQ(skirt.size(), 1u);
    ASSERT_FALSE(raft.empty());
    EXPECT_NEAR(distance(skirt, {raft.front()}), 6 + w, 0.08);

    const fs::path ini = scratch() / "raft.ini";
    std::ofstream(ini) << "raft_layers = 2\nraft_contact_distance = 0.2\nraft_expansion = 2\n"
                          "raft_first_layer_expansion = 1\n";
    std::string err;
    const std::string p = slice(box, "--skirts 0 --load " + ini.string(), "raft_ini", 0, &err);
    EXPECT_EQ(err.find("raft"), std::string::npos) << err;
    const LayerMoves m = read_moves(p);
    ASSERT_GE(m.z.size(), 3u);
    EXPECT_NEAR(m.z.at(2)[0], 0.4 + 0.2 + 0.2, 1e-9);
    const std::array<double, 4> wall = wall_box(p, 2), base = type_box(p, 0, "Support material");
    EXPECT_NEAR(wall[0] - base[0], 3, 0.05);

    // 3 mm of box on 0.7 mm of raft and a 0.1 mm gap: 3.8 mm.
    slice(box, "--max-print-height 3.5", "raft_low");
    slice(box, "--max-print-height 3.5 --raft-layers 3", "raft_tall", 1, &err);
    EXPECT_NE(err.find("on its raft"), std::string::npos) << err;
    slice(box, "--raft-layers 1 --raft-first-layer-expansion 100 --skirts 0", "raft_wide", 1, &err);
    EXPECT_NE(err.find("the raft reaches"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(scratch() / "raft_wide.gcode"));
}

namespace {

// A run refused with one line naming `says`, exit 1, and no G-code left.
void expect_refused(const std::string& model, const std::string& args, const std::string& says) {
    static int n = 0;
    const std::string name = "refused52_" + std::to_string(n++);
    std::string err;
    slice(model, args, name, 1, &err);
    EXPECT_NE(err.find(says), std::string::npos) << args << ": " << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << args << ": " << err;
    EXPECT_FALSE(fs::exists(scratch() / (name + ".gcode"))) << args;
}

std::string ini52(const std::string& name, const std::string& text) {
    const fs::path ini = scratch() / (name + ".ini");
    std::ofstream(ini) << text;
    return "--load " + ini.string();
}

}  // namespace

// Issue #52: every Z written (the layers with --z-offset, travel lifts, the end G-code's lift)
// is within --max-print-height, a first layer the offset leaves thinner than a quarter of the
// layer height is refused, and a pause above the model too; from a profile as from the options.
TEST(PrinterHeight, EveryZWrittenIsWithinThePrinter) {
    const std::string part = small_part();  // 12 mm tall
    expect_refused(part, "--cavities 1 --z-offset 5 --max-print-height 15", "--z-offset 5");
    expect_refused(part, "--cavities 1 " + ini52("z52", "z_offset = 5\nmax_print_height = 15\n"),
                   "--z-offset 5");
    // Two towers: the travel between them retracts and lifts.
    std::vector<carve::test::StlTriangle> t;
    carve::test::add_box(t, 0, 0, 0, 10, 10, 12);
    carve::test::add_box(t, 20, 0, 0, 30, 10, 12);
    const std::string towers = carve::test::write_stl("towers52.stl", t).string();
    expect_refused(towers, "--cavities 1 --z-hop 5 --max-print-height 14", "--z-hop");
    expect_refused(
        towers, "--cavities 1 " + ini52("hop52", "retract_lift = 5\n") + " --max-print-height 14",
        "retract_lift");
    EXPECT_FALSE(slice(towers, "--cavities 1 --z-hop 5 --max-print-height 17", "hop52_ok").empty());
    expect_refused(
        part,
        "--cavities 1 --max-print-height 30 " + ini52("end52", "end_gcode = G91\\nG1 Z20\\nG90\n"),
        "end_gcode");
    expect_refused(part, "--cavities 1 --z-offset -0.16", "quarter");
    expect_refused(part, "--cavities 1 " + ini52("zneg52", "z_offset = -0.16\n"), "quarter");
    expect_refused(part, "--cavities 1 --pause-at 13", "--pause-at 13");
    // Within the printer: the end G-code's lift stops at its height, the offset counted.
    const std::string g = slice(part, "--cavities 1 --z-offset 2 --max-print-height 20", "z52_ok");
    double top = 0;
    for (const std::string& l : lines_of(g))
        if (l.rfind("G1 ", 0) == 0 && words(l).count('Z')) top = std::max(top, words(l)['Z']);
    EXPECT_NEAR(top, 20, 1e-9);
    // A quarter of the layer height is enough.
    EXPECT_FALSE(slice(part, "--cavities 1 --z-offset -0.15", "z52_quarter").empty());
}

// Issue #52: the options that shape extrusion within what a printer prints, the same from a
// profile: the multiplier from 0.5 to 2, the first layer's width under 3 nozzles (1500 % of a
// 0.2 mm first layer is 3 mm), a raft's gap at most the layer height, and a volumetric cap that
// holds the widest line under 5 mm/s.
TEST(PrinterFlow, ExtrusionOptionsStayWithinWhatAPrinterPrints) {
    const std::string part = small_part();
    expect_refused(part, "--cavities 1 --extrusion-multiplier 5", "from 0.5 to 2");
    expect_refused(part, "--cavities 1 --extrusion-multiplier 0.4", "from 0.5 to 2");
    expect_refused(part, "--cavities 1 " + ini52("em52", "extrusion_multiplier = 5\n"),
                   "from 0.5 to 2");
    expect_refused(part, "--cavities 1 --first-layer-extrusion-width 3", "3 nozzle widths");
    expect_refused(part, "--cavities 1 " + ini52("flw52", "first_layer_extrusion_width = 1500%\n"),
                   "3 nozzle widths");
    expect_refused(part, "--cavities 1 --raft-layers 2 --raft-contact-distance 2",
                   "2.2 mm tall line");
    expect_refused(
        part, "--cavities 1 " + ini52("raft52", "raft_layers = 2\nraft_contact_distance = 2\n"),
        "2.2 mm tall line");
    const std::string big = "--cavities 1 --nozzle 3 --layer-height 2 --first-layer-height 2 ";
    expect_refused(part, big + "--max-volumetric-speed 0.1", "0.0167 mm/s");
    expect_refused(part, big + ini52("mvs52", "filament_max_volumetric_speed = 0.1\n"),
                   "0.0167 mm/s");
    // The edges themselves print.
    EXPECT_FALSE(slice(part,
                       "--cavities 1 --extrusion-multiplier 2 --raft-layers 1 "
                       "--raft-contact-distance 0.2 --first-layer-extrusion-width 1.1",
                       "flow52_ok")
                     .empty());
}

// Issue #52: a skirt taller than one layer stays clear of the model at every height it rises
// beside: on a plate wider than its foot it follows the plate (a draft shield), from a profile's
// skirt_height as from the option, and a one-layer skirt keeps to the foot.
TEST(PrinterFirstLayer, ATallSkirtStaysClearOfTheModelAtEveryHeight) {
    std::vector<carve::test::StlTriangle> t;
    carve::test::add_box(t, 10, 10, 0, 20, 20, 2);  // the foot
    carve::test::add_box(t, 0, 0, 2, 30, 30, 5);    // a plate 10 mm wider on every side
    const std::string model = carve::test::write_stl("skirt52.stl", t).string();
    const std::string g = slice(model, "--cavities 1 --skirt-height 20", "skirt52");
    for (int layer = 0; layer < 20; ++layer) {
        const std::vector<Polyline> l = layer_polylines(g, layer);
        const std::vector<Polyline> skirt = of_type(l, "Skirt/Brim"),
                                    wall = of_type(l, "External perimeter");
        ASSERT_FALSE(skirt.empty()) << layer;
        ASSERT_FALSE(wall.empty()) << layer;
        EXPECT_GE(distance(skirt, wall), 6) << layer;
    }
    // The first layer's distance is now from the plate above, not the foot.
    EXPECT_GT(distance(of_type(layer_polylines(g, 0), "Skirt/Brim"),
                       of_type(layer_polylines(g, 0), "External perimeter")),
              15);
    EXPECT_TRUE(
        g == slice(model, "--cavities 1 " + ini52("sk52", "skirt_height = 20\n"), "skirt52_ini"));
    const std::string one = slice(model, "--cavities 1", "skirt52_one");
    EXPECT_NEAR(distance(of_type(layer_polylines(one, 0), "Skirt/Brim"),
                         of_type(layer_polylines(one, 0), "External perimeter")),
                6.4, 0.1);
}

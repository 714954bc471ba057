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
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "support/carve_run.hpp"
#include "support/models.hpp"
#include "support/stl_boxes.hpp"

namespace fs = std::filesystem;
using carve::test::read;
using carve::test::run_carve;
using carve::test::scratch;

namespace {

constexpr size_t kMiB = 1 << 20;

std::string slice(const std::string& model, const std::string& args, const std::string& name,
                  int want_status = 0, std::string* err = nullptr) {
    setenv("SOURCE_DATE_EPOCH", "1767225600", 1);
    const fs::path out = scratch() / (name + ".gcode");
    const carve::test::CarveRun r =
        run_carve("slice " + model + " -o " + out.string() + " -q " + args);
    EXPECT_EQ(r.status, want_status) << r.err;
    if (err) *err = r.err;
    return r.status == 0 ? read(out) : std::string();
}

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> out;
    std::stringstream in(text);
    for (std::string l; std::getline(in, l);) out.push_back(l);
    return out;
}

// The words of a G-code line before its comment: 'G' -> 1, 'X' -> 10.5 ...
std::map<char, double> words(const std::string& line) {
    std::map<char, double> w;
    std::string code = line.substr(0, line.find(';'));
    std::stringstream in(code);
    for (std::string t; in >> t;)
        if (t.size() >= 2 && std::isalpha(static_cast<unsigned char>(t[0]))) {
            try {
                w[char(std::toupper(t[0]))] = std::stod(t.substr(1));
            } catch (...) {
            }
        }
    return w;
}

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
    bool relative = false;
    double e = 0;
    int n = 0;
    for (const std::string& l : lines_of(g)) {
        ++n;
        if (l.empty() || l[0] == ';') continue;
        std::map<char, double> w = words(l);
        const std::string cmd = l.substr(0, l.find_first_of(" ;"));
        if (cmd == "M83") relative = true;
        if (cmd == "M82") relative = false;
        if (cmd == "M190") s.bed_waited = std::max(w['S'], w['R']);
        if (cmd == "M109") s.nozzle_waited = std::max(w['S'], w['R']);
        if (cmd == "G92" && w.count('E')) e = w['E'];
        if ((cmd == "G1" || cmd == "G0") && w.count('E')) {
            const double d = relative ? w['E'] : w['E'] - e;
            e = relative ? e + w['E'] : w['E'];
            if (d > 0 && (w.count('X') || w.count('Y'))) {
                s.first_extrusion = n;
                return s;
            }
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
            static const std::regex z(R"(^;(\d+\.?\d*))");
            std::smatch m;
            for (size_t k = i + 1; k <= i + 2 && k < l.size(); ++k)
                if (std::regex_search(l[k], m, z)) {
                    best = std::max(best, std::stod(m[1]));
                    break;
                }
        }
    if (best >= 0 || comments_only) return best;
    static const std::regex move(R"(G1\sZ([0-9]*\.?[0-9]+)\sF)");
    for (auto it = std::sregex_iterator(footer.begin(), footer.end(), move);
         it != std::sregex_iterator(); ++it)
        best = std::max(best, std::stod((*it)[1]));
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
    bool relative = false, drawing = false;
    double x = 0, y = 0, e = 0;
    for (const std::string& l : lines_of(g)) {
        if (l.rfind(";LAYER:", 0) == 0) at = std::stoi(l.substr(7)), drawing = false;
        if (l.rfind(";TYPE:", 0) == 0) type = l.substr(6), drawing = false;
        if (l.empty() || l[0] == ';') continue;
        const std::string cmd = l.substr(0, l.find_first_of(" ;"));
        std::map<char, double> w = words(l);
        if (cmd == "M83") relative = true;
        if (cmd == "M82") relative = false;
        if (cmd == "G92" && w.count('E')) e = w['E'];
        if (cmd != "G1" && cmd != "G0") continue;
        const double nx = w.count('X') ? w['X'] : x, ny = w.count('Y') ? w['Y'] : y;
        double de = 0;
        if (w.count('E')) {
            de = relative ? w['E'] : w['E'] - e;
            e = relative ? e + w['E'] : w['E'];
        }
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
            slice(fandisk(), "--cavities 1 --printer " + printer + " --thumbnails 8x8", printer);
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
    const std::string k = slice(fandisk(), "--cavities 1 --printer klipper", "klipper2");
    EXPECT_LT(k.find("\nM190 S60"), k.find("\nPRINT_START"));
    EXPECT_LT(k.find("\nM109 S215"), k.find("\nPRINT_START"));
    // A start G-code that waits itself is not doubled (PrusaSlicer's rule).
    const fs::path ini = scratch() / "waits.ini";
    std::ofstream(ini) << "start_gcode = M190 S[first_layer_bed_temperature]\\nM109 "
                          "S[first_layer_temperature]\\nG28\n";
    const std::string own = slice(fandisk(), "--cavities 1 --load " + ini.string(), "own");
    EXPECT_EQ(own.find("wait for bed"), std::string::npos);
    EXPECT_EQ(own.find("wait for nozzle"), std::string::npos);
    EXPECT_EQ(read_start(own).bed_waited, 60);
}

// The mk3s's intro line ends at Z 0.2 on the bed's edge: the nozzle retracts and lifts before
// it travels to the part, and the end G-code lifts it clear of the part and presents the bed.
TEST(PrinterStart, Mk3sRetractsAndLiftsAfterTheIntroLineAndEndsClearOfThePart) {
    const std::string g = slice(fandisk(), "--cavities 1 --printer mk3s", "mk3s_ends");
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
    static const std::regex lift(R"(\nG1 Z([0-9.]+) F)");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(end, m, lift)) << end;
    EXPECT_NEAR(std::stod(m[1]), std::min(80.0 + 49, 210.0), 1e-6);
    EXPECT_NE(end.find("G1 X0 Y200"), std::string::npos);  // the bed forward
    // The generic end lifts 10 mm clear, within the printer's height.
    const std::string generic = end_part(slice(fandisk(), "--cavities 1", "generic_end"));
    ASSERT_TRUE(std::regex_search(generic, m, lift)) << generic;
    EXPECT_NEAR(std::stod(m[1]), 90, 1e-6);
    const std::string low =
        end_part(slice(fandisk(), "--cavities 1 --max-print-height 85", "generic_low"));
    ASSERT_TRUE(std::regex_search(low, m, lift)) << low;
    EXPECT_NEAR(std::stod(m[1]), 85, 1e-6);
}

// The height Moonraker shows is the model's, by either of its rules, on every model of the
// repository and every preset; every layer's Z move states its feed.
TEST(PrinterHosts, MoonrakerFindsTheModelsHeight) {
    for (const std::string name : {"fandisk.stl", "elephant.stl", "man.stl"}) {  // NOLINT
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
    const std::string g = slice(fandisk(), "--cavities 1 --load " + ini, "mk3s_ini");
    EXPECT_NE(g.find("\nM205 X8 Y8 Z0.4 E4.5"), std::string::npos);
    EXPECT_EQ(g.find("\nM205 J"), std::string::npos);
    EXPECT_NE(g.find("\n; filament_type = PLA\n"), std::string::npos);
    EXPECT_NE(g.find("\n; filament_settings_id = \"Prusament PLA\"\n"), std::string::npos);
    EXPECT_NE(g.find("\n; filament_colour = #FF8000\n"), std::string::npos);
    EXPECT_NE(g.find("\n; printer_model = MK3S\n"), std::string::npos);
    EXPECT_NE(g.find("\nM73 Q0 S"), std::string::npos);  // the profile's silent_mode = 1
    EXPECT_NE(g.find("; thumbnail begin 160x120"), std::string::npos);
    const std::string mk3s = slice(fandisk(), "--cavities 1 --printer mk3s", "mk3s_hosts");
    EXPECT_NE(mk3s.find("\nM73 Q100 S0\n"), std::string::npos);
    EXPECT_NE(mk3s.find("; thumbnail begin 220x124"), std::string::npos);
    EXPECT_NE(mk3s.find("\n; printer_model = MK3S\n"), std::string::npos);
    const std::string klipper = slice(fandisk(), "--cavities 1 --printer klipper", "kl_hosts");
    EXPECT_NE(klipper.find("; thumbnail begin 400x300"), std::string::npos);
    EXPECT_EQ(klipper.find("\nM73 Q"), std::string::npos);
    EXPECT_EQ(slice(fandisk(), "--cavities 1", "plain").find("; thumbnail begin"),
              std::string::npos);
}

// The skirt (one loop by default, PrusaSlicer's) and the brim lie on the first layer around the
// part at the distances asked, typed Skirt/Brim, printed before the part; the skirt rises
// --skirt-height layers.
TEST(PrinterFirstLayer, SkirtAndBrimLieAroundThePartAtTheirDistances) {
    constexpr double w = 0.4;
    {
        const std::string g = slice(fandisk(), "--cavities 1", "skirt_default");
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
    const std::string g = slice(fandisk(),
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
            slice(fandisk(), "--cavities 1 --load " + ini.string(), "brim_ini", 0, &err), 0),
        "Skirt/Brim");
    EXPECT_EQ(p.size(), 2u);
    EXPECT_EQ(err.find("brim_width"), std::string::npos) << err;
    EXPECT_EQ(err.find("skirts"), std::string::npos) << err;
}

// A skirt or brim that would leave the bed is refused with one line, and no file is written.
TEST(PrinterFirstLayer, SkirtOrBrimOffTheBedIsAnError) {
    std::string err;
    slice(fandisk(), "--cavities 1 --bed 80x50", "offbed", 1, &err);
    EXPECT_NE(err.find("skirt reaches"), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_FALSE(fs::exists(scratch() / "offbed.gcode"));
    slice(fandisk(), "--cavities 1 --bed 80x50 --skirts 0 --brim-width 5", "offbed2", 1, &err);
    EXPECT_NE(err.find("brim reaches"), std::string::npos) << err;
    slice(fandisk(), "--cavities 1 --bed 80x50 --skirts 0", "onbed", 0);
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
            slice(fandisk(), "--cavities 1 --printer " + printer + " --pause-at 10.1,40",
                  "pause" + printer);
        const std::string command = printer == "klipper" ? "PAUSE" : "M600";
        std::vector<int> before;  // the layer each pause comes in, before its first move
        int layer = -1;
        bool moved = false;
        for (const std::string& l : lines_of(g)) {
            if (l.rfind(";LAYER:", 0) == 0) layer = std::stoi(l.substr(7)), moved = false;
            if (l.rfind("G0 ", 0) == 0 || l.rfind("G1 ", 0) == 0) moved = true;
            if (l == command) {
                EXPECT_FALSE(moved) << printer;
                before.push_back(layer);
            }
        }
        // Layer i's top is 0.2 (i + 1): 10.1 is reached by layer 50 (10.2), 40 by layer 199.
        EXPECT_EQ(before, (std::vector<int>{50, 199})) << printer;
    }
    std::string err;
    slice(fandisk(), "--pause-at 10,x", "pause_bad", 1, &err);
    EXPECT_NE(err.find("--pause-at"), std::string::npos) << err;
}

// Printers, round two (issue #51), read from the G-code as the machines read it: the klipper
// preset against Klipper's stock config/kit-voron2-250mm.cfg (bed, accelerations), the skirt,
// brim and raft outside every object's label block, the park around --pause-at, M73's
// stealth figures on the mk3s, and what PrusaSlicer's viewer is told of the producer.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "support/carve_run.hpp"
#include "support/gcode_slices.hpp"
#include "support/stl_boxes.hpp"

namespace fs = std::filesystem;
using carve::test::read;
using carve::test::run_carve;
using carve::test::scratch;
using carve::test::small_part;

namespace {

std::string slice(const std::string& model, const std::string& args, const std::string& name,
                  int want_status = 0, std::string* err = nullptr) {
    return carve::test::slice_text(model, args, name, want_status, err);
}
using carve::test::lines_of;

std::string command_of(const std::string& l) {
    return l.substr(0, l.find_first_of(" ;"));
}

using carve::test::words;

// The value of `key` in the configuration block ("" if absent).
std::string config_value(const std::string& g, const std::string& key) {
    const std::string tag = "\n; " + key + " = ";
    const size_t at = g.find(tag);
    if (at == std::string::npos) return "";
    const size_t from = at + tag.size();
    return g.substr(from, g.find('\n', from) - from);
}

std::string box_model() {
    std::vector<carve::test::StlTriangle> t;
    carve::test::add_box(t, 0, 0, 0, 20, 14, 4);
    return carve::test::write_stl("printers2_box.stl", t).string();
}

}  // namespace

// The klipper preset is Klipper's own kit-voron2-250mm.cfg: its bed, height and limits are in
// the configuration block, and no M204 S asks for more than its max_accel, 3000, whatever the
// options ask for (Klipper would apply 5000 as given).
TEST(KlipperPreset, MatchesTheStockVoron250AndKeepsWithinItsMaxAccel) {
    for (const std::string extra : {"", " --acceleration 5000 --travel-acceleration 8000"}) {
        const std::string g = slice(small_part(), "--cavities 1 --printer klipper" + extra,
                                    "voron" + std::to_string(extra.size()));
        EXPECT_EQ(config_value(g, "bed_shape"), "0x0,250x0,250x250,0x250");
        EXPECT_EQ(config_value(g, "max_print_height"), "250");
        EXPECT_EQ(config_value(g, "machine_max_acceleration_x"), "3000");
        EXPECT_EQ(config_value(g, "machine_max_acceleration_y"), "3000");
        EXPECT_EQ(config_value(g, "machine_max_feedrate_x"), "350");
        EXPECT_EQ(config_value(g, "machine_max_feedrate_z"), "50");
        EXPECT_NE(config_value(g, "printer_name").find("kit-voron2-250mm.cfg"), std::string::npos);
        int m204 = 0;
        for (const std::string& l : lines_of(g)) {
            if (command_of(l) != "M204") continue;
            ++m204;
            const std::map<char, double> w = words(l);
            ASSERT_TRUE(w.count('S')) << l;  // the one form Klipper reads for every move
            EXPECT_LE(w.at('S'), 3000) << l;
            EXPECT_GT(w.at('S'), 0) << l;
        }
        EXPECT_GT(m204, 0);
    }
    // The bed is the Voron's: a copy beyond 250 mm is refused before anything is written.
    std::string err;
    slice(small_part(), "--printer klipper --copies 60", "voron_full", 1, &err);
    EXPECT_NE(err.find("250 x 250"), std::string::npos) << err;
}

// Marlin 2 and Prusa firmware read the travel acceleration from M204 T (with P for printing
// and R for retracting), written once. Klipper reads M204 P T as min(P, T) for every move, so
// where the two differ (every Marlin preset) an M204 S, which both read alike, precedes each
// change: every extruding move at P's value, every travel at T's.
TEST(KlipperPreset, MarlinPresetsWriteTravelAccelerationAsEveryFirmwareReadsIt) {
    for (const std::string printer : {"mk3s", "ender3", "generic"}) {  // NOLINT
        const std::string g =
            slice(small_part(), "--cavities 1 --printer " + printer, "m204" + printer);
        int ptr = 0, switches = 0, prints = 0, travels = 0;
        double p = 0, t = 0, s = -1;
        bool body = false;
        for (const std::string& l : lines_of(g)) {
            const std::string c = command_of(l);
            const std::map<char, double> w = words(l);
            if (l.rfind(";LAYER_CHANGE", 0) == 0) body = true;
            if (c == "M204" && !w.count('S')) {
                ++ptr;
                EXPECT_TRUE(w.count('P') && w.count('R') && w.count('T')) << l;
                p = w.at('P'), t = w.at('T');
                EXPECT_EQ(t, std::stod(config_value(g, "machine_max_acceleration_travel")));
                EXPECT_NE(p, t) << printer;
            } else if (c == "M204") {
                ++switches;
                s = w.at('S');
            } else if (body && (c == "G0" || c == "G1") && (w.count('X') || w.count('Y'))) {
                if (w.count('E') && w.at('E') > 0 && c == "G1") {
                    ++prints;
                    EXPECT_EQ(s, p) << printer << ": " << l;
                } else if (c == "G0") {
                    ++travels;
                    EXPECT_EQ(s, t) << printer << ": " << l;
                }
            }
        }
        EXPECT_EQ(ptr, 1) << printer;
        EXPECT_GT(switches, 1) << printer;
        EXPECT_GT(prints, 0) << printer;
        EXPECT_GT(travels, 0) << printer;
    }
    // With the two equal, M204 P R T alone says it to every firmware.
    const std::string g = slice(small_part(), "--cavities 1 --travel-acceleration 1000", "m204eq");
    int m204 = 0;
    for (const std::string& l : lines_of(g))
        if (command_of(l) == "M204") {
            ++m204;
            EXPECT_FALSE(words(l).count('S')) << l;
        }
    EXPECT_EQ(m204, 1);
}

// PrusaSlicer's G-code viewer applies a file's configuration only for the producers it names
// (GCodeProcessor::Producers, 2.5 to 2.9.4); carve names itself and none of them, on every
// preset, and still states its bed and printer for the hosts.
TEST(Viewer, CarveNamesItselfAndNoneOfTheViewersProducers) {
    for (const std::string printer : {"generic", "mk3s", "ender3", "klipper"}) {  // NOLINT
        const std::string g =
            slice(small_part(), "--cavities 1 --printer " + printer, "producer" + printer);
        EXPECT_EQ(g.rfind("; generated by carve ", 0), 0u) << g.substr(0, 80);
        for (const char* other :
             {"generated by PrusaSlicer", "generated by Slic3r", "generated by SuperSlicer",
              "Cura_SteamEngine", "G-Code generated by Simplify3D(R)", "CraftWare", "ideaMaker",
              "KISSlicer"})
            EXPECT_EQ(g.find(other), std::string::npos) << printer << ": " << other;
        EXPECT_FALSE(config_value(g, "bed_shape").empty()) << printer;
        EXPECT_FALSE(config_value(g, "printer_name").empty()) << printer;
    }
}

namespace {

// Reads a file of several objects: the extrusions printed inside each label block by type, and
// those outside any.
struct Labelled {
    std::map<std::string, int> inside, outside;            // extruding moves by ;TYPE:
    std::map<std::string, std::array<double, 4>> defined;  // x0, y0, x1, y1
    std::map<std::string, std::array<double, 4>> printed;  // what each block extrudes
    int unbalanced = 0;
};

Labelled read_labels(const std::string& g, bool klipper) {
    Labelled r;
    std::string open, type;
    double e = 0, x = 0, y = 0;
    bool relative = false;
    for (const std::string& l : lines_of(g)) {
        if (l.rfind(";TYPE:", 0) == 0) type = l.substr(6);
        if (l.rfind("EXCLUDE_OBJECT_DEFINE ", 0) == 0) {
            const size_t name = l.find("NAME=") + 5;
            const std::string n = l.substr(name, l.find(' ', name) - name);
            std::array<double, 4> b{1e9, 1e9, -1e9, -1e9};
            std::string num;
            std::vector<double> v;
            for (char c : l.substr(l.find("POLYGON=") + 8)) {
                if (std::isdigit(static_cast<unsigned char>(c)) || c == '.' || c == '-') {
                    num += c;
                } else if (!num.empty()) {
                    v.push_back(std::stod(num));
                    num.clear();
                }
            }
            for (size_t i = 0; i + 1 < v.size(); i += 2)
                b = {std::min(b[0], v[i]), std::min(b[1], v[i + 1]), std::max(b[2], v[i]),
                     std::max(b[3], v[i + 1])};
            r.defined[n] = b;
        }
        const std::string start = klipper ? "EXCLUDE_OBJECT_START NAME=" : "; printing object ";
        const std::string end = klipper ? "EXCLUDE_OBJECT_END NAME=" : "; stop printing object ";
        if (l.rfind(start, 0) == 0) {
            if (!open.empty()) ++r.unbalanced;
            open = l.substr(start.size());
        }
        if (l.rfind(end, 0) == 0) {
            if (open != l.substr(end.size())) ++r.unbalanced;
            open.clear();
        }
        // The firmware's label opens and closes within the comments'.
        if (!klipper && l.rfind("M486 S", 0) == 0 && open.empty()) ++r.unbalanced;
        if (l.empty() || l[0] == ';') continue;
        const std::string cmd = command_of(l);
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
        if (de > 0 && (nx != x || ny != y)) {
            (open.empty() ? r.outside : r.inside)[type]++;
            if (!open.empty()) {
                std::array<double, 4>& b =
                    r.printed.try_emplace(open, std::array<double, 4>{1e9, 1e9, -1e9, -1e9})
                        .first->second;
                b = {std::min(b[0], nx), std::min(b[1], ny), std::max(b[2], nx),
                     std::max(b[3], ny)};
            }
        }
        x = nx, y = ny;
    }
    return r;
}

}  // namespace

// With three copies, the skirt, the brim and the raft are printed outside every object's block
// (EXCLUDE_OBJECT_START/END on Klipper, M486 and the comments elsewhere), so that each object's
// outline holds its own extrusions only and the outlines do not overlap.
TEST(Labels, SkirtBrimAndRaftLieOutsideEveryObjectsBlock) {
    const std::string box = box_model();
    for (const std::string printer : {"klipper", "generic"}) {  // NOLINT
        for (const std::string extra : {"--skirts 2", "--brim-width 3", "--raft-layers 2"}) {
            const bool klipper = printer == "klipper";
            const std::string g =
                slice(box, "--cavities 1 --copies 3 --printer " + printer + " " + extra,
                      "labels_" + printer + extra.substr(2, 4));
            const Labelled r = read_labels(g, klipper);
            const std::string what = printer + " " + extra;
            EXPECT_EQ(r.unbalanced, 0) << what;
            EXPECT_EQ(r.inside.count("Skirt/Brim"), 0u) << what;
            EXPECT_GT(r.outside.count("Skirt/Brim") ? r.outside.at("Skirt/Brim") : 0, 0) << what;
            EXPECT_EQ(r.printed.size(), 3u) << what;
            // The raft's lines (the layers under the model, ;TYPE: of supports) are outside too:
            // nothing but the skirt/brim and the raft is printed outside a block.
            for (const auto& [type, n] : r.outside) {
                if (type != "Skirt/Brim") {
                    EXPECT_NE(extra.find("raft"), std::string::npos)
                        << what << ": " << n << " " << type << " moves outside any object";
                }
            }
            if (!klipper) continue;
            ASSERT_EQ(r.defined.size(), 3u) << what;
            for (const auto& [name, b] : r.defined) {
                ASSERT_TRUE(r.printed.count(name)) << name;
                const std::array<double, 4>& p = r.printed.at(name);
                // The outline is what the block prints, within rounding: a 20 x 14 box.
                for (int i = 0; i < 4; ++i) EXPECT_NEAR(b[i], p[i], 0.01) << what << " " << name;
                EXPECT_LT(b[2] - b[0], 21) << what << " " << name;
                for (const auto& [other, o] : r.defined) {
                    if (other != name) {
                        EXPECT_TRUE(b[2] < o[0] || o[2] < b[0] || b[3] < o[1] || o[3] < b[1])
                            << what << ": " << name << " overlaps " << other;
                    }
                }
            }
        }
    }
    // One object alone: its outline is the object's, not the skirt's.
    const std::string g = slice(box, "--cavities 1 --printer klipper --skirts 1", "labels_one");
    const Labelled r = read_labels(g, true);
    ASSERT_EQ(r.defined.size(), 1u);
    EXPECT_LT(r.defined.begin()->second[2] - r.defined.begin()->second[0], 21);
    EXPECT_EQ(r.inside.count("Skirt/Brim"), 0u);
}

namespace {

// The moves around each pause command: the nozzle's Z and the filament's state (retracted
// when E stands below the most it reached) at the command, and just before the next extrusion.
struct PauseSeen {
    double z_at = -1, z_after = -1;  // at the command, at the first Z move after it
    bool retracted_at = false, unretracted_after = false;
};

std::vector<PauseSeen> read_pauses(const std::string& g, const std::string& command) {
    std::vector<PauseSeen> out;
    double e = 0, e_max = 0, z = 0;
    bool relative = false, after = false;
    for (const std::string& l : lines_of(g)) {
        if (l.empty() || l[0] == ';') continue;
        const std::string cmd = command_of(l);
        std::map<char, double> w = words(l);
        if (l == command) {
            PauseSeen p;
            p.z_at = z;
            p.retracted_at = e < e_max - 0.1;
            out.push_back(p);
            after = true;
            continue;
        }
        if (cmd == "M83") relative = true;
        if (cmd == "M82") relative = false;
        if (cmd == "G92" && w.count('E')) e = e_max = w['E'];
        if (cmd != "G1" && cmd != "G0") continue;
        if (w.count('E')) e = relative ? e + w['E'] : w['E'];
        if (w.count('Z')) z = w['Z'];
        if (after && !w.count('X') && !w.count('Y') && w.count('Z') && out.back().z_after < 0)
            out.back().z_after = z;
        if (after && !w.count('X') && !w.count('Y') && w.count('E') && e >= e_max - 1e-9)
            out.back().unretracted_after = true;
        if (after && (w.count('X') || w.count('Y'))) after = false;  // back to printing
        if (!after) e_max = std::max(e_max, e);
    }
    return out;
}

}  // namespace

// A pause parks: retracted and lifted clear of the part before the command, then down to where
// it was and unretracted before the print goes on; --pause-command names the command, and on
// Klipper the header says what PAUSE needs.
TEST(Pause, RetractsAndLiftsBeforeTheCommandAndReturns) {
    struct Case {
        std::string args, command;
    };
    for (const Case& c :
         {Case{"--printer klipper", "PAUSE"}, Case{"--printer mk3s", "M600"},
          Case{"--printer klipper --pause-command M601", "M601"}, Case{"--relative-e", "M600"}}) {
        const std::string g = slice(small_part(), "--cavities 1 --pause-at 2.1,10 " + c.args,
                                    "park" + std::to_string(c.args.size()));
        const std::vector<PauseSeen> seen = read_pauses(g, c.command);
        ASSERT_EQ(seen.size(), 2u) << c.args;
        // Layer 10 (top 2.2) comes after layer 9's 2.0; layer 49 (10.0) after 9.8.
        const double layer_z[] = {2.0, 9.8};
        for (size_t k = 0; k < seen.size(); ++k) {
            EXPECT_TRUE(seen[k].retracted_at) << c.args << " pause " << k;
            EXPECT_NEAR(seen[k].z_at, layer_z[k] + 5, 1e-6) << c.args << " pause " << k;
            EXPECT_NEAR(seen[k].z_after, layer_z[k], 1e-6) << c.args << " pause " << k;
            EXPECT_TRUE(seen[k].unretracted_after) << c.args << " pause " << k;
        }
        const bool note = g.find(
                              "; --pause-at writes PAUSE: Klipper pauses only with "
                              "[pause_resume]") != std::string::npos;
        EXPECT_EQ(note, c.command == "PAUSE") << c.args;
        EXPECT_EQ(config_value(g, "pause_command"), c.command == "M601" ? "M601" : "");
    }
    // Near the printer's top the lift stops at its height.
    const std::string g =
        slice(small_part(), "--cavities 1 --pause-at 10 --max-print-height 12", "park_top");
    const std::vector<PauseSeen> seen = read_pauses(g, "M600");
    ASSERT_EQ(seen.size(), 1u);
    EXPECT_NEAR(seen[0].z_at, 12, 1e-6);
    std::string err;
    slice(small_part(), "--pause-at 5 --pause-command 'M600 ; x'", "park_bad", 1, &err);
    EXPECT_NE(err.find("--pause-command"), std::string::npos) << err;
}

namespace {

// The M73 lines of a file: "P R" and "Q S" figures in order.
struct M73s {
    std::vector<std::pair<int, int>> normal, stealth;
};

M73s read_m73(const std::string& g) {
    M73s m;
    for (const std::string& l : lines_of(g)) {
        if (command_of(l) != "M73") continue;
        std::map<char, double> w = words(l);
        if (w.count('P')) m.normal.emplace_back(int(w['P']), int(w['R']));
        if (w.count('Q')) m.stealth.emplace_back(int(w['Q']), int(w['S']));
    }
    return m;
}

std::string header_time(const std::string& g, const std::string& mode) {
    const std::string tag = "; estimated printing time (" + mode + " mode) = ";
    const size_t at = g.find(tag);
    if (at == std::string::npos) return "";
    return g.substr(at + tag.size(), g.find('\n', at) - at - tag.size());
}

}  // namespace

// On the mk3s, M73 Q/S are timed with PrusaSlicer's MK3S stealth limits (960 mm/s^2, 100 mm/s
// in X and Y): the very figures the normal mode's M73 P/R state for a printer whose limits are
// those, and not those of the normal mode. Cooling is off: it slows layers by the normal time.
TEST(Stealth, QAndSAreTheEstimateUnderTheStealthLimits) {
    const std::string args = "--cavities 1 --cooling 0 --printer mk3s --travel-speed 180";
    const std::string g = slice(small_part(), args, "stealth");
    const fs::path ini = scratch() / "stealth_limits.ini";
    {
        std::ofstream out(ini);
        out << "machine_max_acceleration_x = 960\nmachine_max_acceleration_y = 960\n"
               "machine_max_feedrate_x = 100\nmachine_max_feedrate_y = 100\n";
    }
    const std::string as_normal = slice(small_part(), args + " --load " + ini.string(), "slow");
    const M73s a = read_m73(g), b = read_m73(as_normal);
    ASSERT_GT(a.normal.size(), 10u);
    EXPECT_EQ(a.stealth.size(), a.normal.size());
    EXPECT_NE(a.stealth, a.normal);
    // The profile that states single limits has no stealth mode of its own.
    EXPECT_EQ(b.stealth, b.normal);
    // Each line's figures are rounded from the times there: the stealth mode's percentages and
    // minutes are the slow printer's.
    EXPECT_EQ(a.stealth.front(), b.normal.front());
    EXPECT_EQ(a.stealth.back(), b.normal.back());
    std::vector<std::pair<int, int>> da = a.stealth, db = b.normal;
    da.erase(std::unique(da.begin(), da.end()), da.end());
    db.erase(std::unique(db.begin(), db.end()), db.end());
    EXPECT_EQ(da, db);
    EXPECT_EQ(header_time(g, "silent"), header_time(as_normal, "normal"));
    EXPECT_NE(header_time(g, "silent"), header_time(g, "normal"));
    // PrusaSlicer's own profile of the MK3S states them as "normal,stealth": read as the preset.
    const fs::path prusa = scratch() / "stealth_prusa.ini";
    {
        std::ofstream out(prusa);
        out << "machine_max_acceleration_x = 1000,960\nmachine_max_acceleration_y = 1000,960\n"
               "machine_max_feedrate_x = 200,100\nmachine_max_feedrate_y = 200,100\n"
               "silent_mode = 1\nremaining_times = 1\n";
    }
    const std::string read_back =
        slice(small_part(), args + " --load " + prusa.string(), "stealth_prusa");
    EXPECT_EQ(read_m73(read_back).stealth, a.stealth);
    EXPECT_EQ(config_value(read_back, "stealth_max_acceleration"), "960");
}

// G-code writer: atomic output, bottom-up assembly of top-down layers, extrusion bookkeeping
// (parsed back from the file), flavours, and the trapezoidal time estimate.
#include "gcode/gcode.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "base/error.hpp"
#include "gcode/emitter.hpp"
#include "gcode/motion.hpp"
#include "gcode/spill.hpp"

using namespace carve;
namespace fs = std::filesystem;

namespace {

constexpr Coord kMm = 1000;

// A fresh empty directory per test.
fs::path temp_dir() {
    std::string tmpl = (fs::temp_directory_path() / "carve-gcode-XXXXXX").string();
    const char* made = mkdtemp(tmpl.data());
    EXPECT_NE(made, nullptr);
    return fs::path(tmpl);
}

std::vector<std::string> dir_entries(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    return names;
}

std::string read_all(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// A square loop of side `side` mm at (x, y) plus a line, for layer `index`.
LayerToolpaths sample_layer(int index, const Settings& st) {
    LayerToolpaths l;
    l.index = index;
    l.z = (index + 1) * st.layer_height;
    Extrusion wall;
    wall.feature = Feature::OuterWall;
    wall.closed = true;
    wall.points = {{0, 0}, {10 * kMm, 0}, {10 * kMm, 10 * kMm}, {0, 10 * kMm}};
    l.extrusions.push_back(wall);
    Extrusion cover;
    cover.feature = Feature::Cover;
    cover.points = {{1 * kMm, 1 * kMm}, {9 * kMm, 1 * kMm}, {9 * kMm, 1400}, {1 * kMm, 1400}};
    cover.flow = 0.97;
    l.extrusions.push_back(cover);
    Extrusion wall2;  // far away: needs a retracted travel
    wall2.feature = Feature::CavityWall;
    wall2.cavity = 1;
    wall2.points = {{30 * kMm, 30 * kMm}, {35 * kMm, 30 * kMm}, {35 * kMm, 31 * kMm}};
    l.extrusions.push_back(wall2);
    if (index % 2 == 1) {
        Extrusion bridge;
        bridge.feature = Feature::Bridge;
        bridge.flow = st.bridge_flow;
        bridge.points = {{35 * kMm, 31 * kMm}, {35 * kMm, 36 * kMm}};
        l.extrusions.push_back(bridge);
    }
    l.extrusions.back().points.push_back(l.extrusions.back().points.back());  // zero-length step
    return l;
}

struct Parsed {
    std::vector<int> layers;  // ;LAYER:n in file order
    // Z of each layer's first extrusion after its ;LAYER: (the first travel of the print is
    // lifted above the first layer)
    std::vector<double> layer_z;
    double extruded = 0;   // filament pushed on XY moves (mm)
    double retracted = 0;  // filament pulled back by E-only moves
    int retract_moves = 0;
    std::vector<std::string> lines;
    double min_x = 1e9, max_x = -1e9;
};

std::map<char, double> words(const std::string& line) {
    std::map<char, double> w;
    std::istringstream in(line.substr(0, line.find(';')));
    std::string tok;
    in >> tok;  // G0 / G1
    while (in >> tok)
        if (tok.size() > 1) w[tok[0]] = std::stod(tok.substr(1));
    return w;
}

Parsed parse(const fs::path& file, bool relative) {
    Parsed p;
    std::ifstream in(file);
    std::string line;
    double e = 0, z = 0;
    bool want_z = false;
    while (std::getline(in, line)) {
        p.lines.push_back(line);
        if (line.rfind(";LAYER:", 0) == 0) {
            p.layers.push_back(std::stoi(line.substr(7)));
            want_z = true;
            continue;
        }
        if (line.rfind("G92", 0) == 0) {
            auto w = words(line);
            if (w.count('E')) e = w['E'];
            continue;
        }
        if (line.rfind("G0 ", 0) != 0 && line.rfind("G1 ", 0) != 0) continue;
        auto w = words(line);
        if (w.count('Z')) z = w['Z'];
        if (want_z && w.count('E') && (w.count('X') || w.count('Y'))) {
            p.layer_z.push_back(z);
            want_z = false;
        }
        if (w.count('X')) p.min_x = std::min(p.min_x, w['X']), p.max_x = std::max(p.max_x, w['X']);
        if (!w.count('E')) continue;
        const double delta = relative ? w['E'] : w['E'] - e;
        e = relative ? e + w['E'] : w['E'];
        if (w.count('X') || w.count('Y')) {
            EXPECT_GE(delta, 0) << line;
            p.extruded += delta;
        } else if (delta < 0) {
            p.retracted -= delta;
            ++p.retract_moves;
        }
    }
    return p;
}

double filament_area(const Settings& st) {
    return std::numbers::pi * st.filament_diameter * st.filament_diameter / 4;
}

}  // namespace

TEST(Motion, StraightMoveMatchesTheAnalyticTrapezoid) {
    // 100 mm at 50 mm/s, 1000 mm/s^2: 0.05 s up (1.25 mm), 0.05 s down, 97.5 mm cruising.
    MotionPlanner planner;
    planner.move(100, 0, 50, 1000);
    planner.stop();
    EXPECT_NEAR(planner.time(), 0.05 + 0.05 + 97.5 / 50, 1e-9);
    EXPECT_NEAR(trapezoid_time(100, 0, 50, 0, 1000), 2.05, 1e-9);
    // Too short to cruise: a triangle peaking at sqrt(a * L).
    EXPECT_NEAR(trapezoid_time(1, 0, 50, 0, 1000), 2 * std::sqrt(1000.0) / 1000, 1e-9);
}

TEST(Motion, CollinearSplitsCostNothingAndCornersSlowDown) {
    MotionPlanner straight, split, corner, reverse;
    straight.move(100, 0, 50, 1000);
    for (int i = 0; i < 10; ++i) split.move(10, 0, 50, 1000);
    corner.move(50, 0, 50, 1000);
    corner.move(0, 50, 50, 1000);
    reverse.move(50, 0, 50, 1000);
    reverse.move(-50, 0, 50, 1000);
    EXPECT_NEAR(split.time(), straight.time(), 1e-9);
    EXPECT_GT(corner.time(), straight.time());
    // A reversal stops dead: two separate trapezoids.
    EXPECT_NEAR(reverse.time(), 2 * trapezoid_time(50, 0, 50, 0, 1000), 1e-9);
    EXPECT_LT(corner.time(), reverse.time());
    // Junction deviation at 90 degrees: v^2 = a * delta * s / (1 - s), s = sin(45 deg).
    const double s = std::sin(std::numbers::pi / 4);
    const double vj = std::sqrt(1000 * kJunctionDeviationMm * s / (1 - s));
    // By symmetry both legs take the same time: up to speed, then down to v_j.
    const double half = trapezoid_time(50, 0, 50, vj, 1000);
    EXPECT_NEAR(corner.time(), 2 * half, 1e-9);
}

TEST(Spill, RoundTripsLayers) {
    Settings st;
    LayerToolpaths l = sample_layer(3, st);
    l.extrusions[0].points.push_back({-123456789, 987654321});
    LayerToolpaths back = decode_layer(encode_layer(l));
    EXPECT_EQ(back.index, 3);
    EXPECT_EQ(back.z, l.z);
    ASSERT_EQ(back.extrusions.size(), l.extrusions.size());
    for (size_t i = 0; i < l.extrusions.size(); ++i) {
        EXPECT_EQ(back.extrusions[i].feature, l.extrusions[i].feature);
        EXPECT_EQ(back.extrusions[i].closed, l.extrusions[i].closed);
        EXPECT_EQ(back.extrusions[i].cavity, l.extrusions[i].cavity);
        EXPECT_EQ(back.extrusions[i].flow, l.extrusions[i].flow);
        EXPECT_EQ(back.extrusions[i].points, l.extrusions[i].points);
    }
    std::string blob = encode_layer(l);
    blob.pop_back();
    EXPECT_THROW(decode_layer(blob), std::runtime_error);
}

TEST(GcodeWriter, FileAppearsOnlyAfterFinishAndLayersComeBottomUp) {
    const fs::path dir = temp_dir();
    const fs::path out = dir / "part.gcode";
    Settings st;
    PrintStats stats;
    {
        GcodeWriter w(out.string(), st, 100, 100, 3);
        for (int i = 2; i >= 0; --i) {
            w.add_layer(sample_layer(i, st));
            EXPECT_FALSE(fs::exists(out));
        }
        EXPECT_TRUE(dir_entries(dir).empty()) << "the spill file must not be visible";
        stats = w.finish({"model = test.stl"});
        EXPECT_THROW(w.finish({}), std::logic_error);
    }
    ASSERT_TRUE(fs::exists(out));
    EXPECT_EQ(dir_entries(dir), std::vector<std::string>{"part.gcode"});
    const Parsed p = parse(out, false);
    EXPECT_EQ(p.layers, (std::vector<int>{0, 1, 2}));
    ASSERT_EQ(p.layer_z.size(), 3u);
    EXPECT_NEAR(p.layer_z[0], 0.2, 1e-9);
    EXPECT_NEAR(p.layer_z[1], 0.4, 1e-9);
    EXPECT_NEAR(p.layer_z[2], 0.6, 1e-9);
    EXPECT_EQ(stats.layers, 3);
    // Offsets applied: model x in [0, 35] mm lands in [100, 135].
    EXPECT_NEAR(p.min_x, 100.0, 1e-9);
    EXPECT_NEAR(p.max_x, 135.0, 1e-9);
    fs::remove_all(dir);
}

TEST(GcodeWriter, NoFileWhenDestroyedBeforeFinish) {
    const fs::path dir = temp_dir();
    const fs::path out = dir / "part.gcode";
    Settings st;
    try {
        GcodeWriter w(out.string(), st, 0, 0, 4);
        w.add_layer(sample_layer(3, st));
        w.add_layer(sample_layer(2, st));
        throw std::runtime_error("carving failed");
    } catch (const std::runtime_error&) {
    }
    EXPECT_FALSE(fs::exists(out));
    EXPECT_TRUE(dir_entries(dir).empty());
    {
        GcodeWriter w(out.string(), st, 0, 0, 2);
        EXPECT_THROW(w.add_layer(sample_layer(5, st)), std::out_of_range);
    }
    EXPECT_TRUE(dir_entries(dir).empty());
    EXPECT_THROW(GcodeWriter((dir / "missing" / "x.gcode").string(), st, 0, 0, 1), OutputError);
    fs::remove_all(dir);
}

TEST(GcodeWriter, ExtrusionAddsUpAndHeaderStatesTheEstimate) {
    for (bool relative : {false, true}) {
        const fs::path dir = temp_dir();
        const fs::path out = dir / "part.gcode";
        Settings st;
        st.relative_e = relative;
        GcodeWriter w(out.string(), st, 50, 60, 6);
        for (int i = 5; i >= 0; --i) w.add_layer(sample_layer(i, st));
        const PrintStats stats = w.finish({});
        const Parsed p = parse(out, relative);
        const double A = filament_area(st);
        EXPECT_NEAR(p.extruded * A / stats.extruded_volume_mm3, 1.0, 1e-3);
        EXPECT_NEAR(stats.filament_length_mm, stats.extruded_volume_mm3 / A, 1e-9);
        EXPECT_NEAR(stats.filament_weight_g, stats.extruded_volume_mm3 / 1000 * st.filament_density,
                    1e-12);
        // Expected volume: per layer a 40 mm loop, a 16.4 mm cover zig-zag at 0.97, a 6 mm wall,
        // and on odd layers a 5 mm bridge; cross-section w x h.
        const double section = st.nozzle * st.layer_height;
        const double per_layer = (40 + 16.4 * 0.97 + 6) * section;
        EXPECT_NEAR(stats.extruded_volume_mm3, 6 * per_layer + 3 * 5 * section * st.bridge_flow,
                    1e-6);
        EXPECT_NEAR(stats.bridge_length_mm, 15.0, 1e-9);
        // Each layer travels 29 mm diagonally to the far wall (retracted), and back.
        EXPECT_GE(stats.retractions, 6 * 2);
        EXPECT_EQ(p.retract_moves, stats.retractions);
        EXPECT_NEAR(p.retracted, stats.retractions * st.retract_length, 1e-6);
        EXPECT_GT(stats.travel_length_mm, 6 * 40.0);

        const std::string text = read_all(out);
        EXPECT_EQ(text.rfind("; generated by carve", 0), 0u);
        EXPECT_NE(text.find("; estimated printing time (normal mode) = "), std::string::npos);
        EXPECT_NE(text.find(";TIME:" + std::to_string(std::llround(stats.estimated_print_time_s))),
                  std::string::npos);
        EXPECT_NE(text.find(";Filament used: "), std::string::npos);
        EXPECT_NE(text.find("; layer_height = 0.2\n"), std::string::npos);
        EXPECT_NE(text.find(relative ? "\nM83" : "\nM82"), std::string::npos);
        EXPECT_NE(text.find(";TYPE:External perimeter\n"), std::string::npos);
        EXPECT_NE(text.find(";TYPE:Solid infill\n"), std::string::npos);
        EXPECT_NE(text.find(";TYPE:Internal infill\n"), std::string::npos);
        EXPECT_NE(text.find(";TYPE:Bridge infill\n"), std::string::npos);
        // Fan off on the first layer, on from the second.
        const size_t layer1 = text.find(";LAYER:1\n");
        ASSERT_NE(layer1, std::string::npos);
        EXPECT_EQ(text.substr(0, layer1).find("M106"), std::string::npos);
        EXPECT_NE(text.find("M106 S255", layer1), std::string::npos);
        // First-layer temperatures before anything moves, regular ones from layer 1.
        EXPECT_LT(text.find("M109 S215"), text.find("G1 X"));
        EXPECT_NE(text.find("M104 S210", layer1), std::string::npos);
        fs::remove_all(dir);
    }
}

TEST(GcodeWriter, SingleMoveTimeMatchesTheTrapezoid) {
    const fs::path dir = temp_dir();
    const fs::path out = dir / "line.gcode";
    Settings st;
    st.perimeter_speed = st.first_layer_speed = 50;
    st.acceleration = 1000;
    st.retract_length = 0;  // nothing but the move and the first Z move
    st.cooling = 0;         // a 2 s layer would be slowed down to the minimum layer time
    LayerToolpaths l;
    l.index = 0;
    l.z = st.layer_height;
    Extrusion e;
    e.points = {{0, 0}, {100 * kMm, 0}};
    l.extrusions.push_back(e);
    GcodeWriter w(out.string(), st, 0, 0, 1);
    w.add_layer(l);
    const PrintStats stats = w.finish({});
    // The Z move within the machine's Z limits (M203 Z, M201 Z).
    const double z_move = trapezoid_time(st.layer_height, 0, std::min(10.0, st.max_feedrate_z), 0,
                                         std::min(st.travel_acceleration, st.max_acceleration_z));
    EXPECT_NEAR(stats.estimated_print_time_s, 2.05 + z_move, 1e-9);
    EXPECT_EQ(stats.retractions, 0);
    EXPECT_NEAR(stats.travel_length_mm, 0, 1e-12);
    fs::remove_all(dir);
}

TEST(GcodeWriter, FlavoursDifferInStartAndFan) {
    const fs::path dir = temp_dir();
    Settings st;
    st.flavor = GcodeFlavor::Klipper;
    st.start_gcode.clear();
    st.end_gcode.clear();
    {
        GcodeWriter w((dir / "k.gcode").string(), st, 0, 0, 2);
        w.add_layer(sample_layer(1, st));
        w.add_layer(sample_layer(0, st));
        w.finish({});
    }
    const std::string k = read_all(dir / "k.gcode");
    EXPECT_NE(k.find("PRINT_START BED_TEMP=60 EXTRUDER_TEMP=215"), std::string::npos);
    // Heated and waited for before the macro too: the stock macros read no parameters.
    EXPECT_LT(k.find("M190 S60"), k.find("PRINT_START"));
    EXPECT_LT(k.find("M109 S215"), k.find("PRINT_START"));
    EXPECT_NE(k.find("PRINT_END"), std::string::npos);
    st = Settings{};
    st.flavor = GcodeFlavor::RepRap;
    st.bridge_fan_speed = 50;  // percent
    {
        GcodeWriter w((dir / "r.gcode").string(), st, 0, 0, 2);
        w.add_layer(sample_layer(1, st));
        w.add_layer(sample_layer(0, st));
        w.finish({});
    }
    const std::string r = read_all(dir / "r.gcode");
    EXPECT_NE(r.find("M106 S1.00"), std::string::npos);
    EXPECT_NE(r.find("M106 S0.50"), std::string::npos);  // bridge fan
    EXPECT_NE(r.find(";FLAVOR:RepRap"), std::string::npos);
    fs::remove_all(dir);
}

TEST(GcodeWriter, ZHopLiftsRetractedTravelsAndOldOutputSurvivesUntilFinish) {
    const fs::path dir = temp_dir();
    const fs::path out = dir / "part.gcode";
    std::ofstream(out) << "old\n";
    Settings st;
    st.z_hop = 0.4;
    {
        GcodeWriter w(out.string(), st, 0, 0, 2);
        w.add_layer(sample_layer(1, st));
        w.add_layer(sample_layer(0, st));
        EXPECT_EQ(read_all(out), "old\n");
        w.finish({});
    }
    const Parsed p = parse(out, false);
    ASSERT_GT(p.retract_moves, 0);
    // Every retraction before a travel is followed by a lift, the travel, and the way down (the
    // travel's M204 S aside: the print and travel accelerations differ).
    std::vector<std::string> moves;
    for (const std::string& l : p.lines)
        if (l.rfind("M204 S", 0) != 0) moves.push_back(l);
    int hops = 0;
    for (size_t i = 0; i + 3 < moves.size(); ++i) {
        if (moves[i].rfind("G1 E", 0) != 0 || moves[i + 1].rfind("G1 Z", 0) != 0) continue;
        const double up = words(moves[i + 1])['Z'];
        EXPECT_EQ(moves[i + 2].rfind("G0 X", 0), 0u) << moves[i + 2];
        ASSERT_EQ(moves[i + 3].rfind("G1 Z", 0), 0u) << moves[i + 3];
        EXPECT_NEAR(up - words(moves[i + 3])['Z'], 0.4, 1e-9);
        ++hops;
    }
    EXPECT_EQ(hops, p.retract_moves - 1);  // the last retraction ends the print
    fs::remove_all(dir);
}

namespace {

// Three small islands in a row, printed first to last or last to first as the layer below
// ended nearer the one or the other: the order alternates from layer to layer, so a chunk's
// warm-up that starts anywhere but at the print's start guesses the phase wrong half of the
// time and the chunk must be written again. Below layer 40 every sixth layer has one island
// (settled: the chunks start after those where they can, and their warm-up is then right).
LayerToolpaths island_layer(int index, const Settings& st) {
    LayerToolpaths l;
    l.index = index;
    l.z = (index + 1) * st.layer_height;
    const int islands = index % 6 == 5 && index < 40 ? 1 : 3;
    for (int k = 0; k < islands; ++k) {
        const Coord x = k * 20 * kMm + (index % 3) * 100;
        l.island_starts.push_back(l.extrusions.size());
        Extrusion wall;
        wall.feature = Feature::OuterWall;
        wall.closed = true;
        wall.points = {{x, 0}, {x + 4 * kMm, 0}, {x + 4 * kMm, 4 * kMm}, {x, 4 * kMm}};
        l.extrusions.push_back(wall);
        Extrusion cover;
        cover.feature = index % 4 == 0 ? Feature::Bridge : Feature::Cover;
        cover.points = {{x + kMm, kMm}, {x + 3 * kMm, kMm}, {x + 3 * kMm, 3 * kMm}};
        l.extrusions.push_back(cover);
    }
    l.island_starts.push_back(l.extrusions.size());
    if (islands < 2) l.island_starts.clear();
    return l;
}

fs::path out_path(const fs::path& dir, int threads) {
    return dir / ("t" + std::to_string(threads) + ".gcode");
}

}  // namespace

// finish() writes chunks of layers side by side, each from the state a warm-up guesses, and
// writes a chunk again where the guess was wrong: the file must be the bytes one thread
// writes, for small layers slowed down by cooling, wipes, relative E and firmware retraction.
// From four threads on, a chunk after layers of several islands is written from both guesses
// of their order, and one of them holds.
TEST(GcodeWriter, ChunksOnThreadsWriteTheBytesOfOneThread) {
    constexpr int kLayers = 150;
    for (int variant = 0; variant < 4; ++variant) {
        Settings st;
        st.wipe = variant == 1;
        st.relative_e = variant == 2;
        st.firmware_retraction = variant == 3;
        const fs::path dir = temp_dir();
        std::string one;
        PrintStats one_stats;
        for (int threads : {1, 2, 5}) {
            const fs::path out = out_path(dir, threads);
            GcodeWriter w(out.string(), st, 50, 60, kLayers);
            w.set_threads(threads);
            for (int i = kLayers - 1; i >= 0; --i) w.add_layer(island_layer(i, st));
            const PrintStats stats = w.finish({});
            const GcodeWriter::ChunkCount chunks = w.chunk_count();
            if (threads == 1) {
                one = read_all(out);
                one_stats = stats;
                EXPECT_EQ(chunks.chunks, 1);
                continue;
            }
            EXPECT_GT(chunks.chunks, 1) << threads;
            if (threads < 4) {
                EXPECT_GT(chunks.written_again, 0) << threads << " variant " << variant;
                EXPECT_LT(chunks.written_again, chunks.chunks) << " variant " << variant;
                EXPECT_EQ(chunks.second_guesses, 0);
            } else {
                EXPECT_GT(chunks.second_guesses, 0) << threads << " variant " << variant;
                EXPECT_EQ(chunks.written_again, 0) << threads << " variant " << variant;
            }
            EXPECT_TRUE(read_all(out) == one) << threads << " threads, variant " << variant;
            EXPECT_EQ(stats.estimated_print_time_s, one_stats.estimated_print_time_s);
            EXPECT_EQ(stats.extruded_volume_mm3, one_stats.extruded_volume_mm3);
            EXPECT_EQ(stats.travel_length_mm, one_stats.travel_length_mm);
            EXPECT_EQ(stats.retractions, one_stats.retractions);
        }
        // Absolute E restarts at every layer's end (G92 E0): it stays under one layer's
        // filament (about 1.3 mm here) however long the print.
        if (!st.relative_e) {
            double most = 0;
            std::istringstream in(one);
            for (std::string line; std::getline(in, line);)
                if (line.rfind("G1 ", 0) == 0 && words(line).count('E'))
                    most = std::max(most, words(line)['E']);
            EXPECT_GT(most, 0.5);
            EXPECT_LT(most, 2.0);
        }
        fs::remove_all(dir);
    }
}

namespace {

// What `e` writes of the layers [from, layers) and the end, to a file of its own.
std::string rest_of_print(Emitter& e, int from, int layers, const Settings& st) {
    std::FILE* f = std::tmpfile();
    e.begin_chunk(f);
    for (int i = from; i < layers; ++i) e.layer(island_layer(i, st));
    e.end();
    std::rewind(f);
    std::string text;
    for (int c; (c = std::fgetc(f)) != EOF;) text.push_back(char(c));
    std::fclose(f);
    return text;
}

}  // namespace

// A chunk's emitter starts from the carried state (Emitter::Carry) and nothing else: one that
// has written nothing, given another's carried state after some layers, writes the rest of the
// print byte for byte as that one does. A state the text depends on kept outside Carry would
// escape the chunks' check of their warm-up, and the file would depend on the thread count.
// Checked by keeping each member out of what resume() takes: this fails for the position, Z,
// first travel, fan, width, wipe and the objects' labels; here the layer's own first moves set
// the feed, acceleration, E and retraction again, and the layer's number and Z, whatever came
// before.
TEST(GcodeWriter, AnEmitterGivenAnothersCarriedStateWritesTheSameRest) {
    constexpr int kLayers = 60;
    std::vector<ObjectLabel> objects;
    for (int k = 0; k < 3; ++k)
        objects.push_back({"island" + std::to_string(k), k * 20.0 - 1, -1, k * 20.0 + 5, 5});
    // Without cooling too: its second pass starts from the layer's first state too, and what
    // that misses it misses on both emitters alike.
    for (int variant = 0; variant < 8; ++variant) {
        Settings st;
        st.wipe = variant % 4 == 1;
        st.relative_e = variant % 4 == 2;
        st.firmware_retraction = variant % 4 == 3;
        st.cooling = variant < 4;
        st.end_gcode = "; ended on layer [layer_num] at [layer_z]\n" + st.end_gcode;
        for (int from : {1, 2, 7, 30, 59}) {
            Emitter whole(st, to_units(50), to_units(60), nullptr, "whole");
            whole.set_objects(objects);
            whole.start();
            for (int i = 0; i < from; ++i) whole.layer(island_layer(i, st));
            Emitter chunk(st, to_units(50), to_units(60), nullptr, "chunk");
            chunk.set_objects(objects);
            chunk.resume(whole.carry());
            const std::string expected = rest_of_print(whole, from, kLayers, st);
            EXPECT_GT(expected.size(), 1000u);
            EXPECT_TRUE(rest_of_print(chunk, from, kLayers, st) == expected)
                << "from layer " << from << ", variant " << variant;
        }
    }
}

// Whatever is printed (supports, a brim, anything added round the model) stays on the bed and
// under the printer's height, or nothing is written (issue #38).
TEST(GcodeWriter, NothingIsWrittenBeyondTheMachine) {
    struct Case {
        const char* what;
        double off_x, height;
        bool bed_check, refused;
    };
    // The sample layers span x 0 to 35 mm and z up to 0.6 mm; the bed is 250 mm wide.
    for (const Case& c : {Case{"on the bed", 100, 210, true, false},
                          Case{"off the bed's right edge", 240, 210, true, true},
                          Case{"above the printer's height", 100, 0.5, true, true},
                          Case{"--no-bed-check", 240, 0.5, false, false}}) {
        const fs::path dir = temp_dir();
        const fs::path out = dir / "part.gcode";
        Settings st;
        st.max_print_height = c.height;
        st.bed_check = c.bed_check;
        {
            GcodeWriter w(out.string(), st, c.off_x, 100, 3);
            for (int i = 2; i >= 0; --i) w.add_layer(sample_layer(i, st));
            if (c.refused)
                EXPECT_THROW(w.finish({}), InputError) << c.what;
            else
                EXPECT_NO_THROW(w.finish({})) << c.what;
        }
        EXPECT_EQ(fs::exists(out), !c.refused) << c.what;
        EXPECT_EQ(dir_entries(dir).size(), c.refused ? 0u : 1u) << c.what;
        fs::remove_all(dir);
    }
}

// run_cut (run/pipeline.hpp, issue #48): a tall box cut into pieces that add up, each flat on
// the bed of its plate with its connector holes where the other piece has them; --cut auto on a
// model twice the printer's height; plates; a model no cut fits refused with nothing written.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "base/error.hpp"
#include "config/profiles.hpp"
#include "run/pipeline.hpp"
#include "support/cut_runs.hpp"
#include "support/models.hpp"
#include "support/sanitizers.hpp"

namespace fs = std::filesystem;

namespace carve {
namespace {

using test::box_model;
using test::cut_options;
using test::read;
using test::scratch;

// The text of one layer of the G-code (";LAYER:n" up to the next).
std::string layer_text(const std::string& gcode, int n) {
    const size_t from = gcode.find(";LAYER:" + std::to_string(n) + "\n");
    if (from == std::string::npos) return {};
    const size_t to = gcode.find(";LAYER:" + std::to_string(n + 1) + "\n", from);
    return gcode.substr(from, to == std::string::npos ? std::string::npos : to - from);
}

TEST(CutRun, TallBoxInTwoPiecesThatAddUp) {
    Settings s;
    s.cut_at = {40};
    const RunOptions o = cut_options(box_model("tall.stl", 30, 20, 100), "tall");
    const CutRunResult r = run_cut(s, o);
    ASSERT_EQ(r.plates.size(), 1u);
    EXPECT_EQ(r.pieces, 2u);
    EXPECT_EQ(r.gcode_paths[0], (scratch() / "tall-plate1.gcode").string());
    const nlohmann::json j = nlohmann::json::parse(read(o.stats_path));
    ASSERT_EQ(j["pieces"].size(), 2u);
    double total = 0, holes = 0;
    for (const auto& p : j["pieces"]) {
        total += p["volume_mm3"].get<double>();
        EXPECT_EQ(p["plate"], 1);
        ASSERT_EQ(p["connectors"].size(), 2u);
        for (const auto& c : p["connectors"]) {
            const double radius = c["diameter_mm"].get<double>() / 2;
            holes += std::numbers::pi * radius * radius * c["depth_mm"].get<double>();
            EXPECT_EQ(c["kind"], "hole");
            EXPECT_NEAR(c["face_z_mm"].get<double>(), 40, 1e-6);
        }
    }
    // The holes are the only material the pieces lack (their rings lie round the circles).
    EXPECT_NEAR(total + holes, 30 * 20 * 100, 0.01 * 30 * 20 * 100);
    EXPECT_LT(total, 30 * 20 * 100);
    // Matching holes: the same x, y in both faces of the cut.
    for (size_t k = 0; k < 2; ++k) {
        EXPECT_EQ(j["pieces"][0]["connectors"][k]["x_mm"], j["pieces"][1]["connectors"][k]["x_mm"]);
        EXPECT_EQ(j["pieces"][0]["connectors"][k]["y_mm"], j["pieces"][1]["connectors"][k]["y_mm"]);
    }
    // Both pieces flat on the bed: each prints on the first layer; the lower one (40 mm, 200
    // layers) stops where the upper one (60 mm) goes on.
    const std::string gcode = read(r.gcode_paths[0]);
    const std::string first = layer_text(gcode, 0);
    EXPECT_NE(first.find("printing object tall_piece1"), std::string::npos);
    EXPECT_NE(first.find("printing object tall_piece2"), std::string::npos);
    EXPECT_NE(layer_text(gcode, 199).find("printing object tall_piece1"), std::string::npos);
    EXPECT_EQ(layer_text(gcode, 200).find("printing object tall_piece1"), std::string::npos);
    EXPECT_NE(layer_text(gcode, 299).find("printing object tall_piece2"), std::string::npos);
    EXPECT_EQ(r.plates[0].layers, 300);
}

TEST(CutRun, AutoCutsAModelTwiceThePrintersHeight) {
    Settings s;
    s.cut_auto = true;
    s.cut_connectors = CutConnectors::Pin;
    const RunOptions o =
        cut_options(box_model("tower.stl", 40, 30, 2 * s.max_print_height), "tower");
    const CutRunResult r = run_cut(s, o);
    const nlohmann::json j = nlohmann::json::parse(read(o.stats_path));
    ASSERT_EQ(j["pieces"].size(), 3u);  // 420 mm in pieces no taller than 210 minus a pin
    EXPECT_EQ(j["cut"]["planes_mm"].size(), 2u);
    for (const auto& p : j["pieces"])
        EXPECT_LE(p["size_mm"][2].get<double>(), s.max_print_height + 1e-6);
    EXPECT_EQ(r.plates.size(), 1u);  // three 40 x 30 mm footprints side by side
    EXPECT_TRUE(fs::exists(r.gcode_paths[0]));
}

TEST(CutRun, PiecesThatFillABedGoOnPlatesOfTheirOwn) {
    Settings s;
    s.cut_auto = true;
    s.cut_connectors = CutConnectors::None;
    const RunOptions o = cut_options(box_model("big.stl", 200, 150, 300), "big");
    const CutRunResult r = run_cut(s, o);
    ASSERT_EQ(r.plates.size(), 2u);
    EXPECT_TRUE(fs::exists(scratch() / "big-plate1.gcode"));
    EXPECT_TRUE(fs::exists(scratch() / "big-plate2.gcode"));
    EXPECT_FALSE(fs::exists(scratch() / "big.gcode"));
    const nlohmann::json j = nlohmann::json::parse(read(o.stats_path));
    EXPECT_EQ(j["plates"].size(), 2u);
    EXPECT_NE(j["pieces"][0]["plate"], j["pieces"][1]["plate"]);
}

TEST(CutRun, AModelNoCutFitsIsRefusedWithNothingWritten) {
    Settings s;
    s.cut_auto = true;
    // Four planes across each of x, y and z at most leave pieces of 250 mm in all three.
    const RunOptions wide = cut_options(box_model("wide.stl", 1000, 1000, 1000), "wide_out");
    test::refusal<InputError>(s, wide);
    // A given cut that leaves a piece too tall names the piece.
    Settings given;
    given.cut_at = {100};
    const RunOptions tall = cut_options(box_model("high.stl", 30, 20, 400), "high_out");
    const std::string message = test::refusal<InputError>(given, tall);
    EXPECT_NE(message.find("piece 2 of 2"), std::string::npos) << message;
    EXPECT_EQ(test::left_behind("wide_out"), std::vector<std::string>{});
    EXPECT_EQ(test::left_behind("high_out"), std::vector<std::string>{});
}

// The extent in x and y of what layer n extrudes for each object, by its label.
std::map<std::string, std::array<double, 4>> first_layer_boxes(const std::string& gcode) {
    std::map<std::string, std::array<double, 4>> boxes;
    std::istringstream in(layer_text(gcode, 0));
    std::string object;
    double x = 0, y = 0;
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("; printing object ", 0) == 0) object = line.substr(18);
        if (line.rfind("; stop printing object", 0) == 0) object.clear();
        if (line.rfind("G1 ", 0) != 0 && line.rfind("G0 ", 0) != 0) continue;
        double nx = x, ny = y;
        bool extrudes = false;
        std::istringstream words(line.substr(0, line.find(';')));
        for (std::string w; words >> w;) {
            if (w[0] == 'X') nx = std::stod(w.substr(1));
            if (w[0] == 'Y') ny = std::stod(w.substr(1));
            if (w[0] == 'E') extrudes = std::stod(w.substr(1)) > 0;
        }
        if (extrudes && !object.empty() && (nx != x || ny != y)) {
            auto [it, fresh] = boxes.try_emplace(object, std::array<double, 4>{x, y, x, y});
            auto& b = it->second;
            for (auto [px, py] : {std::pair{x, y}, std::pair{nx, ny}})
                b = {std::min(b[0], px), std::min(b[1], py), std::max(b[2], px),
                     std::max(b[3], py)};
        }
        x = nx, y = ny;
    }
    return boxes;
}

TEST(CutRun, ALongBoxIsCutAcrossXIntoTwoPiecesEachOnItsCutFace) {
    Settings s;  // a 250 x 210 x 210 mm printer
    s.cut_auto = true;
    const RunOptions o = cut_options(box_model("long.stl", 300, 60, 40), "long");
    const CutRunResult r = run_cut(s, o);
    const nlohmann::json j = nlohmann::json::parse(read(o.stats_path));
    ASSERT_EQ(j["pieces"].size(), 2u);
    ASSERT_EQ(j["cut"]["planes"].size(), 1u);
    EXPECT_EQ(j["cut"]["planes"][0]["normal"], (std::vector<double>{1, 0, 0}));
    double total = 0;
    for (const auto& p : j["pieces"]) {
        total += p["volume_mm3"].get<double>();
        // On its cut face: 60 x 40 mm down (either way round), 150 mm up.
        const double w = p["size_mm"][0], d = p["size_mm"][1], h = p["size_mm"][2];
        EXPECT_NEAR(std::max(w, d), 60, 1e-3);
        EXPECT_NEAR(std::min(w, d), 40, 1e-3);
        EXPECT_NEAR(h, 150, 1e-3);
        for (const auto& c : p["connectors"]) EXPECT_NEAR(c["x_mm"].get<double>(), 150, 1e-3);
    }
    EXPECT_NEAR(total, 300 * 60 * 40, 0.01 * 300 * 60 * 40);
    // Each piece's first layer covers its cut face, less the extrusion's half width round it.
    const auto boxes = first_layer_boxes(read(r.gcode_paths[0]));
    ASSERT_EQ(boxes.size(), 2u);
    for (const auto& [name, b] : boxes)
        EXPECT_NEAR((b[2] - b[0]) * (b[3] - b[1]), 60 * 40, 0.05 * 60 * 40) << name;
    EXPECT_EQ(r.plates[0].layers, 750);
}

TEST(CutRun, ACutPlaneAcrossZGivesThePiecesOfCut) {
    const std::string model = box_model("plane.stl", 30, 20, 100);
    Settings by_height;
    by_height.cut_at = {40};
    Settings by_plane;
    by_plane.cut_planes = {0, 0, 40, 0, 0, 1};
    const RunOptions a = cut_options(model, "by_height"), b = cut_options(model, "by_plane");
    run_cut(by_height, a);
    run_cut(by_plane, b);
    const nlohmann::json ja = nlohmann::json::parse(read(a.stats_path));
    const nlohmann::json jb = nlohmann::json::parse(read(b.stats_path));
    ASSERT_EQ(ja["pieces"].size(), 2u);
    for (size_t k = 0; k < 2; ++k)
        for (const char* key : {"volume_mm3", "bbox", "size_mm", "connectors"})
            EXPECT_EQ(ja["pieces"][k][key], jb["pieces"][k][key]) << key;
    // The same plane tilted: still two pieces of the box's volume.
    Settings tilted;
    tilted.cut_planes = {15, 10, 50, 0.3, 0, 1};
    const RunOptions t = cut_options(model, "tilted");
    run_cut(tilted, t);
    const nlohmann::json jt = nlohmann::json::parse(read(t.stats_path));
    ASSERT_EQ(jt["pieces"].size(), 2u);
    EXPECT_NEAR(
        jt["pieces"][0]["volume_mm3"].get<double>() + jt["pieces"][1]["volume_mm3"].get<double>(),
        30 * 20 * 100, 0.01 * 30 * 20 * 100);
}

// Issue #48: the skull at 225 x 314 x 360 mm, whose footprint no cut across z fits an MK3S.
TEST(CutRun, TheScaledSkullIsCutToFitAnMk3s) {
    SKIP_UNDER_SANITIZERS("the long box's cut across x");
    const std::string skull = test::shared_model("skull.stl");
    if (skull.empty()) GTEST_SKIP() << "no shared skull.stl beside the repository";
    Settings s;
    apply_printer_preset("mk3s", s);
    s.scale = 3;
    s.cut_auto = true;
    s.layer_height = 0.3;
    RunOptions o = cut_options(skull, "skull");
    o.model_path = skull;
    // Every plate passes carve check --strict (issue #48 item 3). Before the fades of ties were
    // kept on their ribs and the start G-code's intro line was no layer of the check, plate 1
    // failed: 11,000 mm2 hanging inside, its bottom skin 18.6 % open.
    o.strict = true;
    const CutRunResult r = run_cut(s, o);
    const nlohmann::json j = nlohmann::json::parse(read(o.stats_path));
    EXPECT_GE(j["pieces"].size(), 2u);
    EXPECT_FALSE(j["cut"]["planes"].empty());
    double total = 0;
    for (const auto& p : j["pieces"]) {
        total += p["volume_mm3"].get<double>();
        const double w = p["size_mm"][0], d = p["size_mm"][1], h = p["size_mm"][2];
        EXPECT_LE(w, 250);
        EXPECT_LE(d, 210);
        EXPECT_LE(h, 210);
    }
    EXPECT_NEAR(total, j["model_volume_mm3"].get<double>(),
                0.01 * j["model_volume_mm3"].get<double>());
    for (const std::string& path : r.gcode_paths) EXPECT_TRUE(fs::exists(path)) << path;
}

}  // namespace
}  // namespace carve

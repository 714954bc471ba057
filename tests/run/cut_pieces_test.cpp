// Issue #48, what a cut leaves beside its plates: the picture of the pieces with their cut faces
// and connectors, --strict on every plate, and --orient auto turning each piece on its own.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <vector>

#include "base/error.hpp"
#include "run/pipeline.hpp"
#include "support/carve_run.hpp"
#include "support/cut_runs.hpp"
#include "support/sanitizers.hpp"
#include "support/stl_boxes.hpp"

namespace fs = std::filesystem;

namespace carve {
namespace {

using test::box_model;
using test::cut_options;

struct Circle {
    std::string cls;
    double x = 0, y = 0;
    bool dashed = false;
};

// One piece's group of the picture: its name, the box of its outline (px) and its connectors.
struct DrawnPiece {
    std::string name;
    std::array<double, 4> box{1e9, 1e9, -1e9, -1e9};
    int cut_faces = 0;
    std::vector<Circle> circles;
};

std::vector<DrawnPiece> drawn_pieces(const std::string& svg) {
    std::vector<DrawnPiece> pieces;
    const std::regex group(R"~(<g class="piece" data-name="([^"]+)">([\s\S]*?)</g>)~");
    const std::regex outline(R"~(class="outline"[^>]* d="([^"]*)")~");
    const std::regex number(R"~((-?[0-9.]+) (-?[0-9.]+))~");
    const std::regex circle(
        R"~(<circle class="(hole|pin)" cx="([0-9.]+)" cy="([0-9.]+)"([^>]*)>)~");
    for (auto g = std::sregex_iterator(svg.begin(), svg.end(), group); g != std::sregex_iterator();
         ++g) {
        DrawnPiece p;
        p.name = (*g)[1];
        const std::string body = (*g)[2];
        std::smatch m;
        if (std::regex_search(body, m, outline)) {
            const std::string d = m[1];
            for (auto n = std::sregex_iterator(d.begin(), d.end(), number);
                 n != std::sregex_iterator(); ++n) {
                const double x = std::stod((*n)[1]), y = std::stod((*n)[2]);
                p.box = {std::min(p.box[0], x), std::min(p.box[1], y), std::max(p.box[2], x),
                         std::max(p.box[3], y)};
            }
        }
        for (size_t at = body.find("class=\"cut-face\""); at != std::string::npos;
             at = body.find("class=\"cut-face\"", at + 1))
            ++p.cut_faces;
        for (auto c = std::sregex_iterator(body.begin(), body.end(), circle);
             c != std::sregex_iterator(); ++c)
            p.circles.push_back(
                {(*c)[1], std::stod((*c)[2]), std::stod((*c)[3]),
                 std::string((*c)[4]).find(R"(dasharray="2 2")") != std::string::npos});
        pieces.push_back(std::move(p));
    }
    return pieces;
}

// A tall box cut at 40 mm: the picture beside the G-code names both pieces, draws each one's cut
// face and its two dowel holes, at the same place in both pieces' outlines (the holes match), the
// upper piece's dashed (they are in the face it stands on).
TEST(CutPicture, NamesEveryPieceWithItsCutFaceAndHoles) {
    Settings s;
    s.cut_at = {40};
    const RunOptions o = cut_options(box_model("pic.stl", 30, 20, 100), "pic");
    const CutRunResult r = run_cut(s, o);
    EXPECT_EQ(r.picture_path, (test::scratch() / "pic-pieces.svg").string());
    ASSERT_TRUE(fs::exists(r.picture_path));
    const nlohmann::json j = nlohmann::json::parse(test::read(o.stats_path));
    EXPECT_EQ(j["cut"]["picture"], r.picture_path);
    const std::string svg = test::read(r.picture_path);
    EXPECT_NE(svg.find("pic-plate1.gcode"), std::string::npos);
    const std::vector<DrawnPiece> pieces = drawn_pieces(svg);
    ASSERT_EQ(pieces.size(), 2u);
    EXPECT_EQ(pieces[0].name, "pic_piece1");
    EXPECT_EQ(pieces[1].name, "pic_piece2");
    for (size_t k = 0; k < 2; ++k) {
        const DrawnPiece& p = pieces[k];
        EXPECT_EQ(p.cut_faces, 1) << p.name;
        // 30 x 20 mm at 2 px a mm.
        EXPECT_NEAR(p.box[2] - p.box[0], 60, 1) << p.name;
        EXPECT_NEAR(p.box[3] - p.box[1], 40, 1) << p.name;
        ASSERT_EQ(p.circles.size(), j["pieces"][k]["connectors"].size()) << p.name;
        ASSERT_EQ(p.circles.size(), 2u) << p.name;
        for (const Circle& c : p.circles) {
            EXPECT_EQ(c.cls, "hole");
            EXPECT_EQ(c.dashed, k == 1) << p.name;
            EXPECT_GT(c.x, p.box[0]);
            EXPECT_LT(c.x, p.box[2]);
            EXPECT_GT(c.y, p.box[1]);
            EXPECT_LT(c.y, p.box[3]);
        }
    }
    for (size_t c = 0; c < 2; ++c) {
        EXPECT_NEAR(pieces[0].circles[c].x - pieces[0].box[0],
                    pieces[1].circles[c].x - pieces[1].box[0], 0.2);
        EXPECT_NEAR(pieces[0].circles[c].y - pieces[0].box[1],
                    pieces[1].circles[c].y - pieces[1].box[1], 0.2);
    }
}

// Cut across x, each piece on its cut face: both faces drawn flat on the bed, pins solid on one
// piece and holes on the other.
TEST(CutPicture, PinsAndHolesOfACutAcrossX) {
    Settings s;
    s.cut_planes = {150, 0, 0, 1, 0, 0};
    s.cut_connectors = CutConnectors::Pin;
    const RunOptions o = cut_options(box_model("pins.stl", 300, 60, 40), "pins");
    const CutRunResult r = run_cut(s, o);
    const std::vector<DrawnPiece> pieces = drawn_pieces(test::read(r.picture_path));
    ASSERT_EQ(pieces.size(), 2u);
    int pins = 0, holes = 0;
    for (const DrawnPiece& p : pieces) {
        EXPECT_EQ(p.cut_faces, 1) << p.name;
        for (const Circle& c : p.circles) ++(c.cls == "pin" ? pins : holes);
    }
    EXPECT_GT(pins, 0);
    EXPECT_EQ(pins, holes);
}

// --strict on a cut: every plate measured against its own pieces. The tall box's plate passes and
// is written with its verdict in the stats; with no covers its skins are open, and the run is
// refused with nothing written, no plate, picture or stats.
TEST(CutStrict, EveryPlatePassesOrNothingIsWritten) {
    const std::string model = box_model("strict.stl", 30, 20, 100);
    Settings s;
    s.cut_at = {40};
    RunOptions o = cut_options(model, "strict_good");
    o.strict = true;
    const CutRunResult r = run_cut(s, o);
    ASSERT_EQ(r.gcode_paths.size(), 1u);
    EXPECT_TRUE(fs::exists(r.gcode_paths[0]));
    const nlohmann::json j = nlohmann::json::parse(test::read(o.stats_path));
    EXPECT_TRUE(j["plates"][0]["check"]["printability"]["passes"].get<bool>());
    s.covers = 0;
    o = cut_options(model, "strict_bad");
    o.strict = true;
    const std::string message = test::refusal<RuleError>(s, o);
    EXPECT_NE(message.find("strict_bad-plate1.gcode: fails carve check --strict"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("skin left open"), std::string::npos) << message;
    EXPECT_EQ(test::left_behind("strict_bad"), std::vector<std::string>{});
}

// carve slice --strict on one output: status 5, the rules on stderr, no G-code; without it the
// same run writes its G-code.
TEST(CutStrict, ASingleOutputThatFailsIsNotWritten) {
    const std::string model = box_model("strict_one.stl", 30, 20, 20);
    const auto gcode = test::scratch() / "strict_one.gcode";
    test::CarveRun r =
        test::run_carve("slice " + model + " -o " + gcode.string() + " --covers 0 --strict -q");
    EXPECT_EQ(r.status, 5) << r.err;
    EXPECT_NE(r.err.find("strict_one.gcode: fails carve check --strict (top skin left open"),
              std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(gcode));
    r = test::run_carve("slice " + model + " -o " + gcode.string() + " --strict -q");
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(fs::exists(gcode));
}

// A stem under a wide cap, cut across the stem: on its cut face the upper piece holds its cap up
// on supports; with --orient auto it is turned off that face to the lightest of its candidates
// (a face of its hull across the cap's rim), and the lower piece keeps standing as it stood.
TEST(CutOrient, EachPieceInTheOrientationWithLeastMaterial) {
    SKIP_UNDER_SANITIZERS("the candidates of two pieces, each carved");
    std::vector<test::StlTriangle> t;
    test::add_box(t, 20, 20, 0, 40, 40, 42);
    test::add_box(t, 0, 0, 40, 60, 60, 45);
    const std::string model = test::write_stl("mushroom.stl", t).string();
    Settings s;
    s.cut_at = {20};
    s.support = SupportMode::Auto;
    const RunOptions given = cut_options(model, "mushroom_given");
    run_cut(s, given);
    s.orient = OrientMode::Auto;
    const RunOptions o = cut_options(model, "mushroom_auto");
    const CutRunResult r = run_cut(s, o);
    const nlohmann::json a = nlohmann::json::parse(test::read(given.stats_path));
    const nlohmann::json j = nlohmann::json::parse(test::read(o.stats_path));
    ASSERT_EQ(j["pieces"].size(), 2u);
    EXPECT_FALSE(a["pieces"][1].contains("orientation"));
    for (const auto& p : j["pieces"]) {
        ASSERT_TRUE(p.contains("orientation")) << p["name"];
        // Those given up part way extruded more than the one chosen by then; of the others,
        // ties within half a percent go to the shorter print.
        double least = 1e18, chosen = 0, given_up_above = 1e18;
        for (const auto& c : p["orientation"]["candidates"]) {
            if (!c["fits"].get<bool>()) continue;
            if (c["given_up"].get<bool>()) {
                given_up_above = std::min(given_up_above, c["extruded_at_least_mm3"].get<double>());
                continue;
            }
            least = std::min(least, c["extruded_volume_mm3"].get<double>());
            if (c["chosen"].get<bool>()) chosen = c["extruded_volume_mm3"].get<double>();
        }
        EXPECT_GT(chosen, 0) << p["name"];
        EXPECT_LE(chosen, least * 1.005) << p["name"];
        EXPECT_LT(chosen, given_up_above) << p["name"];
    }
    EXPECT_EQ(j["pieces"][0]["orientation"]["chosen"]["name"], "as given");
    EXPECT_NE(j["pieces"][1]["orientation"]["chosen"]["name"], "as given");
    EXPECT_LT(j["extruded_volume_mm3"].get<double>(), a["extruded_volume_mm3"].get<double>());
    EXPECT_LT(j["plates"][0]["support_volume_mm3"].get<double>(),
              a["plates"][0]["support_volume_mm3"].get<double>());
    // The upper piece (the stem from 20 mm up, the cap) is printed turned as the choice says:
    // its size on the bed is its corners' extent under the rotation chosen.
    const nlohmann::json& m = j["pieces"][1]["orientation"]["chosen"]["matrix"];
    auto turned = [&](const std::array<double, 3>& v) {
        std::array<double, 3> out{};
        for (size_t i = 0; i < 3; ++i)
            for (size_t k = 0; k < 3; ++k) out[i] += m[i][k].get<double>() * v[k];
        return out;
    };
    std::array<double, 3> lo{1e9, 1e9, 1e9}, hi{-1e9, -1e9, -1e9};
    for (const auto& [x0, y0, z0, x1, y1, z1] : {std::array<double, 6>{20, 20, 20, 40, 40, 42},
                                                 std::array<double, 6>{0, 0, 40, 60, 60, 45}})
        for (int c = 0; c < 8; ++c) {
            const auto p = turned({c & 1 ? x1 : x0, c & 2 ? y1 : y0, c & 4 ? z1 : z0});
            for (size_t i = 0; i < 3; ++i)
                lo[i] = std::min(lo[i], p[i]), hi[i] = std::max(hi[i], p[i]);
        }
    const auto& up = j["pieces"][1]["size_mm"];
    const double w = up[0], d = up[1];
    EXPECT_NEAR(std::max(w, d), std::max(hi[0] - lo[0], hi[1] - lo[1]), 0.01);
    EXPECT_NEAR(std::min(w, d), std::min(hi[0] - lo[0], hi[1] - lo[1]), 0.01);
    EXPECT_NEAR(up[2].get<double>(), hi[2] - lo[2], 0.01);
    EXPECT_GT(std::abs(up[2].get<double>() - 25), 1);  // not on its cut face
    // The picture draws the holes as the piece lies: in the face on the bed (dashed) when their
    // face looks down.
    const std::vector<DrawnPiece> pieces = drawn_pieces(test::read(r.picture_path));
    ASSERT_EQ(pieces.size(), 2u);
    ASSERT_EQ(pieces[1].circles.size(), j["pieces"][1]["connectors"].size());
    for (size_t k = 0; k < pieces[1].circles.size(); ++k) {
        const auto& n = j["pieces"][1]["connectors"][k]["normal"];
        const double down = turned({n[0].get<double>(), n[1].get<double>(), n[2].get<double>()})[2];
        EXPECT_EQ(pieces[1].circles[k].dashed, down < -0.5) << down;
    }
}

}  // namespace
}  // namespace carve

// Issue #48, the files a cut writes and the options that follow it onto the plates: each plate's
// pieces as a mesh that carve check --mesh --strict takes as it stands, --pause-at as heights on
// the plates, and the outputs a cut makes checked as the CLI checks the run's.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "base/error.hpp"
#include "mesh/mesh.hpp"
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

size_t count(const std::string& text, const std::string& what) {
    size_t n = 0;
    for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
}

// A tall box cut at 40 mm onto one plate: the plate's mesh holds both pieces, as much of them as
// the stats say, and carve check takes it with the plate's G-code under --strict with no offset
// to find (the mesh lies where the G-code prints it).
TEST(CutOutputs, EachPlatesMeshIsWhereItsGcodePrintsIt) {
    Settings s;
    s.cut_at = {40};
    RunOptions o = cut_options(box_model("meshes.stl", 30, 20, 100), "meshes");
    o.plate_meshes = true;
    const CutRunResult r = run_cut(s, o);
    ASSERT_EQ(r.mesh_paths.size(), 1u);
    EXPECT_EQ(r.mesh_paths[0], (test::scratch() / "meshes-plate1.stl").string());
    MeshReport report;
    const Mesh plate = load_mesh(r.mesh_paths[0], report);
    EXPECT_EQ(report.open_edges, 0u);
    const nlohmann::json j = nlohmann::json::parse(test::read(o.stats_path));
    double pieces = 0;
    for (const auto& p : j["pieces"]) pieces += p["volume_mm3"].get<double>();
    EXPECT_NEAR(signed_volume(plate), pieces, 1e-3 * pieces);
    const test::CarveRun check = test::run_carve("check " + r.gcode_paths[0] + " --mesh " +
                                                 r.mesh_paths[0] + " --mesh-offset 0,0 --strict");
    EXPECT_EQ(check.status, 0) << check.out << check.err;
    // Without the offset carve check finds the same place from the extrusion.
    const test::CarveRun found = test::run_carve("check " + r.gcode_paths[0] + " --mesh " +
                                                 r.mesh_paths[0] + " --strict --json");
    ASSERT_EQ(found.status, 0) << found.err;
    const nlohmann::json c = nlohmann::json::parse(found.out);
    EXPECT_NEAR(c["mesh_offset_mm"][0].get<double>(), 0, 0.5) << found.out;
    EXPECT_NEAR(c["mesh_offset_mm"][1].get<double>(), 0, 0.5) << found.out;
}

// An 80 x 60 mm box cut at 80 of its 120 mm on a 100 mm bed: a piece a plate, 80 and 40 mm tall.
// A pause at 60 mm comes on the taller plate only, and the lower one says it prints without it;
// a pause above both plates is refused before anything is written.
TEST(CutOutputs, APauseIsAHeightOnEachPlate) {
    Settings s;
    s.cut_at = {80};
    s.cut_connectors = CutConnectors::None;
    s.bed_x = s.bed_y = 100;
    s.pause_at = {60};
    const std::string model = box_model("paused.stl", 80, 60, 120);
    RunOptions o = cut_options(model, "paused");
    std::vector<std::string> notes;
    o.note = [&](const std::string& n) { notes.push_back(n); };
    const CutRunResult r = run_cut(s, o);
    ASSERT_EQ(r.gcode_paths.size(), 2u);
    const std::string tall = test::read(r.gcode_paths[0]), low = test::read(r.gcode_paths[1]);
    EXPECT_EQ(count(tall, "\nM600"), 1u);
    EXPECT_EQ(count(low, "\nM600"), 0u);
    bool said = false;
    for (const std::string& n : notes)
        said = said || n.find("plate 2 is 40.00 mm tall and prints without the pause at 60 mm") !=
                           std::string::npos;
    EXPECT_TRUE(said);
    s.pause_at = {100};
    o = cut_options(model, "paused_high");
    const std::string message = test::refusal<InputError>(s, o);
    EXPECT_NE(message.find("--pause-at 100 mm is above every plate's top"), std::string::npos)
        << message;
    EXPECT_EQ(test::left_behind("paused_high"), std::vector<std::string>{});
}

// The stats named as the picture the cut draws: refused, naming both, with nothing written.
TEST(CutOutputs, AnOutputThatIsAnotherOfTheCutsIsRefused) {
    Settings s;
    s.cut_at = {40};
    RunOptions o = cut_options(box_model("clash.stl", 30, 20, 100), "clash");
    o.stats_path = (test::scratch() / "clash-pieces.svg").string();
    const std::string message = test::refusal<OutputError>(s, o);
    EXPECT_NE(message.find("is the same file as the pieces' picture"), std::string::npos)
        << message;
    EXPECT_EQ(test::left_behind("clash-"), std::vector<std::string>{});
}

// --plate-meshes says what it needs rather than doing nothing.
TEST(CutOutputs, PlateMeshesWithoutACutIsAUsageError) {
    const std::string model = box_model("uncut.stl", 20, 20, 20);
    const auto gcode = test::scratch() / "uncut.gcode";
    const test::CarveRun r =
        test::run_carve("slice " + model + " -o " + gcode.string() + " --plate-meshes");
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("--plate-meshes needs --cut or --cut-plane"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(gcode));
}

}  // namespace
}  // namespace carve

// Hostile inputs and hostile environments, end to end through the carve executable: meshes
// written here by a small STL writer (huge coordinates, below the bed, overlapping shells,
// thinner than a line), the --max-vertices-per-layer guard, and a disk that fills up. Each case
// must end in a clear one-line message and no output file, or in a sensible G-code.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "geometry/polygon.hpp"
#include "mesh/mesh.hpp"
#include "slice/slicer.hpp"
#include "support/carve_run.hpp"
#include "support/regex.hpp"

namespace fs = std::filesystem;
using namespace carve;
using namespace carve::test;

namespace {

using Triangle = std::array<Vec3, 3>;

// Axis-aligned box [x0,x1]x[y0,y1]x[z0,z1], twelve triangles counter-clockwise from outside.
std::vector<Triangle> box(double x0, double y0, double z0, double x1, double y1, double z1) {
    auto p = [&](int i) { return Vec3{(i & 1) ? x1 : x0, (i & 2) ? y1 : y0, (i & 4) ? z1 : z0}; };
    // Corner i has bit 0 = x, bit 1 = y, bit 2 = z; each quad is listed counter-clockwise.
    const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    std::vector<Triangle> out;
    for (const auto& q : quads) {
        out.push_back({p(q[0]), p(q[1]), p(q[2])});
        out.push_back({p(q[0]), p(q[2]), p(q[3])});
    }
    return out;
}

// Binary STL (little-endian host assumed, as everywhere in this project's tests).
fs::path write_stl(const std::string& name, const std::vector<Triangle>& triangles) {
    const fs::path path = scratch() / name;
    std::ofstream out(path, std::ios::binary);
    char header[80] = {};
    out.write(header, 80);
    const uint32_t n = static_cast<uint32_t>(triangles.size());
    out.write(reinterpret_cast<const char*>(&n), 4);
    for (const Triangle& t : triangles) {
        float f[12] = {};
        for (int v = 0; v < 3; ++v) {
            f[3 + 3 * v] = static_cast<float>(t[v].x);
            f[4 + 3 * v] = static_cast<float>(t[v].y);
            f[5 + 3 * v] = static_cast<float>(t[v].z);
        }
        out.write(reinterpret_cast<const char*>(f), sizeof f);
        const uint16_t attribute = 0;
        out.write(reinterpret_cast<const char*>(&attribute), 2);
    }
    return path;
}

// Files in `dir` whose name starts with `stem` (the output, its .tmp-XXXXXX and .spill-XXXXXX).
std::vector<std::string> leftovers(const fs::path& dir, const std::string& stem) {
    std::vector<std::string> found;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().filename().string().rfind(stem, 0) == 0)
            found.push_back(e.path().filename().string());
    return found;
}

// stderr without the progress lines ("carve: 10/100 layers (10 %), ...") that a run prints
// when stderr is not a terminal: a failure found after slicing started follows them.
std::string without_progress(const std::string& err) {
    static const carve::test::Regex progress(R"(^carve: \d+/\d+ layers .*\n)");
    std::string out, line;
    std::istringstream in(err);
    while (std::getline(in, line))
        if (!progress.match(line + "\n")) out += line + "\n";
    return out;
}

// Expects exit `status` (1: a refused input; 3: an output not written), one line on stderr
// (besides progress) containing `needle`, and nothing left named like `gcode`.
void expect_refused(const CarveRun& run, const fs::path& gcode, const std::string& needle,
                    int status = 1) {
    CarveRun r = run;
    r.err = without_progress(run.err);
    EXPECT_EQ(r.status, status) << r.err;
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_EQ(r.err.rfind("carve: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << r.err;
    EXPECT_TRUE(leftovers(gcode.parent_path(), gcode.filename().string()).empty());
}

// The value of a ";KEY:value" header line of a G-code text, or NaN.
double header_value(const std::string& gcode, const std::string& key) {
    const size_t at = gcode.find(";" + key + ":");
    if (at == std::string::npos) return std::nan("");
    return std::stod(gcode.substr(at + key.size() + 2));
}

}  // namespace

TEST(Hostile, CoordinatesBeyondTheIntegerRangeAreAClearError) {
    // 1e30 mm is far beyond what micrometre integers (or any printer) hold; float32 still
    // stores it, so the loader must refuse it by value.
    std::vector<Triangle> t = box(0, 0, 0, 20, 20, 20);
    t[3][1] = {1e30, 5, 5};
    const fs::path stl = write_stl("huge.stl", t), gcode = scratch() / "huge.gcode";
    expect_refused(run_carve("slice " + stl.string() + " -o " + gcode.string()), gcode,
                   "beyond +-1 km");
}

TEST(Hostile, ModelBelowTheBedIsDroppedOntoIt) {
    // A 20 mm cube floating 50 mm below z = 0: printed from the bed up, first layer at h.
    const fs::path stl = write_stl("below.stl", box(0, 0, -50, 20, 20, -30));
    const fs::path gcode = scratch() / "below.gcode";
    const CarveRun r = run_carve("slice " + stl.string() + " -o " + gcode.string() +
                                 " --cavities 1 --layer-height 0.2 -q");
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string g = read(gcode);
    EXPECT_DOUBLE_EQ(header_value(g, "MINZ"), 0.2);
    EXPECT_DOUBLE_EQ(header_value(g, "MAXZ"), 20.0);
    EXPECT_EQ(header_value(g, "LAYER_COUNT"), 100);
    // Same bytes as the cube standing on the bed, apart from the "; model = path" line.
    const fs::path stl_on = write_stl("on.stl", box(0, 0, 0, 20, 20, 20));
    const fs::path gcode_on = scratch() / "on.gcode";
    ASSERT_EQ(run_carve("slice " + stl_on.string() + " -o " + gcode_on.string() +
                        " --cavities 1 --layer-height 0.2 -q")
                  .status,
              0);
    std::string a = g, b = read(gcode_on);
    a.erase(0, a.find('\n', a.find("; model = ")));
    b.erase(0, b.find('\n', b.find("; model = ")));
    a = carve::test::Regex("object below").replace(a, "object on");  // the object labels
    a = carve::test::Regex("M486 Abelow").replace(a, "M486 Aon");
    EXPECT_TRUE(a == b);
}

TEST(Hostile, OverlappingShellsAreUnited) {
    // Two 20 mm cubes overlapping in a 10 x 10 x 20 block: every slice is their union,
    // 400 + 400 - 100 mm^2, and the whole prints.
    std::vector<Triangle> t = box(0, 0, 0, 20, 20, 20);
    for (const Triangle& u : box(10, 10, 0, 30, 30, 20)) t.push_back(u);
    const fs::path stl = write_stl("overlap.stl", t);
    MeshReport report;
    const Mesh mesh = load_mesh(stl.string(), report);
    EXPECT_EQ(report.shells, 2u);
    for (double z : {0.1, 5.0, 10.0, 19.9}) {
        const Paths region = slice_at(mesh, z);
        EXPECT_NEAR(area_mm2(region), 700.0, 1e-6) << z;
        EXPECT_EQ(region.size(), 1u) << z;
    }
    const fs::path gcode = scratch() / "overlap.gcode";
    const CarveRun r =
        run_carve("slice " + stl.string() + " -o " + gcode.string() + " --cavities 2 -q");
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(fs::exists(gcode));
}

TEST(Hostile, ModelThinnerThanALineIsAClearError) {
    // A 0.08 mm fin, 20 mm long and tall: narrower than the smallest part printed (0.1 mm at a
    // 0.4 mm nozzle), nothing can be printed. A 0.2 mm fin is printed (thin walls, #47).
    const fs::path stl = write_stl("fin.stl", box(0, 0, 0, 20, 0.08, 20));
    const fs::path gcode = scratch() / "fin.gcode";
    expect_refused(run_carve("slice " + stl.string() + " -o " + gcode.string()), gcode,
                   "narrower than 0.1 mm, the smallest part printed");
    // A 0.05 mm sheet: thinner than one layer.
    const fs::path sheet = write_stl("sheet.stl", box(0, 0, 0, 20, 20, 0.05));
    const fs::path gcode2 = scratch() / "sheet.gcode";
    expect_refused(run_carve("slice " + sheet.string() + " -o " + gcode2.string()), gcode2,
                   "thinner than one layer");
}

TEST(ResourceGuard, TooManyVerticesInASliceStopsTheRun) {
    // A 40-sided prism has about 40 contour vertices per slice (the union may split an edge or
    // two): a limit of 30 must stop the run, with either thread count, and leave nothing behind;
    // 60 lets it through.
    std::vector<Triangle> t;
    const int n = 40;
    auto rim = [&](int i, double z) {
        const double a = 2 * 3.14159265358979 * (i % n) / n;
        return Vec3{10 + 8 * std::cos(a), 10 + 8 * std::sin(a), z};
    };
    const Vec3 bottom{10, 10, 0}, top{10, 10, 10};
    for (int i = 0; i < n; ++i) {
        t.push_back({bottom, rim(i + 1, 0), rim(i, 0)});
        t.push_back({top, rim(i, 10), rim(i + 1, 10)});
        t.push_back({rim(i, 0), rim(i + 1, 0), rim(i + 1, 10)});
        t.push_back({rim(i, 0), rim(i + 1, 10), rim(i, 10)});
    }
    const fs::path stl = write_stl("prism.stl", t);
    for (const char* threads : {"1", "2", "5"}) {
        const fs::path gcode = scratch() / "prism.gcode";
        expect_refused(run_carve("slice " + stl.string() + " -o " + gcode.string() +
                                 " --max-vertices-per-layer 30 --threads " + threads),
                       gcode, "the limit of 30");
        const CarveRun ok = run_carve("slice " + stl.string() + " -o " + gcode.string() +
                                      " --max-vertices-per-layer 60 -q --threads " + threads);
        EXPECT_EQ(ok.status, 0) << ok.err;
        EXPECT_TRUE(fs::exists(gcode));
        fs::remove(gcode);
    }
    const fs::path gcode = scratch() / "prism0.gcode";
    EXPECT_EQ(run_carve("slice " + stl.string() + " -o " + gcode.string() +
                        " --max-vertices-per-layer 0 -q")
                  .status,
              0);
    EXPECT_EQ(run_carve("slice " + stl.string() + " -o " + gcode.string() +
                        " --max-vertices-per-layer -5")
                  .status,
              1);
}

TEST(DiskFull, FileSizeLimitGivesOneLineAndLeavesNoFile) {
    // RLIMIT_FSIZE of 16 KiB (ulimit -f counts 512-byte blocks in dash, 1 KiB in bash: either
    // is far below the G-code of a 20 mm cube). carve must not die of SIGXFSZ but report the
    // failed write and remove its temporary files.
    const fs::path stl = write_stl("full.stl", box(0, 0, 0, 20, 20, 20));
    const fs::path dir = scratch() / "full";
    fs::create_directories(dir);
    const fs::path gcode = dir / "full.gcode";
    const CarveRun r =
        run_carve("slice " + stl.string() + " -o " + gcode.string() + " -q", "ulimit -f 16;");
    expect_refused(r, gcode, "cannot write", 3);
    EXPECT_TRUE(fs::is_empty(dir)) << leftovers(dir, "").size() << " files left";
    // And the previous G-code at that path survives a failed run untouched.
    {
        std::ofstream old(gcode);
        old << "; an older print\n";
    }
    const CarveRun again =
        run_carve("slice " + stl.string() + " -o " + gcode.string() + " -q", "ulimit -f 16;");
    EXPECT_EQ(again.status, 3);
    EXPECT_EQ(read(gcode), "; an older print\n");
    EXPECT_EQ(leftovers(dir, "").size(), 1u);
}

// The run's oneTBB pipeline in-process: an error raised on a worker, inside the parallel
// filter, must reach the caller as the same exception with its message, for any thread count,
// and leave no output behind.
#include "run/pipeline.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "base/error.hpp"
#include "run/span_log.hpp"
#include "support/scratch.hpp"

namespace fs = std::filesystem;

namespace carve {
namespace {

fs::path scratch() {
    static const test::ScratchDir dir("carve_pipeline_test_");
    return dir.path();
}

// A sphere of diameter 40 mm about the origin, 48 x 96 facets: the shape of the shared
// synthetic/sphere_40mm.stl (200 layers, cavities, bridges), made here so that the test needs
// nothing beside the repository. Written once, as a binary STL.
std::string sphere_stl() {
    static const std::string path = [] {
        const int rings = 48, segments = 96;
        const double r = 20;
        // The poles exactly, and segment `segments` as segment 0, so that facets share vertices.
        auto at = [&](int i, int j) -> std::array<float, 3> {
            if (i == 0) return {0, 0, float(r)};
            if (i == rings) return {0, 0, float(-r)};
            const double theta = std::numbers::pi * i / rings;
            const double phi = 2 * std::numbers::pi * (j % segments) / segments;
            return {float(r * std::sin(theta) * std::cos(phi)),
                    float(r * std::sin(theta) * std::sin(phi)), float(r * std::cos(theta))};
        };
        std::vector<std::array<std::array<float, 3>, 3>> facets;
        for (int i = 0; i < rings; ++i)
            for (int j = 0; j < segments; ++j) {
                // Counter-clockwise seen from outside: south (b), then east (d) of a.
                const auto a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
                if (i > 0) facets.push_back({a, b, d});
                if (i + 1 < rings) facets.push_back({b, c, d});
            }
        const fs::path p = scratch() / "sphere_40mm.stl";
        std::ofstream out(p, std::ios::binary);
        const char header[80] = {};
        out.write(header, sizeof header);
        const auto n = static_cast<std::uint32_t>(facets.size());
        out.write(reinterpret_cast<const char*>(&n), 4);
        for (const auto& t : facets) {
            float f[12] = {};  // the normal left zero: the loader works it out
            for (int v = 0; v < 3; ++v)
                for (int k = 0; k < 3; ++k) f[3 + 3 * v + k] = t[v][k];
            out.write(reinterpret_cast<const char*>(f), sizeof f);
            const std::uint16_t attribute = 0;
            out.write(reinterpret_cast<const char*>(&attribute), 2);
        }
        return p.string();
    }();
    return path;
}

RunOptions options_for(const fs::path& gcode) {
    RunOptions o;
    o.model_path = sphere_stl();
    o.gcode_path = gcode.string();
    return o;
}

class PipelineThreads : public ::testing::TestWithParam<int> {};

TEST_P(PipelineThreads, ErrorInParallelStageReachesCallerWithItsMessage) {
    Settings settings;
    settings.threads = GetParam();
    const fs::path gcode = scratch() / "fails.gcode";
    RunOptions o = options_for(gcode);
    std::thread::id caller = std::this_thread::get_id();
    bool on_worker = false;
    o.in_parallel_stage = [&](int layer) {
        if (std::this_thread::get_id() != caller) on_worker = true;
        if (layer == 57) throw InputError("layer 57 could not be planned");
    };
    try {
        run_slice(settings, o);
        ADD_FAILURE() << "the run went through";
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(), "layer 57 could not be planned");
    }
    EXPECT_FALSE(fs::exists(gcode));
    for (const auto& entry : fs::directory_iterator(scratch()))
        EXPECT_EQ(entry.path().string().find("fails.gcode"), std::string::npos)
            << "left behind: " << entry.path();
    // With one thread everything runs on the caller; with more, layers run on workers (not
    // guaranteed for any single layer, so only said, not asserted).
    if (GetParam() == 1) {
        EXPECT_FALSE(on_worker);
    }
}

TEST_P(PipelineThreads, OtherExceptionTypesKeepTheirType) {
    Settings settings;
    settings.threads = GetParam();
    const fs::path gcode = scratch() / "logic.gcode";
    RunOptions o = options_for(gcode);
    o.in_parallel_stage = [](int layer) {
        if (layer % 50 == 3)
            throw std::logic_error("broken invariant at layer " + std::to_string(layer));
    };
    EXPECT_THROW(
        {
            try {
                run_slice(settings, o);
            } catch (const std::logic_error& e) {
                EXPECT_NE(std::string(e.what()).find("broken invariant at layer"),
                          std::string::npos);
                throw;
            }
        },
        std::logic_error);
    EXPECT_FALSE(fs::exists(gcode));
}

TEST_P(PipelineThreads, SameFiguresAsOneThread) {
    Settings one;
    one.threads = 1;
    const RunResult a = run_slice(one, options_for(scratch() / "one.gcode"));
    Settings many;
    many.threads = GetParam();
    const RunResult b = run_slice(many, options_for(scratch() / "many.gcode"));
    EXPECT_EQ(a.layers, b.layers);
    EXPECT_EQ(a.bridges, b.bridges);
    EXPECT_EQ(a.layer_material_mm3, b.layer_material_mm3);  // exactly: summed in layer order
    EXPECT_EQ(a.cavity_volume_mm3, b.cavity_volume_mm3);
    EXPECT_EQ(a.print.extruded_volume_mm3, b.print.extruded_volume_mm3);
}

INSTANTIATE_TEST_SUITE_P(Threads, PipelineThreads, ::testing::Values(1, 2, 3, 8));

TEST(Pipeline, ThreadCountDefaultsToTheCoresAvailable) {
    Settings s;
    EXPECT_EQ(s.threads, 0);
    EXPECT_GE(thread_count(s), 1);
    s.threads = 7;
    EXPECT_EQ(thread_count(s), 7);
}

}  // namespace
}  // namespace carve

// The profile's critical path: a serial filter's layer waits for its own previous layer and
// for the filter before it on the same layer; what each filter adds along that chain says
// which one to split next.
TEST(Pipeline, CriticalPathNamesTheFiltersOnIt) {
    carve::SpanLog span(3, 3);  // layers 0..2, filters: parallel, serial, parallel
    span.serial = {false, true, false};
    const int64_t ms = 1000000;
    const int64_t cells[3][3] = {{5 * ms, 1 * ms, 1 * ms},  // layer 0
                                 {1 * ms, 4 * ms, 1 * ms},
                                 {1 * ms, 4 * ms, 2 * ms}};
    for (int n = 0; n < 3; ++n)
        for (int f = 0; f < 3; ++f) span.ns[size_t(n) * 3 + size_t(f)] = cells[n][f];
    // 5 (layer 0's first filter) + 1 + 4 + 4 (the serial filter, layers 0..2) + 2.
    const auto [path_s, by_filter] = span.critical_path_by_filter_s();
    EXPECT_NEAR(path_s, 0.016, 1e-12);
    EXPECT_NEAR(span.critical_path_s(), 0.016, 1e-12);
    ASSERT_EQ(by_filter.size(), 3u);
    EXPECT_NEAR(by_filter[0], 0.005, 1e-12);
    EXPECT_NEAR(by_filter[1], 0.009, 1e-12);
    EXPECT_NEAR(by_filter[2], 0.002, 1e-12);
}

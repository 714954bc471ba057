// Speed of the 24-gon morphology against Clipper's ClipperOffset (round joins) on noisy
// polygons, the kind of contour a sliced scanned model gives.
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <random>

#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"

using namespace carve;

namespace {

// A noisy circle of radius 20 mm with n vertices and +-80 um of radial noise.
Paths noisy_polygon(int n) {
    std::mt19937_64 engine(12345);
    Path p;
    for (int i = 0; i < n; ++i) {
        const double t = i * 2 * std::numbers::pi / n;
        const double noise = (double(engine() >> 11) / 9007199254740992.0 - 0.5) * 160.0;
        const double rad = 20000 + noise;
        p.emplace_back(Coord(std::llround(rad * std::cos(t))),
                       Coord(std::llround(rad * std::sin(t))));
    }
    return unite(Paths{p});
}

Paths clipper_offset(const Paths& region, double delta) {
    ClipperLib::ClipperOffset off;
    off.ArcTolerance = 0.25;  // a quarter micrometre, as our element's rounding
    off.AddPaths(region, ClipperLib::jtRound, ClipperLib::etClosedPolygon);
    Paths out;
    off.Execute(out, delta);
    return out;
}

size_t vertices(const Paths& region) {
    size_t n = 0;
    for (const Path& p : region) n += p.size();
    return n;
}

void BM_Dilate(benchmark::State& state) {
    const Paths s = noisy_polygon(int(state.range(0)));
    Paths out;
    for (auto _ : state) benchmark::DoNotOptimize(out = dilate(s, 200));
    state.counters["out_vertices"] = double(vertices(out));
}

void BM_Erode(benchmark::State& state) {
    const Paths s = noisy_polygon(int(state.range(0)));
    Paths out;
    for (auto _ : state) benchmark::DoNotOptimize(out = erode(s, 200));
    state.counters["out_vertices"] = double(vertices(out));
}

void BM_ClipperOffsetDilate(benchmark::State& state) {
    const Paths s = noisy_polygon(int(state.range(0)));
    Paths out;
    for (auto _ : state) benchmark::DoNotOptimize(out = clipper_offset(s, 200));
    state.counters["out_vertices"] = double(vertices(out));
}

void BM_ClipperOffsetErode(benchmark::State& state) {
    const Paths s = noisy_polygon(int(state.range(0)));
    Paths out;
    for (auto _ : state) benchmark::DoNotOptimize(out = clipper_offset(s, -200));
    state.counters["out_vertices"] = double(vertices(out));
}

// Fifty successive dilations by r, as a cavity grows over fifty slices.
void BM_Dilate50Times(benchmark::State& state) {
    const Paths s = noisy_polygon(int(state.range(0)));
    Paths out;
    for (auto _ : state) {
        out = s;
        for (int i = 0; i < 50; ++i) out = dilate(out, 200);
        benchmark::DoNotOptimize(out);
    }
    state.counters["out_vertices"] = double(vertices(out));
}

void BM_ClipperOffset50Times(benchmark::State& state) {
    const Paths s = noisy_polygon(int(state.range(0)));
    Paths out;
    for (auto _ : state) {
        out = s;
        for (int i = 0; i < 50; ++i) out = clipper_offset(out, 200);
        benchmark::DoNotOptimize(out);
    }
    state.counters["out_vertices"] = double(vertices(out));
}

}  // namespace

BENCHMARK(BM_Dilate)->Arg(5000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Erode)->Arg(5000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ClipperOffsetDilate)->Arg(5000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ClipperOffsetErode)->Arg(5000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Dilate50Times)->Arg(5000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ClipperOffset50Times)->Arg(5000)->Unit(benchmark::kMillisecond);

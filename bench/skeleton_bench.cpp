// Benchmarks of SKEL (report section 5.2), the hottest function of the carving sweep (k calls
// per layer): medial_axis() and skeleton() on synthetic regions and on real slices.
//
// Real slices come from a bench-local binary STL reader and plane cut (the product's slicer was
// not committed when this was written), then carved k = 6 times the way the sweep does it with
// the cavity above left out: V^j = V^{j-1} minus (SKEL(V^{j-1}) dilated by 2 mm).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"
#include "mesh/mesh.hpp"
#include "skeleton/skeleton.hpp"
#include "skeleton/skeleton_detail.hpp"
#include "slice/slicer.hpp"

using namespace carve;

namespace {

constexpr double kPi = std::numbers::pi;

Path jittered_circle(double r, int n, int jitter, uint64_t seed) {
    std::mt19937_64 rng(seed);
    Path p;
    for (int i = 0; i < n; ++i) {
        const double a = 2 * kPi * i / n;
        p.emplace_back(std::llround(r * std::cos(a)) + int(rng() % (2 * jitter + 1)) - jitter,
                       std::llround(r * std::sin(a)) + int(rng() % (2 * jitter + 1)) - jitter);
    }
    return p;
}

Path star(double r_in, double r_out, int spikes, double cx = 0, double cy = 0) {
    Path p;
    for (int i = 0; i < 2 * spikes; ++i) {
        const double a = kPi * i / spikes;
        const double r = (i % 2) ? r_in : r_out;
        p.emplace_back(std::llround(cx + r * std::cos(a)), std::llround(cy + r * std::sin(a)));
    }
    return p;
}

Paths multi_component() {
    Paths region;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            const Coord x = i * 25000, y = j * 25000;
            Path outer = jittered_circle(10000, 500, 2, uint64_t(i * 4 + j));
            for (Point& p : outer) p.X += x, p.Y += y;
            region.push_back(outer);
            if ((i + j) % 2) {
                Path hole = jittered_circle(4000, 200, 2, uint64_t(100 + i * 4 + j));
                for (Point& p : hole) p.X += x + 2000, p.Y += y;
                std::reverse(hole.begin(), hole.end());
                region.push_back(hole);
            }
        }
    return region;
}

// ---- bench-local STL plane cut ----
// Real slices come from the product's own loader and slicer.
carve::Mesh read_model(const std::string& path) {
    carve::MeshReport report;
    return carve::load_mesh(path, report);
}

Paths cut(const carve::Mesh& mesh, double z) {
    return carve::slice_at(mesh, z);
}

Paths mid_slice(const std::string& model) {
    const carve::Mesh tris = read_model(std::string(CARVE_MODELS_DIR) + "/" + model);
    const carve::BBox3 box = carve::bounding_box(tris);
    const double lo = box.min.z, hi = box.max.z;
    return cut(tris, 0.5 * (lo + hi) + 0.0123);
}

// The remainders V^0..V^5 of a slice carved without the cavity above.
std::vector<Paths> remainders(const Paths& slice) {
    std::vector<Paths> out{slice};
    SkeletonOptions opt;
    for (int j = 1; j < 6; ++j) {
        const Paths& v = out.back();
        out.push_back(subtract(v, dilate(skeleton(v, opt), 2000)));
    }
    return out;
}

size_t vertices(const Paths& region) {
    size_t n = 0;
    for (const Path& p : region) n += p.size();
    return n;
}

void run_axis(benchmark::State& state, const Paths& region) {
    SkeletonOptions opt;
    for (auto _ : state) benchmark::DoNotOptimize(medial_axis(region, opt));
    state.counters["vertices"] = double(vertices(region));
    state.counters["axis_edges"] = skel::last_stats().edges;
    state.counters["retries"] = skel::last_stats().retries;
}

void run_skeleton(benchmark::State& state, const Paths& region) {
    SkeletonOptions opt;
    for (auto _ : state) benchmark::DoNotOptimize(skeleton(region, opt));
    state.counters["vertices"] = double(vertices(region));
}

void BM_AxisCircle2000(benchmark::State& s) {
    run_axis(s, {jittered_circle(20000, 2000, 1, 1)});
}
void BM_SkeletonCircle2000(benchmark::State& s) {
    run_skeleton(s, {jittered_circle(20000, 2000, 1, 1)});
}
void BM_AxisStar(benchmark::State& s) {
    run_axis(s, {star(8000, 30000, 40)});
}
void BM_SkeletonStar(benchmark::State& s) {
    run_skeleton(s, {star(8000, 30000, 40)});
}
void BM_AxisMultiComponent(benchmark::State& s) {
    run_axis(s, multi_component());
}
void BM_SkeletonMultiComponent(benchmark::State& s) {
    run_skeleton(s, multi_component());
}

const std::vector<Paths>& elephant() {
    static const std::vector<Paths> v = remainders(mid_slice("elephant.stl"));
    return v;
}
const std::vector<Paths>& skull() {
    static const std::vector<Paths> v = remainders(mid_slice("skull.stl"));
    return v;
}

void BM_SkeletonElephantMid(benchmark::State& s) {
    run_skeleton(s, elephant()[size_t(s.range(0))]);
}
void BM_AxisElephantMid(benchmark::State& s) {
    run_axis(s, elephant()[size_t(s.range(0))]);
}
void BM_SkeletonSkullMid(benchmark::State& s) {
    run_skeleton(s, skull()[size_t(s.range(0))]);
}

}  // namespace

BENCHMARK(BM_AxisCircle2000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SkeletonCircle2000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_AxisStar)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SkeletonStar)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_AxisMultiComponent)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SkeletonMultiComponent)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_AxisElephantMid)->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SkeletonElephantMid)->DenseRange(0, 2)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SkeletonSkullMid)->DenseRange(0, 3)->Unit(benchmark::kMicrosecond);

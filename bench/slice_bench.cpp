// Benchmarks of the streaming slicer on real models, and of the 24-gon morphology on a real
// slice (the middle layer of the elephant).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdlib>
#include <map>
#include <new>
#include <string>

#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"
#include "slice/slicer.hpp"

using namespace carve;

// ---- heap accounting: every operator new/delete of the process (Clipper's included) goes
// through these, so the peak heap of the slicing alone can be measured, unlike peak RSS which
// the allocator's retained pages blur. Single-threaded use only. ----
namespace {
size_t g_heap_live = 0;
size_t g_heap_peak = 0;
constexpr size_t kHeader = 16;  // keeps the default new alignment

void* counted_alloc(size_t n) {
    void* raw = std::malloc(n + kHeader);
    if (!raw) throw std::bad_alloc();
    *static_cast<size_t*>(raw) = n;
    g_heap_live += n;
    g_heap_peak = std::max(g_heap_peak, g_heap_live);
    return static_cast<char*>(raw) + kHeader;
}
void counted_free(void* p) noexcept {
    if (!p) return;
    void* raw = static_cast<char*>(p) - kHeader;
    g_heap_live -= *static_cast<size_t*>(raw);
    std::free(raw);
}
}  // namespace

void* operator new(size_t n) {
    return counted_alloc(n);
}
void* operator new[](size_t n) {
    return counted_alloc(n);
}
void* operator new(size_t n, const std::nothrow_t&) noexcept {
    try {
        return counted_alloc(n);
    } catch (...) {
        return nullptr;
    }
}
void* operator new[](size_t n, const std::nothrow_t& t) noexcept {
    return operator new(n, t);
}
void operator delete(void* p) noexcept {
    counted_free(p);
}
void operator delete[](void* p) noexcept {
    counted_free(p);
}
void operator delete(void* p, size_t) noexcept {
    counted_free(p);
}
void operator delete[](void* p, size_t) noexcept {
    counted_free(p);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
    counted_free(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept {
    counted_free(p);
}

namespace {

Mesh read_model(const std::string& path) {
    MeshReport report;
    return load_mesh(path, report);
}

const Mesh& cached(const std::string& name) {
    static std::map<std::string, Mesh> meshes;
    auto it = meshes.find(name);
    if (it == meshes.end())
        it = meshes.emplace(name, read_model(std::string(CARVE_MODELS_DIR) + "/" + name)).first;
    return it->second;
}

const Mesh& stretched(const std::string& name, double factor) {
    static std::map<std::string, Mesh> meshes;
    auto it = meshes.find(name);
    if (it == meshes.end()) {
        Mesh m = read_model(std::string(CARVE_MODELS_DIR) + "/" + name);  // one mesh in memory
        for (Vec3& v : m.vertices) v.z *= factor;
        it = meshes.emplace(name, std::move(m)).first;
    }
    return it->second;
}

void slice_all(benchmark::State& state, const Mesh& mesh) {
    size_t points = 0;
    int layers = 0;
    size_t peak = 0, sweep_peak = 0;
    for (auto _ : state) {
        const size_t live_before = g_heap_live;
        g_heap_peak = g_heap_live;
        TopDownSlicer slicer(mesh, 0.2);
        const size_t setup_peak = g_heap_peak;
        g_heap_peak = g_heap_live;  // from here on: the sweep alone
        layers = slicer.layer_count();
        points = 0;
        while (auto s = slicer.next()) {
            for (const Path& p : s->region) points += p.size();
            benchmark::DoNotOptimize(s->region.data());
        }
        peak = std::max({peak, setup_peak - live_before, g_heap_peak - live_before});
        sweep_peak = std::max(sweep_peak, g_heap_peak - live_before);
    }
    state.counters["triangles"] = double(mesh.triangles.size());
    state.counters["layers"] = layers;
    state.counters["points"] = double(points);
    // Heap the slicer used at its peak on top of the loaded mesh (the set-up's sort buffers),
    // and during the sweep: sorted index, active set, per-plane buffers and one slice.
    state.counters["slicing_heap_peak_MiB"] = double(peak) / (1 << 20);
    state.counters["sweep_heap_peak_MiB"] = double(sweep_peak) / (1 << 20);
    state.counters["mesh_MiB"] =
        double(mesh.vertices.size() * sizeof(Vec3) + mesh.triangles.size() * 12) / (1 << 20);
}

void BM_SliceElephant(benchmark::State& state) {
    slice_all(state, cached("elephant.stl"));
}
void BM_SliceSkull100k(benchmark::State& state) {
    slice_all(state, cached("skull.stl"));
}
void BM_SliceSkull400k(benchmark::State& state) {
    slice_all(state, cached("skull_x4_400k.stl"));
}
// The same skull 10 times taller (6000 layers): memory must not grow with the layer count.
void BM_SliceSkull400kStretched10(benchmark::State& state) {
    slice_all(state, stretched("skull_x4_400k.stl", 10));
}

// The set-up alone: bounds, layer count and the triangles sorted by top z.
void BM_SortSkull400k(benchmark::State& state) {
    const Mesh& mesh = cached("skull_x4_400k.stl");
    for (auto _ : state) {
        TopDownSlicer slicer(mesh, 0.2);
        benchmark::DoNotOptimize(slicer.layer_count());
    }
}

const Paths& elephant_middle() {
    static const Paths region = [] {
        const Mesh& mesh = cached("elephant.stl");
        TopDownSlicer slicer(mesh, 0.2);
        const int middle = slicer.layer_count() / 2;
        while (auto s = slicer.next())
            if (s->index == middle) return s->region;
        return Paths{};
    }();
    return region;
}

void BM_DilateElephantMiddle(benchmark::State& state) {
    const Paths& region = elephant_middle();
    size_t points = 0;
    for (auto _ : state) {
        Paths d = dilate(region, to_units(0.2));
        points = 0;
        for (const Path& p : d) points += p.size();
        benchmark::DoNotOptimize(d.data());
    }
    state.counters["in_points"] = double([&] {
        size_t n = 0;
        for (const Path& p : region) n += p.size();
        return n;
    }());
    state.counters["out_points"] = double(points);
}

void BM_ErodeElephantMiddle(benchmark::State& state) {
    const Paths& region = elephant_middle();
    size_t points = 0;
    for (auto _ : state) {
        Paths e = erode(region, to_units(0.2));
        points = 0;
        for (const Path& p : e) points += p.size();
        benchmark::DoNotOptimize(e.data());
    }
    state.counters["out_points"] = double(points);
}

}  // namespace

BENCHMARK(BM_SliceElephant)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SliceSkull100k)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SliceSkull400k)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SliceSkull400kStretched10)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_SortSkull400k)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DilateElephantMiddle)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ErodeElephantMiddle)->Unit(benchmark::kMillisecond);

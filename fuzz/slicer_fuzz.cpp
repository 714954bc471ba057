// libFuzzer target: the repair and streaming slicer fed random triangle soups.
//
// The first byte picks how the rest becomes coordinates: on a coarse grid (one byte per
// coordinate, 0.5 mm steps: shared vertices, vertices on the cutting planes, duplicated and
// opposite triangles, non-manifold fans) or as raw float32 (anything the loaders accept, i.e.
// finite and within +-1 km). The mesh is welded like a loader's, repaired, then sliced top-down.
#include <cmath>
#include <cstring>

#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace carve;
    if (size < 2) return 0;
    const uint8_t mode = data[0];
    const bool grid = (mode & 1) == 0;
    ++data, --size;
    const size_t stride = grid ? 9 : 36;
    const size_t count = std::min<size_t>(size / stride, 4000);
    static const std::string kPath = "fuzz input";
    detail::Welder welder(3 * count, kPath);
    Mesh mesh;
    for (size_t t = 0; t < count; ++t) {
        const uint8_t* p = data + t * stride;
        std::array<uint32_t, 3> tri{};
        bool ok = true;
        for (int c = 0; c < 3 && ok; ++c) {
            double v[3];
            for (int k = 0; k < 3; ++k) {
                if (grid) {
                    v[k] = 0.5 * p[3 * c + k];
                } else {
                    float f;
                    std::memcpy(&f, p + 4 * (3 * c + k), 4);
                    v[k] = f;
                }
                if (!(std::abs(v[k]) <= detail::kMaxCoordinateMm)) ok = false;
            }
            if (ok) tri[c] = welder.add(v[0], v[1], v[2]);
        }
        if (ok) mesh.triangles.push_back(tri);
    }
    mesh.vertices = welder.take();
    MeshReport report;
    analyse_and_repair(mesh, report);
    if (mesh.triangles.empty()) return 0;
    const BBox3 box = bounding_box(mesh);
    // At most about 40 layers whatever the model's height, never thinner than 0.05 mm.
    const double h = std::max(0.05, (box.max.z - box.min.z) / 40.0);
    TopDownSlicer slicer(mesh, (mode & 2) ? h : std::max(h, 0.5));
    while (auto slice = slicer.next()) {
        for (const Path& path : slice->region)
            if (path.size() < 3) __builtin_trap();  // the slicer promises closed polygons
    }
    return 0;
}

// Shared by the libFuzzer targets: what happens to a mesh after a reader has produced it.
//
// A reader may refuse its input only with carve::InputError (the one user-facing error); any
// other exception escaping a target is a bug, and libFuzzer reports it as a crash.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "base/error.hpp"
#include "mesh/loader.hpp"
#include "mesh/mesh.hpp"
#include "slice/slicer.hpp"

namespace carve::fuzz {

// Triangles beyond this are repaired but not sliced, so that one input stays fast.
constexpr size_t kMaxSlicedTriangles = 20000;

// Repair as load_mesh does, then cut a few planes through the result, including the heights of
// a few vertices (planes through vertices are the slicer's hardest case).
inline void repair_and_slice(Mesh& mesh) {
    MeshReport report;
    analyse_and_repair(mesh, report);
    if (mesh.triangles.empty() || mesh.triangles.size() > kMaxSlicedTriangles) return;
    const BBox3 box = bounding_box(mesh);
    const double height = box.max.z - box.min.z;
    for (int i = 0; i <= 4; ++i) slice_at(mesh, box.min.z + height * i / 4.0);
    for (size_t i = 0; i < std::min<size_t>(mesh.vertices.size(), 3); ++i)
        slice_at(mesh, mesh.vertices[i].z);
}

// Runs one reader over data, then repair_and_slice on what it read.
template <class Reader>
int run_reader(const uint8_t* data, size_t size, Reader&& read) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    Mesh mesh;
    MeshReport report;
    try {
        read(bytes, "fuzz", mesh, report);
    } catch (const InputError&) {
        return 0;  // a clear refusal is a correct answer
    }
    repair_and_slice(mesh);
    return 0;
}

}  // namespace carve::fuzz

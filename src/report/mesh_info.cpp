// Mesh description for `carve info`: the same facts as text for a person and as JSON for tools.
#include "report/mesh_info.hpp"

#include <fmt/format.h>

namespace carve {

namespace {

Vec3 size_of(const BBox3& b) {
    return {b.max.x - b.min.x, b.max.y - b.min.y, b.max.z - b.min.z};
}

std::string count_of(size_t n, const char* word) {
    return fmt::format("{} {}{}", n, word, n == 1 ? "" : "s");
}

}  // namespace

std::string describe(const MeshReport& r) {
    const Vec3 size = size_of(r.bbox);
    std::string out;
    out += fmt::format("format:       {}\n", r.format);
    out += fmt::format("triangles:    {}", r.triangles);
    if (r.triangles != r.triangles_read) out += fmt::format(" ({} in the file)", r.triangles_read);
    out += fmt::format("\nvertices:     {}\n", r.vertices);
    out += fmt::format("bounding box: ({:.2f}, {:.2f}, {:.2f}) to ({:.2f}, {:.2f}, {:.2f}) mm\n",
                       r.bbox.min.x, r.bbox.min.y, r.bbox.min.z, r.bbox.max.x, r.bbox.max.y,
                       r.bbox.max.z);
    out += fmt::format("size:         {:.2f} x {:.2f} x {:.2f} mm\n", size.x, size.y, size.z);
    out += fmt::format("volume:       {:.3f} cm^3\n", r.volume_mm3 / 1000.0);
    if (r.closed())
        out += "closed:       yes\n";
    else
        out += fmt::format("closed:       no ({}, {})\n", count_of(r.open_edges, "open edge"),
                           count_of(r.nonmanifold_edges, "non-manifold edge"));
    out += fmt::format("shells:       {}", r.shells);
    if (r.internal_voids > 0)
        out += fmt::format(" ({} inside the others)", count_of(r.internal_voids, "internal void"));
    out += "\n";
    if (r.warnings.empty()) {
        out += "repairs:      none needed\n";
    } else {
        out += "repairs:\n";
        for (const std::string& w : r.warnings) out += "  - " + w + "\n";
    }
    return out;
}

nlohmann::json to_json(const MeshReport& r) {
    const Vec3 size = size_of(r.bbox);
    return {
        {"format", r.format},
        {"triangles", r.triangles},
        {"triangles_read", r.triangles_read},
        {"vertices", r.vertices},
        {"bbox_min", {r.bbox.min.x, r.bbox.min.y, r.bbox.min.z}},
        {"bbox_max", {r.bbox.max.x, r.bbox.max.y, r.bbox.max.z}},
        {"size_mm", {size.x, size.y, size.z}},
        {"model_volume_mm3", r.volume_mm3},
        {"closed", r.closed()},
        {"open_edges", r.open_edges},
        {"nonmanifold_edges", r.nonmanifold_edges},
        {"shells", r.shells},
        {"internal_voids", r.internal_voids},
        {"degenerate_dropped", r.degenerate_dropped},
        {"duplicate_dropped", r.duplicate_dropped},
        {"flipped_triangles", r.flipped_triangles},
        {"inverted", r.inverted},
        {"inverted_shells", r.inverted_shells},
        {"warnings", r.warnings},
    };
}

}  // namespace carve

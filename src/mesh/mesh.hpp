// An indexed triangle mesh, the loaders' output and the slicer's input.
//
// Vertices are merged on exact equality of their coordinates so that the slicer can chain
// segments through shared edges by index, never by float proximity.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "geometry/types.hpp"

namespace carve {

struct Mesh {
    std::vector<Vec3> vertices;                      // millimetres
    std::vector<std::array<uint32_t, 3>> triangles;  // counter-clockwise seen from outside
};

// What loading found and fixed, in words a user understands.
struct MeshReport {
    std::string format;         // "binary STL", "ASCII STL", "OBJ", "3MF"
    size_t triangles_read = 0;  // as stored in the file
    size_t triangles = 0;       // after dropping degenerate ones
    size_t vertices = 0;        // after merging duplicates
    size_t degenerate_dropped = 0;
    size_t duplicate_dropped = 0;
    size_t open_edges = 0;         // edges with one incident triangle
    size_t nonmanifold_edges = 0;  // edges with more than two incident triangles
    size_t flipped_triangles = 0;  // triangles re-oriented to agree with their neighbours
    bool inverted = false;         // the whole mesh faced inwards and was turned out
    size_t inverted_shells = 0;    // shells turned outside out (inverted: at least one)
    size_t shells = 0;             // connected components
    size_t internal_voids = 0;     // closed shells nested inside another, kept facing inwards
    size_t zero_area_splits = 0;   // neighbours split at a dropped sliver's middle vertex
    bool closed() const { return open_edges == 0 && nonmanifold_edges == 0; }
    double volume_mm3 = 0;  // after repair, from the divergence theorem
    BBox3 bbox;
    std::vector<std::string> warnings;  // one line each: what was wrong and what was done
    // A 3MF's build items, each an object on the plate: name and extent in the plane, mm.
    struct BuildItem {
        std::string name;
        double min_x = std::numeric_limits<double>::max(), min_y = min_x;
        double max_x = std::numeric_limits<double>::lowest(), max_y = max_x;
    };
    std::vector<BuildItem> items;
};

// What load_mesh refuses besides unreadable files.
struct LoadOptions {
    // A triangle soup (is_triangle_soup), refused as soon as the edges are counted: `carve
    // slice` cannot slice one, and the rest of the repair would cost memory for nothing.
    bool refuse_soup = false;
    // OBJ and ASCII STL files from this size get a first pass that counts their triangles and
    // corners (a soup is refused there, before it is welded); tests lower it.
    size_t text_first_pass_bytes = 64u << 20;
};

// Reads STL (binary or ASCII, told apart by content), OBJ or 3MF, merges vertices, drops
// degenerate triangles, fixes orientation and measures the result. Throws InputError with one
// clear line for anything that cannot be read (empty, truncated, NaN/inf, no triangles, unknown
// format, unreadable file) or that options refuse.
Mesh load_mesh(const std::string& path, MeshReport& report, const LoadOptions& options = {});

// Fewer triangles than this are never called a soup: small test pieces and fragments.
constexpr size_t kSoupMinTriangles = 1000;
// Most edges belong to one triangle only: no solid. Its slices are thousands of crossing
// segments whose union costs the square of their number (5,000 random triangles ran for
// minutes); an open mesh with a hole has a few open edges.
bool is_triangle_soup(const MeshReport& report);
// "<path>: not a solid: ..." with the counts.
std::string triangle_soup_message(const std::string& path, const MeshReport& report);

// Orientation, closedness and volume of an already indexed mesh (used by load_mesh and tests).
// edges_counted, when given, is called once the report's triangle and edge counts are final
// and before the shells are walked; it may throw to stop the repair there.
void analyse_and_repair(Mesh& mesh, MeshReport& report,
                        const std::function<void(const MeshReport&)>& edges_counted = {});

double signed_volume(const Mesh& mesh);
BBox3 bounding_box(const Mesh& mesh);

// The mesh as a binary STL file's bytes (float32, little-endian, facet normals from the vertex
// order), `name` in the 80-byte header: how a cut's plates are handed to carve check --mesh
// or to another slicer.
std::string binary_stl(const Mesh& mesh, const std::string& name);

// Triangles a model may have once every copy is placed (3MF components and items, --copies):
// some 2 GB of mesh and slicing work, ten times the largest scans the shared models hold.
constexpr size_t kMaxPlacedTriangles = 20'000'000;

// `copies` of the mesh side by side, `gap` mm apart, in a grid as square as their count allows
// (rows of ceil(sqrt(n))), centred where the one mesh was. `boxes` gets each copy's extent in
// the plane, in the order their labels number them. More than kMaxPlacedTriangles in all is
// refused (InputError) before anything is allocated.
struct CopyBox {
    double min_x = 0, min_y = 0, max_x = 0, max_y = 0;
};
Mesh arrange_copies(const Mesh& mesh, int copies, double gap, std::vector<CopyBox>& boxes);

}  // namespace carve

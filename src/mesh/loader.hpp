// Private to the mesh loaders: the vertex welder every reader feeds, and the readers themselves.
//
// Readers turn file bytes into welded vertices plus triangles; the welder merges points whose
// coordinates are exactly equal, so that the slicer can follow shared edges by index.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mesh/mesh.hpp"

namespace carve::detail {

// Coordinates larger than this (mm) are taken as a units mistake rather than a real part.
constexpr double kMaxCoordinateMm = 1e6;

// Throws InputError "<path>: <what>".
[[noreturn]] void fail(const std::string& path, const std::string& what);

// Checks one point; `where` is only called to describe it when something is wrong.
template <class Where>
inline void check_point(const std::string& path, double x, double y, double z, Where&& where) {
    if (std::abs(x) <= kMaxCoordinateMm && std::abs(y) <= kMaxCoordinateMm &&
        std::abs(z) <= kMaxCoordinateMm)
        return;
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
        fail(path, where() + " has a NaN or infinite coordinate; the file is corrupt");
    fail(path, where() + " lies beyond +-1 km (coordinates over 1e6 mm); wrong units?");
}

// Merges points on exact coordinate equality (open addressing over the coordinates' bits;
// -0 and +0 are the same point). A slot is 4 bytes, a vertex index and 6 bits of the hash as
// a tag; the coordinates are compared in the vertex array.
class Welder {
  public:
    // path names the file when it has more points than an index can number.
    explicit Welder(size_t expected_points, const std::string& path);
    uint32_t add(double x, double y, double z);
    // Room for this many points without moving them: a first pass over a large text file
    // knows the most there can be, and a doubling array would hold two copies at once.
    void reserve(size_t points) { vertices_.reserve(points); }
    size_t size() const { return vertices_.size(); }
    std::vector<Vec3> take() { return std::move(vertices_); }

  private:
    void grow();
    std::vector<Vec3> vertices_;
    std::vector<uint32_t> table_;  // hash tag | vertex index, or all ones when empty
    uint64_t mask_ = 0;
    const std::string& path_;
};

// Each reader fills mesh (welded, not yet repaired) and report.format / triangles_read.
void read_binary_stl(std::string_view data, const std::string& path, Mesh& mesh,
                     MeshReport& report);
// The same from an open file at its start, read in blocks (the caller checked its size).
void read_binary_stl(std::FILE* file, const std::string& path, Mesh& mesh, MeshReport& report);
// Binary STLs of this many facets or more are checked for a soup before they are welded
// (binary_stl_soup_corners); smaller ones are refused within 500 MB by the welded count.
constexpr uint32_t kSoupPrepassFacets = 2'000'000;
// For an open binary STL file at its start: its triangles and the distinct points found once
// they prove it a triangle soup (more than 2.25 per triangle), else nothing. Leaves the file
// anywhere; the caller rewinds it.
struct SoupProof {
    uint32_t triangles = 0;
    uint64_t corners = 0;
};
std::optional<SoupProof> binary_stl_soup_corners(std::FILE* file, const std::string& path,
                                                 uint32_t min_facets = kSoupPrepassFacets);

// "not a solid: its T triangles have V distinct corners or more, ..." (without the path).
std::string soup_corners_message(uint64_t triangles, uint64_t corners);

// What the first pass over a large text file (LoadOptions::text_first_pass_bytes) found: its
// triangles and the distinct points they use, counted before anything is welded. A soup is
// refused from those counts, at 8 bytes a corner instead of the welder's 30, and welding then
// reserves what it needs once instead of doubling its arrays.
struct TextCounts {
    uint64_t triangles = 0;
    uint64_t vertex_lines = 0;  // OBJ: "v" lines, used or not
    // Distinct hashes of the points triangles use: never more than the distinct points, since
    // equal points hash alike, so a count past 2.25 a triangle proves a soup as surely.
    uint64_t corners = 0;
};

// The welder's hash of a point (after -0 is made +0), which the first pass counts.
uint64_t hash_point(double x, double y, double z);

// The number of distinct values in hashes, which it sorts.
uint64_t count_distinct(std::vector<uint64_t>& hashes);

void read_ascii_stl(std::string_view data, const std::string& path, Mesh& mesh, MeshReport& report);
// The first pass over an ASCII STL file of the given size, at its start.
TextCounts count_ascii_stl(std::FILE* file, size_t size, const std::string& path);
// From an open file of the given size at its start, read in blocks. counts, when given
// (count_ascii_stl on the same file), size the arrays.
void read_ascii_stl(std::FILE* file, size_t size, const std::string& path, Mesh& mesh,
                    MeshReport& report, const TextCounts* counts);
void read_obj(std::string_view data, const std::string& path, Mesh& mesh, MeshReport& report);
// The first pass over an OBJ file of the given size, at its start.
TextCounts count_obj(std::FILE* file, size_t size, const std::string& path);
// The same from an open file of the given size, at its start, read in blocks; counts as for
// read_ascii_stl.
void read_obj(std::FILE* file, size_t size, const std::string& path, Mesh& mesh, MeshReport& report,
              const TextCounts* counts);
// Frees data once the model part is unpacked.
void read_3mf(std::string& data, const std::string& path, Mesh& mesh, MeshReport& report);

// Parses a decimal number (leading '+' allowed); false when the token is not one.
bool parse_double(std::string_view token, double& value);

// 1-based line number of position pos in data (for error messages).
size_t line_of(std::string_view data, size_t pos);

}  // namespace carve::detail

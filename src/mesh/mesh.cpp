// load_mesh: reads the file in one go, tells the format from its content, and hands the welded
// mesh to analyse_and_repair. Also the welder and the small measures (volume, bounding box).
#include "mesh/mesh.hpp"

#include <algorithm>
#include <bit>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>

#include "base/error.hpp"
#include "mesh/loader.hpp"

namespace carve {

namespace detail {

void fail(const std::string& path, const std::string& what) {
    throw InputError(path + ": " + what);
}

bool parse_double(std::string_view token, double& value) {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    if (token.empty()) return false;
    auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    return ec == std::errc() && end == token.data() + token.size();
}

size_t line_of(std::string_view data, size_t pos) {
    pos = std::min(pos, data.size());
    return 1 + static_cast<size_t>(std::count(data.begin(), data.begin() + pos, '\n'));
}

namespace {

inline uint64_t bits_of(double v) {
    return std::bit_cast<uint64_t>(v);
}

size_t table_size_for(size_t points) {
    return std::bit_ceil(std::max<size_t>(16, 2 * points));
}

}  // namespace

// A slot holds the vertex index in its low 26 bits and the hash's top 6 bits as a tag, so that
// a probe past a different point rarely has to read that point's coordinates. The all-ones
// slot (tag 63, index kIdMask) marks an empty one, so kIdMask itself is never a vertex.
constexpr uint32_t kIdMask = (1u << 26) - 1;
constexpr uint32_t kEmptySlot = 0xFFFFFFFFu;

inline uint32_t tag_of(uint64_t h) {
    return static_cast<uint32_t>(h >> 58) << 26;
}

// Coordinates read from float32 have their low 29 mantissa bits zero, so the bits are first
// spread by odd multipliers and then folded down by a murmur-style finaliser.
uint64_t hash_point(double x, double y, double z) {
    uint64_t h = bits_of(x) * 0x9E3779B97F4A7C15ULL;
    h ^= bits_of(y) * 0xC2B2AE3D27D4EB4FULL;
    h ^= std::rotl(bits_of(z) * 0x165667B19E3779F9ULL, 31);
    h ^= h >> 33;
    h *= 0xFF51AFD7ED558CCDULL;
    h ^= h >> 33;
    h *= 0xC4CEB9FE1A85EC53ULL;
    h ^= h >> 33;
    return h;
}

Welder::Welder(size_t expected_points, const std::string& path) : path_(path) {
    vertices_.reserve(expected_points);
    table_.assign(table_size_for(expected_points), kEmptySlot);
    mask_ = table_.size() - 1;
}

void Welder::grow() {
    // The points are hashed again from the vertex array, so the old table goes first.
    const size_t size = table_.size() * 2;
    table_ = std::vector<uint32_t>();  // frees it (= {} would keep its capacity)
    table_.assign(size, kEmptySlot);
    mask_ = size - 1;
    for (uint32_t id = 0; id < vertices_.size(); ++id) {
        const Vec3& v = vertices_[id];
        const uint64_t h = hash_point(v.x, v.y, v.z);
        uint64_t i = h & mask_;
        while (table_[i] != kEmptySlot) i = (i + 1) & mask_;
        table_[i] = tag_of(h) | id;
    }
}

uint32_t Welder::add(double x, double y, double z) {
    if (2 * (vertices_.size() + 1) > table_.size()) grow();
    // Adding +0.0 turns -0.0 into +0.0, so both hash and compare alike.
    x += 0.0;
    y += 0.0;
    z += 0.0;
    const uint64_t h = hash_point(x, y, z);
    const uint32_t tag = tag_of(h);
    uint64_t i = h & mask_;
    for (;;) {
        const uint32_t slot = table_[i];
        if (slot == kEmptySlot) {
            const uint32_t id = static_cast<uint32_t>(vertices_.size());
            if (id == kIdMask)
                fail(path_, "more than 67 million distinct vertices; carve reads fewer");
            table_[i] = tag | id;
            vertices_.push_back({x, y, z});
            return id;
        }
        if ((slot & ~kIdMask) == tag) {
            const Vec3& v = vertices_[slot & kIdMask];
            if (v.x == x && v.y == y && v.z == z) return slot & kIdMask;
        }
        i = (i + 1) & mask_;
    }
}

}  // namespace detail

namespace {

using detail::fail;

// Models carve reads at most: about 10 million binary STL triangles, whose welded mesh and
// slices already take over a gigabyte. A larger file is refused before it is read, so that a
// refusal costs no memory; a pipe is cut off at the same size.
constexpr long kMaxModelBytes = 512L << 20;

struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

// Opens the model; size is its length, or -1 when it cannot be told (a pipe).
File open_model(const std::string& path, long& size) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) fail(path, "is a directory, not a mesh file");
    File f(std::fopen(path.c_str(), "rb"));
    if (!f) fail(path, std::string("cannot open the file: ") + std::strerror(errno));
    size = -1;
    if (std::fseek(f.get(), 0, SEEK_END) == 0) {
        size = std::ftell(f.get());
        if (size > kMaxModelBytes)
            fail(path,
                 "larger than 512 MB; carve reads models up to 512 MB (about 10 million "
                 "triangles of binary STL): decimate the mesh first");
        std::rewind(f.get());
    }
    return f;
}

uint64_t binary_stl_size(std::string_view head) {
    uint32_t count = 0;
    std::memcpy(&count, head.data() + 80, 4);
    if constexpr (std::endian::native == std::endian::big) count = __builtin_bswap32(count);
    return 84 + 50 * uint64_t(count);
}

bool is_zip(std::string_view d) {
    return d.size() >= 4 && d.substr(0, 4) == std::string_view("PK\x03\x04", 4);
}

// A file of known size that is exactly what its binary STL header announces (and not a zip,
// which load_mesh tries first) is read facet by facet without ever being held whole.
bool streams_as_binary_stl(std::FILE* f, long size) {
    if (size < 84) return false;
    char head[84];
    const bool got = std::fread(head, 1, sizeof head, f) == sizeof head;
    std::rewind(f);
    const std::string_view h(head, sizeof head);
    return got && !is_zip(h) && binary_stl_size(h) == static_cast<uint64_t>(size);
}

// A file of known size named .obj whose first bytes rule out every format tried before OBJ (a
// zip, a binary STL of exactly its size, ASCII STL's leading "solid") is read line by line
// without ever being held whole.
bool streams_as_obj(std::FILE* f, long size, const std::string& ext);
bool streams_as_ascii_stl(std::FILE* f, long size);

std::string read_whole_file(std::FILE* f, const std::string& path, long size) {
    std::string data;
    if (size > 0) {
        data.resize(static_cast<size_t>(size));
        size_t got = std::fread(data.data(), 1, data.size(), f);
        data.resize(got);
    }
    // Not seekable (a pipe) or changed under us: fall back to reading in chunks.
    if (data.empty()) {
        std::clearerr(f);
        std::rewind(f);
        char buf[1 << 16];
        size_t got;
        while ((got = std::fread(buf, 1, sizeof buf, f)) > 0) {
            // Refused before the string grows past the limit: appending first doubled its
            // capacity to 1 GB, so /dev/zero was refused only after taking 1,040 MB.
            if (data.size() + got > static_cast<size_t>(kMaxModelBytes))
                fail(path, "larger than 512 MB; carve reads models up to 512 MB");
            data.append(buf, got);
        }
    }
    if (std::ferror(f)) fail(path, std::string("cannot read the file: ") + std::strerror(errno));
    return data;
}

std::string lower_extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

bool is_space(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v';
}

bool starts_with_word(std::string_view s, std::string_view word) {
    if (s.size() < word.size()) return false;
    for (size_t i = 0; i < word.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(s[i])) != word[i]) return false;
    return s.size() == word.size() || is_space(s[word.size()]);
}

std::string_view skip_space(std::string_view s) {
    size_t i = 0;
    while (i < s.size() && is_space(s[i])) ++i;
    return s.substr(i);
}

// No control bytes in the first 4 kB: text, not a binary STL's float data.
bool textual(std::string_view d) {
    for (char c : d.substr(0, 4096))
        if (static_cast<unsigned char>(c) < 0x09) return false;
    return true;
}

// Text editors on Windows put a UTF-8 byte order mark before the first word.
std::string_view without_bom(std::string_view d) {
    return d.substr(0, 3) == std::string_view("\xEF\xBB\xBF", 3) ? d.substr(3) : d;
}

// "solid <name>" on the first line, then "facet" or "endsolid": binary files whose header
// happens to begin with "solid" fail the second test.
bool looks_like_ascii_stl(std::string_view data) {
    std::string_view s = skip_space(data);
    if (!starts_with_word(s, "solid")) return false;
    // Any line end: old Mac files end their lines with CR alone.
    size_t eol = s.find_first_of("\r\n");
    if (eol == std::string_view::npos) return false;
    s = skip_space(s.substr(eol + 1));
    return starts_with_word(s, "facet") || starts_with_word(s, "endsolid");
}

// The first meaningful lines are all OBJ statements and at least one is a vertex.
bool looks_like_obj(std::string_view data) {
    static constexpr std::string_view kKeywords[] = {"v", "vt", "vn", "vp", "f",      "o",
                                                     "g", "s",  "l",  "p",  "usemtl", "mtllib"};
    size_t pos = 0, lines = 0;
    bool vertex = false;
    while (pos < data.size() && lines < 64) {
        size_t eol = data.find('\n', pos);
        if (eol == std::string_view::npos) eol = data.size();
        std::string_view line = skip_space(data.substr(pos, eol - pos));
        pos = eol + 1;
        if (line.empty() || line.front() == '#') continue;
        ++lines;
        bool known = false;
        for (std::string_view k : kKeywords) {
            if (starts_with_word(line, k)) {
                known = true;
                if (k == "v") vertex = true;
                break;
            }
        }
        if (!known) return false;
    }
    return vertex;
}

bool streams_as_obj(std::FILE* f, long size, const std::string& ext) {
    if (ext != ".obj" || size < 84) return false;
    char head[4096];
    const size_t got = std::fread(head, 1, sizeof head, f);
    std::rewind(f);
    const std::string_view h(head, got);
    if (got < 84 || is_zip(h) || binary_stl_size(h) == static_cast<uint64_t>(size)) return false;
    // "solid" followed by a space or the end decides for ASCII STL: only a first word wholly
    // inside the head is known not to be one.
    const std::string_view s = skip_space(without_bom(h));
    return s.size() > 5 && !starts_with_word(s, "solid");
}

// A file of known size whose first bytes are an ASCII STL's ("solid", a name, then "facet" or
// "endsolid") and not a binary STL of exactly its size is read word by word without ever being
// held whole; a name longer than the first 4 kB leaves it to the reader of whole files.
bool streams_as_ascii_stl(std::FILE* f, long size) {
    if (size < 84) return false;
    char head[4096];
    const size_t got = std::fread(head, 1, sizeof head, f);
    std::rewind(f);
    const std::string_view h(head, got);
    if (got < 84 || is_zip(h) || binary_stl_size(h) == static_cast<uint64_t>(size)) return false;
    return looks_like_ascii_stl(without_bom(h));
}

// Tells the format from the content of a file held whole and reads it. The 3MF reader frees the
// archive's bytes once it has unpacked the model.
void read_from_memory(std::string& data, const std::string& path, Mesh& mesh, MeshReport& report) {
    const std::string_view d(data);
    if (d.empty()) fail(path, "the file is empty");
    const std::string ext = lower_extension(path);
    const uint64_t binary_size = d.size() >= 84 ? binary_stl_size(d) : 0;
    if (is_zip(d)) {
        detail::read_3mf(data, path, mesh, report);
    } else if (d.size() >= 84 && d.size() == binary_size) {
        detail::read_binary_stl(d, path, mesh, report);
    } else if (looks_like_ascii_stl(without_bom(d))) {
        detail::read_ascii_stl(without_bom(d), path, mesh, report);
    } else if (ext == ".obj" || looks_like_obj(without_bom(d))) {
        detail::read_obj(without_bom(d), path, mesh, report);
    } else if (starts_with_word(skip_space(without_bom(d)), "solid") && textual(d)) {
        fail(path,
             "not a valid STL: it begins like ASCII STL ('solid') but no 'facet' or "
             "'endsolid' follows its first line, and its size does not fit a binary STL");
    } else if (ext == ".stl") {
        if (d.size() < 84)
            fail(path, "not a valid STL: " + std::to_string(d.size()) +
                           " bytes is too short for a binary STL and it is not ASCII STL");
        fail(path, std::string(d.size() < binary_size ? "truncated" : "corrupt") +
                       " binary STL: its header announces " +
                       std::to_string((binary_size - 84) / 50) + " triangles (" +
                       std::to_string(binary_size) + " bytes) but the file has " +
                       std::to_string(d.size()) + " bytes");
    } else if (ext == ".3mf") {
        fail(path, "not a valid 3MF file: it is not a zip archive");
    } else {
        fail(path, "unknown mesh format (expected binary or ASCII STL, OBJ or 3MF)");
    }
}

}  // namespace

bool is_triangle_soup(const MeshReport& m) {
    return m.triangles_read > kSoupMinTriangles && m.open_edges * 2 > 3 * m.triangles_read;
}

std::string triangle_soup_message(const std::string& path, const MeshReport& m) {
    return path + ": not a solid: " + std::to_string(m.open_edges) + " of the " +
           std::to_string(3 * m.triangles_read) +
           " triangles' edges are shared with no other triangle (a triangle soup); repair the "
           "mesh first";
}

namespace detail {

std::string soup_corners_message(uint64_t triangles, uint64_t corners) {
    return "not a solid: its " + std::to_string(triangles) + " triangles have " +
           std::to_string(corners) +
           " distinct corners or more, over 2.25 a triangle, so more than half of their edges "
           "are shared with no other triangle (a triangle soup); repair the mesh first";
}

uint64_t count_distinct(std::vector<uint64_t>& hashes) {
    std::sort(hashes.begin(), hashes.end());
    return static_cast<uint64_t>(std::unique(hashes.begin(), hashes.end()) - hashes.begin());
}

}  // namespace detail

namespace {

// A large text file's first pass: refused here when its counts prove a soup.
detail::TextCounts first_pass(detail::TextCounts counts, const std::string& path,
                              const LoadOptions& options) {
    if (options.refuse_soup && counts.triangles > kSoupMinTriangles &&
        double(counts.corners) > 2.25 * double(counts.triangles))
        fail(path, detail::soup_corners_message(counts.triangles, counts.corners));
    return counts;
}

}  // namespace

Mesh load_mesh(const std::string& path, MeshReport& report, const LoadOptions& options) {
    report = MeshReport{};
    Mesh mesh;
    {
        long size = -1;
        File file = open_model(path, size);
        if (streams_as_binary_stl(file.get(), size)) {
            if (options.refuse_soup) {
                if (const auto soup = detail::binary_stl_soup_corners(file.get(), path))
                    fail(path, detail::soup_corners_message(soup->triangles, soup->corners));
                std::rewind(file.get());
            }
            detail::read_binary_stl(file.get(), path, mesh, report);
        } else if (streams_as_obj(file.get(), size, lower_extension(path))) {
            const auto bytes = static_cast<size_t>(size);
            std::optional<detail::TextCounts> counts;
            if (bytes >= options.text_first_pass_bytes) {
                counts = first_pass(detail::count_obj(file.get(), bytes, path), path, options);
                std::rewind(file.get());
            }
            detail::read_obj(file.get(), bytes, path, mesh, report, counts ? &*counts : nullptr);
        } else if (streams_as_ascii_stl(file.get(), size)) {
            const auto bytes = static_cast<size_t>(size);
            std::optional<detail::TextCounts> counts;
            if (bytes >= options.text_first_pass_bytes) {
                counts =
                    first_pass(detail::count_ascii_stl(file.get(), bytes, path), path, options);
                std::rewind(file.get());
            }
            detail::read_ascii_stl(file.get(), bytes, path, mesh, report,
                                   counts ? &*counts : nullptr);
        } else {
            std::string data = read_whole_file(file.get(), path, size);
            file.reset();
            read_from_memory(data, path, mesh, report);
        }
    }  // the file's bytes are freed here, before the repair needs memory of its own

    // The corners prove a soup before the edges are counted (see binary_stl_soup_corners),
    // without the half-edge array of 36 bytes a triangle: what a soup of any format peaks at.
    if (options.refuse_soup && mesh.triangles.size() > kSoupMinTriangles) {
        std::vector<bool> used(mesh.vertices.size());
        uint64_t corners = 0;
        for (const auto& t : mesh.triangles)
            for (uint32_t v : t)
                if (!used[v]) used[v] = true, ++corners;
        if (double(corners) > 2.25 * double(mesh.triangles.size()))
            fail(path, detail::soup_corners_message(mesh.triangles.size(), corners));
    }
    const size_t read = report.triangles_read;
    // A soup is refused as soon as its edges are counted: the walk over shells that follows
    // costs some 120 bytes per shell, and every triangle of a soup is a shell of its own.
    analyse_and_repair(mesh, report, [&](const MeshReport& counted) {
        if (options.refuse_soup && is_triangle_soup(counted))
            throw InputError(triangle_soup_message(path, counted));
    });
    if (report.triangles == 0) {
        if (read == 0) fail(path, "the file holds no triangles");
        if (report.duplicate_dropped == 0)
            fail(path, "no triangles left: all " + std::to_string(read) +
                           " triangles are degenerate (zero area)");
        fail(path, "no triangles left: of " + std::to_string(read) + " triangles, " +
                       std::to_string(report.degenerate_dropped) +
                       " are degenerate (zero area) and " +
                       std::to_string(report.duplicate_dropped) +
                       " duplicates that cancel out (the same facet facing both ways)");
    }
    return mesh;
}

double signed_volume(const Mesh& mesh) {
    // Measured about the box centre so that far-off coordinates do not eat the precision.
    BBox3 box = bounding_box(mesh);
    const Vec3 o{(box.min.x + box.max.x) / 2, (box.min.y + box.max.y) / 2,
                 (box.min.z + box.max.z) / 2};
    double six = 0;
    for (const auto& t : mesh.triangles) {
        const Vec3& pa = mesh.vertices[t[0]];
        const Vec3& pb = mesh.vertices[t[1]];
        const Vec3& pc = mesh.vertices[t[2]];
        double ax = pa.x - o.x, ay = pa.y - o.y, az = pa.z - o.z;
        double bx = pb.x - o.x, by = pb.y - o.y, bz = pb.z - o.z;
        double cx = pc.x - o.x, cy = pc.y - o.y, cz = pc.z - o.z;
        six += ax * (by * cz - bz * cy) + ay * (bz * cx - bx * cz) + az * (bx * cy - by * cx);
    }
    return six / 6.0;
}

BBox3 bounding_box(const Mesh& mesh) {
    BBox3 box;
    if (mesh.vertices.empty()) return box;
    box.min = box.max = mesh.vertices.front();
    for (const Vec3& v : mesh.vertices) {
        box.min.x = std::min(box.min.x, v.x);
        box.min.y = std::min(box.min.y, v.y);
        box.min.z = std::min(box.min.z, v.z);
        box.max.x = std::max(box.max.x, v.x);
        box.max.y = std::max(box.max.y, v.y);
        box.max.z = std::max(box.max.z, v.z);
    }
    return box;
}

Mesh arrange_copies(const Mesh& mesh, int copies, double gap, std::vector<CopyBox>& boxes) {
    boxes.clear();
    const BBox3 b = bounding_box(mesh);
    const int n = std::max(1, copies);
    if (mesh.triangles.size() * size_t(n) > kMaxPlacedTriangles)
        throw InputError("--copies " + std::to_string(n) + " of a model of " +
                         std::to_string(mesh.triangles.size()) + " triangles make " +
                         std::to_string(mesh.triangles.size() * size_t(n)) +
                         " triangles, over the limit of " + std::to_string(kMaxPlacedTriangles) +
                         "; print fewer copies");
    const int columns = static_cast<int>(std::ceil(std::sqrt(double(n))));
    const int rows = (n + columns - 1) / columns;
    const double pitch_x = b.max.x - b.min.x + gap, pitch_y = b.max.y - b.min.y + gap;
    // Copy k in column k % columns, row k / columns, the grid's centre on the mesh's.
    const double x0 = -0.5 * (columns - 1) * pitch_x, y0 = 0.5 * (rows - 1) * pitch_y;
    Mesh out;
    out.vertices.reserve(mesh.vertices.size() * size_t(n));
    out.triangles.reserve(mesh.triangles.size() * size_t(n));
    for (int k = 0; k < n; ++k) {
        const double dx = x0 + (k % columns) * pitch_x, dy = y0 - (k / columns) * pitch_y;
        const auto first = static_cast<uint32_t>(out.vertices.size());
        for (const Vec3& v : mesh.vertices) out.vertices.push_back({v.x + dx, v.y + dy, v.z});
        for (const auto& t : mesh.triangles)
            out.triangles.push_back({t[0] + first, t[1] + first, t[2] + first});
        boxes.push_back({b.min.x + dx, b.min.y + dy, b.max.x + dx, b.max.y + dy});
    }
    return out;
}

}  // namespace carve

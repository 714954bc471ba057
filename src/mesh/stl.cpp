// STL readers. Binary: 50 bytes per facet, welded as they come, from a file in blocks (the
// file is never held whole) or from a buffer already in memory (a pipe). ASCII: a whitespace
// tokenizer over "solid / facet / outer loop / vertex / endloop / endfacet / endsolid".
// Stored facet normals are ignored: orientation comes from the vertex order and is checked later.
#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <optional>
#include <string>

#include "mesh/loader.hpp"

namespace carve::detail {

namespace {

// Welds float32 points on their bit patterns (after turning -0 into +0). A slot is 4 bytes, a
// vertex index and a few bits of the hash as a tag, and the coordinates are compared in the
// vertex array itself: a soup of 3 million triangles has 9 million distinct points, whose
// table of 16-byte slots with the key inside took 512 MB (768 MB while it grew). A look-up
// now touches the vertex too; read_binary_stl prefetches both a few facets ahead, since on a
// large file welding is bound by memory latency, not arithmetic.
class FloatWelder {
  public:
    // A closed mesh of n triangles has about n / 2 points, n triangles have at most 3 n.
    explicit FloatWelder(size_t triangles) : triangles_(triangles) {
        const size_t expected_points = triangles / 2 + 16;
        vertices.reserve(expected_points);
        slots_.assign(std::bit_ceil(std::max<size_t>(16, 2 * expected_points)), kEmpty);
        mask_ = slots_.size() - 1;
    }

    static uint32_t key(float f) {
        const uint32_t b = std::bit_cast<uint32_t>(f);
        return b == 0x80000000u ? 0u : b;
    }

    // Where the point of hash h is looked up first: its slot, and, once that slot is in cache,
    // the vertex it names. The caller prefetches them itself: wrapped in a function, GCC takes
    // the prefetch for a pure call whose result is unused and drops it.
    const void* slot_of(uint64_t h) const { return &slots_[h & mask_]; }
    const void* vertex_of(uint64_t h) const {
        const uint32_t s = slots_[h & mask_];
        return s == kEmpty ? nullptr : &vertices[s & kIdMask];
    }

    uint32_t add(uint32_t x, uint32_t y, uint32_t z, uint64_t h) {
        if (2 * (vertices.size() + 1) > slots_.size()) grow();
        const double dx = std::bit_cast<float>(x), dy = std::bit_cast<float>(y),
                     dz = std::bit_cast<float>(z);
        const uint32_t tag = tag_of(h);
        for (uint64_t i = h & mask_;; i = (i + 1) & mask_) {
            const uint32_t s = slots_[i];
            if (s == kEmpty) {
                const uint32_t id = static_cast<uint32_t>(vertices.size());
                slots_[i] = tag | id;
                if (vertices.size() == vertices.capacity()) reserve_more();
                vertices.push_back({dx, dy, dz});
                return id;
            }
            if ((s & ~kIdMask) == tag) {
                const Vec3& v = vertices[s & kIdMask];
                if (v.x == dx && v.y == dy && v.z == dz) return s & kIdMask;
            }
        }
    }

    static uint64_t hash(uint32_t x, uint32_t y, uint32_t z) {
        uint64_t h = ((uint64_t(x) << 32) | y) * 0x9E3779B97F4A7C15ULL;
        h ^= uint64_t(z) * 0xC2B2AE3D27D4EB4FULL;
        h ^= h >> 29;
        h *= 0xFF51AFD7ED558CCDULL;
        h ^= h >> 32;
        return h;
    }

    std::vector<Vec3> vertices;

    // 26 bits of index. The all-ones slot (tag 63, index kIdMask) marks an empty one, so that
    // kIdMask itself is never a vertex.
    static constexpr uint32_t kIdMask = (1u << 26) - 1;
    static constexpr size_t kMaxVertices = kIdMask;

  private:
    static constexpr uint32_t kEmpty = 0xFFFFFFFFu;

    // The tag comes from the hash's top bits, the slot from its low ones.
    static uint32_t tag_of(uint64_t h) { return static_cast<uint32_t>(h >> 58) << 26; }

    // Past the closed mesh's estimate the vertices make room for one point per triangle (open
    // meshes, many shells), then for all 3 at once (a soup), rather than doubling: a soup's 9
    // million points doubled from 1.5 million held 144 MB of the old array beside 288 MB of
    // the new while they were copied. Pages reserved but not reached cost no memory.
    void reserve_more() {
        const size_t size = vertices.size();
        vertices.reserve(size < triangles_ ? triangles_ + 16 : std::max(3 * triangles_, 2 * size));
    }

    // The old table is dropped before the new one is made (the points are hashed again from
    // the vertex array), so that growing never holds both.
    void grow() {
        const size_t size = slots_.size() * 2;
        slots_ = std::vector<uint32_t>();  // frees it (= {} would keep its capacity)
        slots_.assign(size, kEmpty);
        mask_ = size - 1;
        for (uint32_t id = 0; id < vertices.size(); ++id) {
            const Vec3& v = vertices[id];
            const uint64_t h = hash(key(static_cast<float>(v.x)), key(static_cast<float>(v.y)),
                                    key(static_cast<float>(v.z)));
            uint64_t i = h & mask_;
            while (slots_[i] != kEmpty) i = (i + 1) & mask_;
            slots_[i] = tag_of(h) | id;
        }
    }

    std::vector<uint32_t> slots_;
    uint64_t mask_ = 0;
    size_t triangles_;
};

// The 9 coordinates of a facet record as welder keys (little-endian file, any host).
void facet_keys(const char* facet, uint32_t k[9]) {
    float v[9];
    std::memcpy(v, facet + 12, sizeof v);
    for (int i = 0; i < 9; ++i) {
        if constexpr (std::endian::native == std::endian::big)
            v[i] = std::bit_cast<float>(__builtin_bswap32(std::bit_cast<uint32_t>(v[i])));
        k[i] = FloatWelder::key(v[i]);
    }
}

// Welds `count` facet records, the first of which is facet number `first` of the file.
void weld_facets(const char* facets, uint32_t count, uint32_t first, const std::string& path,
                 FloatWelder& welder, Mesh& mesh) {
    // The slots of the facet kFar ahead are prefetched; by the time the facet kNear ahead is
    // reached its slots are in cache and name the vertices to prefetch. The points' hashes
    // wait in a ring until their facet is welded.
    constexpr uint32_t kFar = 16, kNear = 8, kRing = 32;
    uint64_t ring[kRing][3];
    uint32_t k[9];
    auto hash_facet = [&](uint32_t j) {
        facet_keys(facets + 50 * size_t(j), k);
        for (int c = 0; c < 3; ++c)
            ring[j % kRing][c] = FloatWelder::hash(k[3 * c], k[3 * c + 1], k[3 * c + 2]);
    };
    for (uint32_t j = 0; j < std::min(count, kFar); ++j) hash_facet(j);
    for (uint32_t i = 0; i < count; ++i) {
        if (i + kFar < count) {
            hash_facet(i + kFar);
            for (uint64_t h : ring[(i + kFar) % kRing]) __builtin_prefetch(welder.slot_of(h));
        }
        if (i + kNear < count)
            for (uint64_t h : ring[(i + kNear) % kRing]) __builtin_prefetch(welder.vertex_of(h));
        facet_keys(facets + 50 * size_t(i), k);
        auto& tri = mesh.triangles[first + i];
        for (int c = 0; c < 3; ++c) {
            const double x = std::bit_cast<float>(k[3 * c]), y = std::bit_cast<float>(k[3 * c + 1]),
                         z = std::bit_cast<float>(k[3 * c + 2]);
            check_point(path, x, y, z, [&] { return "triangle " + std::to_string(first + i + 1); });
            tri[c] = welder.add(k[3 * c], k[3 * c + 1], k[3 * c + 2], ring[i % kRing][c]);
        }
    }
}

// The facet count of the header, refused when the welder's indices could not number its
// points (unreachable within the 512 MB input limit, which allows 10.7 million facets).
uint32_t facet_count(const char header[84], const std::string& path) {
    uint32_t count = 0;
    std::memcpy(&count, header + 80, 4);
    if constexpr (std::endian::native == std::endian::big) count = __builtin_bswap32(count);
    if (3 * uint64_t(count) >= FloatWelder::kMaxVertices)
        fail(path, "the binary STL announces " + std::to_string(count) +
                       " triangles; carve reads at most 22 million");
    return count;
}

}  // namespace

void read_binary_stl(std::string_view data, const std::string& path, Mesh& mesh,
                     MeshReport& report) {
    report.format = "binary STL";
    const uint32_t count = facet_count(data.data(), path);
    report.triangles_read = count;
    FloatWelder welder(count);
    mesh.triangles.resize(count);
    weld_facets(data.data() + 84, count, 0, path, welder, mesh);
    mesh.vertices = std::move(welder.vertices);
}

void read_binary_stl(std::FILE* file, const std::string& path, Mesh& mesh, MeshReport& report) {
    report.format = "binary STL";
    char header[84];
    if (std::fread(header, 1, sizeof header, file) != sizeof header)
        fail(path, std::string("cannot read the file: ") + std::strerror(errno));
    const uint32_t count = facet_count(header, path);
    report.triangles_read = count;
    FloatWelder welder(count);
    mesh.triangles.resize(count);
    // Blocks of 64k facets (3.2 MB): large enough that reading costs nothing next to welding.
    constexpr uint32_t kBlock = 1u << 16;
    std::vector<char> block(50 * size_t(std::min(count, kBlock)));
    for (uint32_t done = 0; done < count;) {
        const uint32_t n = std::min(count - done, kBlock);
        const size_t got = std::fread(block.data(), 50, n, file);
        if (got != n) {
            if (std::ferror(file))
                fail(path, std::string("cannot read the file: ") + std::strerror(errno));
            fail(path, "the file shrank while it was read (truncated binary STL)");
        }
        weld_facets(block.data(), n, done, path, welder, mesh);
        done += n;
    }
    mesh.vertices = std::move(welder.vertices);
}

namespace {

// A set of float32 points by their welder keys: what binary_stl_soup_corners counts with.
class PointSet {
  public:
    explicit PointSet(size_t expected) : slots_(std::bit_ceil(2 * expected + 16), kEmpty) {}
    size_t size() const { return points_.size(); }
    void insert(const std::array<uint32_t, 3>& p, uint64_t h) {
        for (uint64_t i = h & mask();; i = (i + 1) & mask()) {
            if (slots_[i] == kEmpty) {
                slots_[i] = static_cast<uint32_t>(points_.size());
                points_.push_back(p);
                break;
            }
            if (points_[slots_[i]] == p) return;
        }
        if (2 * points_.size() > slots_.size()) grow();
    }

  private:
    static constexpr uint32_t kEmpty = ~0u;
    uint64_t mask() const { return slots_.size() - 1; }
    void grow() {
        const size_t size = 2 * slots_.size();
        std::vector<uint32_t>().swap(slots_);  // freed before the new table is made
        slots_.assign(size, kEmpty);
        for (uint32_t id = 0; id < points_.size(); ++id) {
            const auto& q = points_[id];
            uint64_t j = FloatWelder::hash(q[0], q[1], q[2]) & mask();
            while (slots_[j] != kEmpty) j = (j + 1) & mask();
            slots_[j] = id;
        }
    }
    std::vector<std::array<uint32_t, 3>> points_;
    std::vector<uint32_t> slots_;
};

// Calls f(point, hash) for each corner of the first `facets` facets after the header; false
// when the file ends early.
template <class F>
bool for_each_corner(std::FILE* file, uint32_t facets, std::vector<char>& block, F&& f) {
    if (std::fseek(file, 84, SEEK_SET) != 0) return false;
    const uint32_t per_block = static_cast<uint32_t>(block.size() / 50);
    uint32_t k[9];
    for (uint32_t done = 0; done < facets;) {
        const uint32_t n = std::min(facets - done, per_block);
        if (std::fread(block.data(), 50, n, file) != n) return false;
        for (uint32_t i = 0; i < n; ++i) {
            facet_keys(block.data() + 50 * size_t(i), k);
            for (int c = 0; c < 3; ++c)
                f(std::array<uint32_t, 3>{k[3 * c], k[3 * c + 1], k[3 * c + 2]},
                  FloatWelder::hash(k[3 * c], k[3 * c + 1], k[3 * c + 2]));
        }
        done += n;
    }
    return true;
}

}  // namespace

// Corners of a soup: every vertex used by one triangle alone opens the triangle's two edges at
// it, so a mesh of T triangles with V distinct points has at least 2V - 3T such vertices and as
// many open edges; past V = 2.25 T that is more than half of its 3T edges, is_triangle_soup's
// test. The points are counted exactly, one eighth of the hash range per pass over the file,
// so that a table of all of them (a 10-million-triangle soup has 30 million) is never held.
// The passes run only when the file's first 256k facets look like a soup (over 2 points a
// facet; a solid's patch has about 0.5): on a solid the check costs one read of 13 MB.
std::optional<SoupProof> binary_stl_soup_corners(std::FILE* file, const std::string& path,
                                                 uint32_t min_facets) {
    char header[84];
    if (std::fread(header, 1, sizeof header, file) != sizeof header) return std::nullopt;
    const uint32_t count = facet_count(header, path);
    if (count < min_facets) return std::nullopt;
    std::vector<char> block(50 * size_t(1u << 16));
    {
        const uint32_t prefix = std::min(count, 1u << 18);
        PointSet first(prefix);
        if (!for_each_corner(file, prefix, block,
                             [&](const auto& p, uint64_t h) { first.insert(p, h); }) ||
            first.size() <= 2 * size_t(prefix))
            return std::nullopt;
    }
    constexpr int kParts = 8;
    uint64_t total = 0;
    for (int part = 0; part < kParts; ++part) {
        PointSet points(3 * size_t(count) / kParts / 2);
        if (!for_each_corner(file, count, block, [&](const auto& p, uint64_t h) {
                if (int(h >> 61) == part) points.insert(p, h);
            }))
            return std::nullopt;
        total += points.size();
        if (double(total) > 2.25 * count) return SoupProof{count, total};
    }
    return std::nullopt;
}

namespace {

// Whitespace-separated words, from text in memory or from a file read in blocks. From a file,
// the words already consumed are dropped as the next block comes in, so a word (and the line
// counted for messages) never spans two blocks; a word stays valid until the next call.
class Tokens {
  public:
    explicit Tokens(std::string_view data) : data_(data) {}
    // Reads at most size bytes: the size the file had when it was opened, as a file read whole.
    Tokens(std::FILE* file, size_t size, const std::string& path)
        : file_(file), path_(&path), unread_(size) {
        refill(0);
        if (data_.substr(0, 3) == std::string_view("\xEF\xBB\xBF", 3)) pos_ = 3;
    }

    // The next word, empty at the end.
    std::string_view next() {
        for (;;) {
            while (pos_ < data_.size() && is_space(data_[pos_])) ++pos_;
            if (pos_ < data_.size() || !refill(pos_)) break;
        }
        size_t start = pos_;
        for (;;) {
            while (pos_ < data_.size() && !is_space(data_[pos_])) ++pos_;
            if (pos_ < data_.size() || !file_) break;
            // The text before the word is dropped even when the file has nothing more: the
            // word then ends the file.
            const bool more = refill(start);
            start = 0;
            if (!more) break;
        }
        last_ = start;
        return data_.substr(start, pos_ - start);
    }

    void skip_line() {
        for (;;) {
            while (pos_ < data_.size() && data_[pos_] != '\n' && data_[pos_] != '\r') ++pos_;
            if (pos_ < data_.size() || !refill(pos_)) break;
        }
    }

    // The 1-based line of the last word.
    size_t last_line() const { return lines_dropped_ + line_of(data_, last_); }

  private:
    static bool is_space(char c) {
        return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v';
    }

    // Drops the text before keep and appends the next block; false at the end of the file.
    bool refill(size_t keep) {
        if (!file_) return false;
        lines_dropped_ +=
            static_cast<size_t>(std::count(buffer_.begin(), buffer_.begin() + keep, '\n'));
        buffer_.erase(0, keep);
        pos_ -= keep;
        if (buffer_.size() > kMaxWord)
            fail(*path_, "malformed ASCII STL at line " + std::to_string(lines_dropped_ + 1) +
                             ": a word of more than 1 MB");
        const size_t old = buffer_.size();
        const size_t want = std::min(kBlock, unread_);
        buffer_.resize(old + want);
        const size_t got = want ? std::fread(buffer_.data() + old, 1, want, file_) : 0;
        buffer_.resize(old + got);
        unread_ -= got;
        if (got == 0 && std::ferror(file_))
            fail(*path_, std::string("cannot read the file: ") + std::strerror(errno));
        data_ = buffer_;
        return got > 0;
    }

    static constexpr size_t kBlock = 4 << 20;
    static constexpr size_t kMaxWord = 1 << 20;
    std::string_view data_;
    size_t pos_ = 0, last_ = 0;
    std::FILE* file_ = nullptr;
    const std::string* path_ = nullptr;
    size_t unread_ = 0;
    std::string buffer_;
    size_t lines_dropped_ = 0;
};

bool same_word(std::string_view a, std::string_view keyword) {
    if (a.size() != keyword.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(a[i])) != keyword[i]) return false;
    return true;
}

}  // namespace

namespace {

void parse_ascii_stl(Tokens& tokens, const std::string& path, Mesh& mesh, MeshReport& report,
                     Welder& welder) {
    report.format = "ASCII STL";
    auto malformed = [&](const std::string& what) {
        fail(path,
             "malformed ASCII STL at line " + std::to_string(tokens.last_line()) + ": " + what);
    };
    auto describe = [](std::string_view tok) {
        if (tok.empty()) return std::string("the end of the file");
        std::string quoted(1, '\'');  // built up in place: GCC 12 warns about "'" + string
        quoted.append(tok.substr(0, 40));
        quoted.push_back('\'');
        return quoted;
    };
    auto expect = [&](std::string_view keyword) {
        std::string_view tok = tokens.next();
        if (!same_word(tok, keyword))
            malformed("expected '" + std::string(keyword) + "', found " + describe(tok));
    };
    auto number = [&]() {
        std::string_view tok = tokens.next();
        double value = 0;
        if (!parse_double(tok, value)) malformed("expected a number, found " + describe(tok));
        return value;
    };

    std::vector<uint32_t> loop;
    std::string_view tok = tokens.next();
    if (!same_word(tok, "solid")) malformed("expected 'solid', found " + describe(tok));
    // Several solids may follow one another; each one's name runs to the end of its line.
    while (!tok.empty()) {
        if (!same_word(tok, "solid")) malformed("expected 'solid', found " + describe(tok));
        tokens.skip_line();
        for (;;) {
            tok = tokens.next();
            if (same_word(tok, "endsolid")) {
                tokens.skip_line();
                break;
            }
            if (tok.empty()) malformed("the file ends without 'endsolid' (truncated?)");
            if (!same_word(tok, "facet"))
                malformed("expected 'facet' or 'endsolid', found " + describe(tok));
            tok = tokens.next();
            if (same_word(tok, "normal")) {
                // Normals are not used; some exporters write nan here, so skip the words.
                tokens.next();
                tokens.next();
                tokens.next();
                tok = tokens.next();
            }
            if (!same_word(tok, "outer"))
                malformed("expected 'outer loop', found " + describe(tok));
            expect("loop");
            loop.clear();
            for (;;) {
                tok = tokens.next();
                if (!same_word(tok, "vertex")) break;
                const double x = number(), y = number(), z = number();
                check_point(path, x, y, z,
                            [&] { return "vertex at line " + std::to_string(tokens.last_line()); });
                loop.push_back(welder.add(x, y, z));
            }
            if (!same_word(tok, "endloop"))
                malformed("expected 'vertex' or 'endloop', found " + describe(tok));
            if (loop.size() < 3)
                malformed("a facet has " + std::to_string(loop.size()) + " vertices, not 3");
            expect("endfacet");
            for (size_t k = 1; k + 1 < loop.size(); ++k)
                mesh.triangles.push_back({loop[0], loop[k], loop[k + 1]});
        }
        tok = tokens.next();
    }
    report.triangles_read = mesh.triangles.size();
    mesh.vertices = welder.take();
}

}  // namespace

void read_ascii_stl(std::string_view data, const std::string& path, Mesh& mesh,
                    MeshReport& report) {
    Tokens tokens(data);
    Welder welder(data.size() / 400 + 16, path);
    parse_ascii_stl(tokens, path, mesh, report, welder);
}

TextCounts count_ascii_stl(std::FILE* file, size_t size, const std::string& path) {
    // The reading pass's words in the same order, with a solid's name skipped as it skips it:
    // a valid file's triangles are counted exactly, never fewer. Every vertex is a corner of
    // its facet; "vertex 1 2 3" takes 12 bytes or more, and its hash 8.
    TextCounts counts;
    std::vector<uint64_t> hashes;
    hashes.reserve(size / 12);
    Tokens tokens(file, size, path);
    uint64_t corners = 0;
    for (std::string_view tok = tokens.next(); !tok.empty(); tok = tokens.next()) {
        if (same_word(tok, "solid") || same_word(tok, "endsolid")) {
            tokens.skip_line();
        } else if (same_word(tok, "vertex")) {
            double c[3] = {0, 0, 0};
            for (double& value : c)
                if (!parse_double(tokens.next(), value)) value = 0;
            hashes.push_back(hash_point(c[0] + 0.0, c[1] + 0.0, c[2] + 0.0));
            ++corners;
        } else if (same_word(tok, "endloop")) {
            if (corners >= 3) counts.triangles += corners - 2;
            corners = 0;
        }
    }
    counts.corners = count_distinct(hashes);
    return counts;
}

void read_ascii_stl(std::FILE* file, size_t size, const std::string& path, Mesh& mesh,
                    MeshReport& report, const TextCounts* counts) {
    Tokens tokens(file, size, path);
    Welder welder(size / 400 + 16, path);
    if (counts) {
        welder.reserve(counts->corners + 16);
        mesh.triangles.reserve(counts->triangles);
    }
    parse_ascii_stl(tokens, path, mesh, report, welder);
}

}  // namespace carve::detail

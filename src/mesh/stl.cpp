// STL readers. Binary: one pass over the buffer already in memory, 50 bytes per facet. ASCII: a
// whitespace tokenizer over "solid / facet / outer loop / vertex / endloop / endfacet / endsolid".
// Stored facet normals are ignored: orientation comes from the vertex order and is checked later.
#include <algorithm>
#include <bit>
#include <cctype>
#include <cstring>
#include <string>

#include "mesh/loader.hpp"

namespace carve::detail {

namespace {

// Welds float32 points on their bit patterns (after turning -0 into +0). The key sits inside
// the slot, so a probe costs one memory access, and read_binary_stl prefetches the slots of a
// few facets ahead: on a large file the welding is bound by memory latency, not arithmetic.
class FloatWelder {
  public:
    explicit FloatWelder(size_t expected_points) {
        vertices.reserve(expected_points);
        slots_.assign(std::bit_ceil(std::max<size_t>(16, 2 * expected_points)), Slot{});
        mask_ = slots_.size() - 1;
    }

    static uint32_t key(float f) {
        const uint32_t b = std::bit_cast<uint32_t>(f);
        return b == 0x80000000u ? 0u : b;
    }

    // Where point (x, y, z) is looked up first. The caller prefetches it itself: wrapped in a
    // function, GCC takes the prefetch for a pure call whose result is unused and drops it.
    const void* slot_of(uint32_t x, uint32_t y, uint32_t z) const {
        return &slots_[hash(x, y, z) & mask_];
    }

    uint32_t add(uint32_t x, uint32_t y, uint32_t z) {
        if (2 * (vertices.size() + 1) > slots_.size()) grow();
        for (uint64_t i = hash(x, y, z) & mask_;; i = (i + 1) & mask_) {
            Slot& s = slots_[i];
            if (s.id == kEmpty) {
                s = {x, y, z, static_cast<uint32_t>(vertices.size())};
                vertices.push_back(
                    {std::bit_cast<float>(x), std::bit_cast<float>(y), std::bit_cast<float>(z)});
                return s.id;
            }
            if (s.x == x && s.y == y && s.z == z) return s.id;
        }
    }

    std::vector<Vec3> vertices;

  private:
    static constexpr uint32_t kEmpty = 0xFFFFFFFFu;
    struct Slot {
        uint32_t x = 0, y = 0, z = 0, id = kEmpty;
    };

    static uint64_t hash(uint32_t x, uint32_t y, uint32_t z) {
        uint64_t h = ((uint64_t(x) << 32) | y) * 0x9E3779B97F4A7C15ULL;
        h ^= uint64_t(z) * 0xC2B2AE3D27D4EB4FULL;
        h ^= h >> 29;
        h *= 0xFF51AFD7ED558CCDULL;
        h ^= h >> 32;
        return h;
    }

    void grow() {
        std::vector<Slot> old(slots_.size() * 2);
        old.swap(slots_);
        mask_ = slots_.size() - 1;
        for (const Slot& s : old) {
            if (s.id == kEmpty) continue;
            uint64_t i = hash(s.x, s.y, s.z) & mask_;
            while (slots_[i].id != kEmpty) i = (i + 1) & mask_;
            slots_[i] = s;
        }
    }

    std::vector<Slot> slots_;
    uint64_t mask_ = 0;
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

}  // namespace

void read_binary_stl(std::string_view data, const std::string& path, Mesh& mesh,
                     MeshReport& report) {
    report.format = "binary STL";
    uint32_t count = 0;
    std::memcpy(&count, data.data() + 80, 4);
    if constexpr (std::endian::native == std::endian::big) count = __builtin_bswap32(count);
    report.triangles_read = count;

    // A closed mesh has about half as many vertices as triangles.
    FloatWelder welder(count / 2 + 16);
    mesh.triangles.resize(count);
    const char* facets = data.data() + 84;
    constexpr uint32_t kAhead = 8;
    uint32_t k[9];
    for (uint32_t i = 0; i < count; ++i) {
        if (i + kAhead < count) {
            facet_keys(facets + 50 * size_t(i + kAhead), k);
            for (int c = 0; c < 9; c += 3)
                __builtin_prefetch(welder.slot_of(k[c], k[c + 1], k[c + 2]));
        }
        facet_keys(facets + 50 * size_t(i), k);
        auto& tri = mesh.triangles[i];
        for (int c = 0; c < 3; ++c) {
            const double x = std::bit_cast<float>(k[3 * c]), y = std::bit_cast<float>(k[3 * c + 1]),
                         z = std::bit_cast<float>(k[3 * c + 2]);
            check_point(path, x, y, z, [&] { return "triangle " + std::to_string(i + 1); });
            tri[c] = welder.add(k[3 * c], k[3 * c + 1], k[3 * c + 2]);
        }
    }
    mesh.vertices = std::move(welder.vertices);
}

namespace {

class Tokens {
  public:
    Tokens(std::string_view data) : data_(data) {}

    // The next whitespace-separated word, empty at the end.
    std::string_view next() {
        while (pos_ < data_.size() && is_space(data_[pos_])) ++pos_;
        size_t start = pos_;
        while (pos_ < data_.size() && !is_space(data_[pos_])) ++pos_;
        last_ = start;
        return data_.substr(start, pos_ - start);
    }

    void skip_line() {
        while (pos_ < data_.size() && data_[pos_] != '\n' && data_[pos_] != '\r') ++pos_;
    }

    size_t last_position() const { return last_; }

  private:
    static bool is_space(char c) {
        return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v';
    }
    std::string_view data_;
    size_t pos_ = 0, last_ = 0;
};

bool same_word(std::string_view a, std::string_view keyword) {
    if (a.size() != keyword.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (std::tolower(static_cast<unsigned char>(a[i])) != keyword[i]) return false;
    return true;
}

}  // namespace

void read_ascii_stl(std::string_view data, const std::string& path, Mesh& mesh,
                    MeshReport& report) {
    report.format = "ASCII STL";
    Tokens tokens(data);
    auto malformed = [&](const std::string& what) {
        fail(path, "malformed ASCII STL at line " +
                       std::to_string(line_of(data, tokens.last_position())) + ": " + what);
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

    Welder welder(data.size() / 400 + 16);
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
                check_point(path, x, y, z, [&] {
                    return "vertex at line " +
                           std::to_string(line_of(data, tokens.last_position()));
                });
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

}  // namespace carve::detail

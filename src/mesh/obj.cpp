// Wavefront OBJ reader: "v x y z" and "f a b c ..." (with a/b/c, a//c and negative, i.e.
// relative, indices). Polygons become triangle fans; every other statement is ignored.
#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <optional>
#include <string>

#include "mesh/loader.hpp"

namespace carve::detail {

namespace {

bool is_blank(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

// Splits one line into words.
class Words {
  public:
    explicit Words(std::string_view line) : line_(line) {}
    std::string_view next() {
        while (pos_ < line_.size() && is_blank(line_[pos_])) ++pos_;
        size_t start = pos_;
        while (pos_ < line_.size() && !is_blank(line_[pos_])) ++pos_;
        return line_.substr(start, pos_ - start);
    }

  private:
    std::string_view line_;
    size_t pos_ = 0;
};

// 'tok', built up in place: GCC 12 warns (-Wrestrict) about "'" + std::string(tok) here.
std::string quoted(std::string_view tok) {
    std::string q(1, '\'');
    q.append(tok);
    q.push_back('\'');
    return q;
}

// The 0-based vertex that a face's word ("7", "7/1", "-2//3") refers to among the n defined so
// far: OBJ counts from 1, and back from the last with negative numbers. Nothing when the word
// is no reference (index is then 0) or names a vertex not defined yet (index is as written).
std::optional<size_t> vertex_ref(std::string_view tok, size_t n, long long& index) {
    const std::string_view text = tok.substr(0, tok.find('/'));
    index = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), index);
    if (ec != std::errc() || end != text.data() + text.size()) index = 0;
    if (index == 0) return std::nullopt;
    const long long zero_based = index > 0 ? index - 1 : static_cast<long long>(n) + index;
    if (zero_based < 0 || zero_based >= static_cast<long long>(n)) return std::nullopt;
    return static_cast<size_t>(zero_based);
}

// The reader's state between lines, so that a file can be fed in pieces.
class ObjReader {
  public:
    ObjReader(size_t file_bytes, const std::string& path, Mesh& mesh,
              const TextCounts* counts = nullptr)
        : path_(path), mesh_(mesh), welder_(file_bytes / 64 + 16, path) {
        if (counts) {
            welder_.reserve(counts->vertex_lines);
            welded_.reserve(counts->vertex_lines);
            mesh_.triangles.reserve(counts->triangles);
        }
    }

    void line(std::string_view line) {
        ++line_no_;
        if (size_t hash = line.find('#'); hash != std::string_view::npos)
            line = line.substr(0, hash);

        Words words(line);
        std::string_view keyword = words.next();
        if (keyword == "v") {
            double c[3];
            for (double& value : c) {
                std::string_view tok = words.next();
                if (!parse_double(tok, value))
                    malformed(tok.empty() ? "a vertex needs three coordinates"
                                          : quoted(tok) + " is not a number");
            }
            check_point(path_, c[0], c[1], c[2],
                        [&] { return "the vertex at line " + std::to_string(line_no_); });
            welded_.push_back(welder_.add(c[0], c[1], c[2]));
        } else if (keyword == "f") {
            polygon_.clear();
            for (std::string_view tok = words.next(); !tok.empty(); tok = words.next()) {
                long long index = 0;
                const auto at = vertex_ref(tok, welded_.size(), index);
                if (index == 0) malformed(quoted(tok) + " is not a vertex reference");
                if (!at)
                    malformed("a face refers to vertex " + std::to_string(index) + " but " +
                              std::to_string(welded_.size()) + " vertices are defined so far");
                polygon_.push_back(welded_[*at]);
            }
            if (polygon_.size() < 3)
                malformed("a face has " + std::to_string(polygon_.size()) +
                          " vertices, not 3 or more");
            for (size_t k = 1; k + 1 < polygon_.size(); ++k)
                mesh_.triangles.push_back({polygon_[0], polygon_[k], polygon_[k + 1]});
        }
    }

    void finish(MeshReport& report) {
        report.triangles_read = mesh_.triangles.size();
        mesh_.vertices = welder_.take();
    }

  private:
    [[noreturn]] void malformed(const std::string& what) const {
        fail(path_, "malformed OBJ at line " + std::to_string(line_no_) + ": " + what);
    }

    const std::string& path_;
    Mesh& mesh_;
    Welder welder_;
    std::vector<uint32_t> welded_;  // file vertex (0-based) -> welded vertex
    std::vector<uint32_t> polygon_;
    size_t line_no_ = 0;
};

}  // namespace

void read_obj(std::string_view data, const std::string& path, Mesh& mesh, MeshReport& report) {
    report.format = "OBJ";
    ObjReader reader(data.size(), path, mesh);
    size_t pos = 0;
    while (pos < data.size()) {
        size_t eol = data.find('\n', pos);
        if (eol == std::string_view::npos) eol = data.size();
        reader.line(data.substr(pos, eol - pos));
        pos = eol + 1;
    }
    reader.finish(report);
}

namespace {

// Calls line(text) for each line of an open file of the given size, from its start, in blocks
// of 4 MB up to the size the file had when it was opened (as a file read whole); a line cut by
// a block's end waits in `rest` for the next block.
template <class Line>
void for_each_line(std::FILE* file, size_t size, const std::string& path, Line&& line) {
    std::vector<char> block(4 << 20);
    std::string rest;
    bool first = true;
    for (size_t total = 0; total < size;) {
        const size_t got = std::fread(block.data(), 1, std::min(block.size(), size - total), file);
        if (got == 0) break;
        total += got;
        std::string_view d(block.data(), got);
        if (first && d.substr(0, 3) == std::string_view("\xEF\xBB\xBF", 3)) d.remove_prefix(3);
        first = false;
        size_t pos = 0;
        for (size_t eol; (eol = d.find('\n', pos)) != std::string_view::npos; pos = eol + 1) {
            if (rest.empty()) {
                line(d.substr(pos, eol - pos));
            } else {
                rest.append(d.substr(pos, eol - pos));
                line(std::string_view(rest));
                rest.clear();
            }
        }
        rest.append(d.substr(pos));
    }
    if (std::ferror(file)) fail(path, std::string("cannot read the file: ") + std::strerror(errno));
    if (!rest.empty()) line(std::string_view(rest));
}

}  // namespace

TextCounts count_obj(std::FILE* file, size_t size, const std::string& path) {
    TextCounts counts;
    // Each vertex line's hash, then whether a face uses it: faces may refer back relatively,
    // so the lines are marked as the faces come. What the reading pass would refuse is skipped
    // here. A vertex line takes 8 bytes or more, as its hash does.
    std::vector<uint64_t> hashes;
    hashes.reserve(size / 8);
    std::vector<bool> used;
    for_each_line(file, size, path, [&](std::string_view line) {
        Words words(line.substr(0, line.find('#')));
        const std::string_view keyword = words.next();
        if (keyword == "v") {
            double c[3] = {0, 0, 0};
            for (double& value : c)
                if (!parse_double(words.next(), value)) value = 0;
            hashes.push_back(hash_point(c[0] + 0.0, c[1] + 0.0, c[2] + 0.0));
        } else if (keyword == "f") {
            if (used.size() < hashes.size()) used.resize(hashes.size());
            uint64_t corners = 0;
            for (std::string_view tok = words.next(); !tok.empty(); tok = words.next(), ++corners) {
                long long index = 0;
                if (const auto at = vertex_ref(tok, hashes.size(), index)) used[*at] = true;
            }
            if (corners >= 3) counts.triangles += corners - 2;
        }
    });
    counts.vertex_lines = hashes.size();
    // Only the points a face uses count: the unused ones are moved out first.
    size_t kept = 0;
    for (size_t i = 0; i < hashes.size() && i < used.size(); ++i)
        if (used[i]) hashes[kept++] = hashes[i];
    hashes.resize(kept);
    counts.corners = count_distinct(hashes);
    return counts;
}

void read_obj(std::FILE* file, size_t size, const std::string& path, Mesh& mesh, MeshReport& report,
              const TextCounts* counts) {
    report.format = "OBJ";
    ObjReader reader(size, path, mesh, counts);
    for_each_line(file, size, path, [&](std::string_view line) { reader.line(line); });
    reader.finish(report);
}

}  // namespace carve::detail

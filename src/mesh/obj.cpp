// Wavefront OBJ reader: "v x y z" and "f a b c ..." (with a/b/c, a//c and negative, i.e.
// relative, indices). Polygons become triangle fans; every other statement is ignored.
#include <charconv>
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

}  // namespace

void read_obj(std::string_view data, const std::string& path, Mesh& mesh, MeshReport& report) {
    report.format = "OBJ";
    Welder welder(data.size() / 64 + 16);
    std::vector<uint32_t> welded;  // file vertex (0-based) -> welded vertex
    std::vector<uint32_t> polygon;
    size_t line_no = 0, pos = 0;
    auto malformed = [&](const std::string& what) {
        fail(path, "malformed OBJ at line " + std::to_string(line_no) + ": " + what);
    };

    while (pos < data.size()) {
        size_t eol = data.find('\n', pos);
        if (eol == std::string_view::npos) eol = data.size();
        std::string_view line = data.substr(pos, eol - pos);
        pos = eol + 1;
        ++line_no;
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
                                          : "'" + std::string(tok) + "' is not a number");
            }
            check_point(path, c[0], c[1], c[2],
                        [&] { return "the vertex at line " + std::to_string(line_no); });
            welded.push_back(welder.add(c[0], c[1], c[2]));
        } else if (keyword == "f") {
            polygon.clear();
            for (std::string_view tok = words.next(); !tok.empty(); tok = words.next()) {
                std::string_view index_text = tok.substr(0, tok.find('/'));
                long long index = 0;
                auto [end, ec] = std::from_chars(index_text.data(),
                                                 index_text.data() + index_text.size(), index);
                if (ec != std::errc() || end != index_text.data() + index_text.size() || index == 0)
                    malformed("'" + std::string(tok) + "' is not a vertex reference");
                const long long n = static_cast<long long>(welded.size());
                const long long zero_based = index > 0 ? index - 1 : n + index;
                if (zero_based < 0 || zero_based >= n)
                    malformed("a face refers to vertex " + std::to_string(index) + " but " +
                              std::to_string(n) + " vertices are defined so far");
                polygon.push_back(welded[static_cast<size_t>(zero_based)]);
            }
            if (polygon.size() < 3)
                malformed("a face has " + std::to_string(polygon.size()) +
                          " vertices, not 3 or more");
            for (size_t k = 1; k + 1 < polygon.size(); ++k)
                mesh.triangles.push_back({polygon[0], polygon[k], polygon[k + 1]});
        }
    }
    report.triangles_read = mesh.triangles.size();
    mesh.vertices = welder.take();
}

}  // namespace carve::detail

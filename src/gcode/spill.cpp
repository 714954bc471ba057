// Varint encoding of spilled layers (see spill.hpp).
#include "gcode/spill.hpp"

#include <cstdint>
#include <cstring>
#include <stdexcept>

namespace carve {

namespace {

void put_varint(std::string& out, std::uint64_t v) {
    while (v >= 0x80) {
        out.push_back(static_cast<char>((v & 0x7f) | 0x80));
        v >>= 7;
    }
    out.push_back(static_cast<char>(v));
}

void put_signed(std::string& out, std::int64_t v) {
    put_varint(out, (static_cast<std::uint64_t>(v) << 1) ^ static_cast<std::uint64_t>(v >> 63));
}

void put_double(std::string& out, double v) {
    char bytes[sizeof v];
    std::memcpy(bytes, &v, sizeof v);
    out.append(bytes, sizeof v);
}

// A count, then zig-zag deltas from the previous point (the first from 0, 0).
void put_points(std::string& out, const Path& path) {
    put_varint(out, path.size());
    Point prev(0, 0);
    for (const Point& p : path) {
        put_signed(out, p.X - prev.X);
        put_signed(out, p.Y - prev.Y);
        prev = p;
    }
}

class Reader {
  public:
    explicit Reader(const std::string& s) : p_(s.data()), end_(s.data() + s.size()) {}

    std::uint64_t varint() {
        std::uint64_t v = 0;
        for (int shift = 0; shift < 64; shift += 7) {
            const auto byte = static_cast<unsigned char>(next());
            v |= static_cast<std::uint64_t>(byte & 0x7f) << shift;
            if (!(byte & 0x80)) return v;
        }
        throw std::runtime_error("carve: malformed layer spill (varint)");
    }
    std::int64_t signed_varint() {
        const std::uint64_t u = varint();
        return static_cast<std::int64_t>(u >> 1) ^ -static_cast<std::int64_t>(u & 1);
    }
    double real() {
        if (end_ - p_ < static_cast<std::ptrdiff_t>(sizeof(double)))
            throw std::runtime_error("carve: truncated layer spill");
        double v;
        std::memcpy(&v, p_, sizeof v);
        p_ += sizeof v;
        return v;
    }
    char next() {
        if (p_ == end_) throw std::runtime_error("carve: truncated layer spill");
        return *p_++;
    }
    bool done() const { return p_ == end_; }

  private:
    const char* p_;
    const char* end_;
};

void read_points(Reader& r, const std::string& blob, Path& path) {
    const std::uint64_t n = r.varint();
    if (n > blob.size()) throw std::runtime_error("carve: malformed layer spill (points)");
    path.resize(n);
    Point prev(0, 0);
    for (Point& p : path) {
        p.X = prev.X + r.signed_varint();
        p.Y = prev.Y + r.signed_varint();
        prev = p;
    }
}

}  // namespace

std::string encode_layer(const LayerToolpaths& layer) {
    std::string out;
    size_t points = 0;
    for (const Extrusion& e : layer.extrusions) points += e.points.size();
    out.reserve(32 + layer.extrusions.size() * 16 + points * 4);
    put_signed(out, layer.index);
    put_double(out, layer.z);
    put_varint(out, layer.extrusions.size());
    for (const Extrusion& e : layer.extrusions) {
        out.push_back(static_cast<char>(e.feature));
        out.push_back(static_cast<char>(e.closed ? 1 : 0));
        put_signed(out, e.cavity);
        put_double(out, e.flow);
        put_points(out, e.points);
    }
    put_varint(out, layer.travels.size());
    for (const Travel& t : layer.travels) {
        out.push_back(static_cast<char>(t.kind));
        put_points(out, t.via);
    }
    put_varint(out, layer.comb_region.size());
    for (const Path& p : layer.comb_region) put_points(out, p);
    put_varint(out, layer.thin_region.size());
    for (const Path& p : layer.thin_region) put_points(out, p);
    put_varint(out, layer.island_starts.size());
    for (size_t k : layer.island_starts) put_varint(out, k);
    return out;
}

LayerToolpaths decode_layer(const std::string& blob) {
    Reader r(blob);
    LayerToolpaths layer;
    layer.index = static_cast<int>(r.signed_varint());
    layer.z = r.real();
    const std::uint64_t count = r.varint();
    if (count > blob.size()) throw std::runtime_error("carve: malformed layer spill (count)");
    layer.extrusions.resize(count);
    for (Extrusion& e : layer.extrusions) {
        const int feature = static_cast<unsigned char>(r.next());
        if (feature >= static_cast<int>(kFeatureCount))
            throw std::runtime_error("carve: malformed layer spill (feature)");
        e.feature = static_cast<Feature>(feature);
        e.closed = (r.next() & 1) != 0;
        e.cavity = static_cast<int>(r.signed_varint());
        e.flow = r.real();
        read_points(r, blob, e.points);
    }
    const std::uint64_t travels = r.varint();
    if (travels != 0 && travels != count)
        throw std::runtime_error("carve: malformed layer spill (travels)");
    layer.travels.resize(travels);
    for (Travel& t : layer.travels) {
        const int kind = static_cast<unsigned char>(r.next());
        if (kind > static_cast<int>(TravelKind::Leaves))
            throw std::runtime_error("carve: malformed layer spill (travel)");
        t.kind = static_cast<TravelKind>(kind);
        read_points(r, blob, t.via);
    }
    const std::uint64_t contours = r.varint();
    if (contours > blob.size()) throw std::runtime_error("carve: malformed layer spill (count)");
    layer.comb_region.resize(contours);
    for (Path& p : layer.comb_region) read_points(r, blob, p);
    const std::uint64_t thin = r.varint();
    if (thin > blob.size()) throw std::runtime_error("carve: malformed layer spill (count)");
    layer.thin_region.resize(thin);
    for (Path& p : layer.thin_region) read_points(r, blob, p);
    const std::uint64_t islands = r.varint();
    if (islands > count + 1) throw std::runtime_error("carve: malformed layer spill (islands)");
    layer.island_starts.resize(islands);
    for (size_t& k : layer.island_starts) {
        const std::uint64_t first = r.varint();
        if (first > count || (&k != layer.island_starts.data() && first < *(&k - 1)))
            throw std::runtime_error("carve: malformed layer spill (islands)");
        k = first;
    }
    if (!r.done()) throw std::runtime_error("carve: malformed layer spill (trailing bytes)");
    return layer;
}

}  // namespace carve

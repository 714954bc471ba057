// binary_stl (mesh.hpp): the one mesh writer carve has. Binary, since it is a quarter of ASCII's
// size and reads back to the same float32 points every reader welds alike.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>

#include "mesh/mesh.hpp"

namespace carve {

namespace {

static_assert(std::endian::native == std::endian::little,
              "binary STL is little-endian; this writer copies floats as the machine holds them");

void put(std::string& out, float f) {
    char b[4];
    std::memcpy(b, &f, 4);
    out.append(b, 4);
}

void put(std::string& out, uint32_t n) {
    char b[4];
    std::memcpy(b, &n, 4);
    out.append(b, 4);
}

}  // namespace

std::string binary_stl(const Mesh& mesh, const std::string& name) {
    std::string out(80, ' ');
    // A header starting "solid" reads as ASCII to some readers: never let the name begin so.
    const std::string head = "carve " + name;
    out.replace(0, std::min<size_t>(80, head.size()), head, 0, 80);
    out.reserve(84 + 50 * mesh.triangles.size());
    put(out, static_cast<uint32_t>(mesh.triangles.size()));
    for (const auto& t : mesh.triangles) {
        const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
        const Vec3 u{b.x - a.x, b.y - a.y, b.z - a.z}, v{c.x - a.x, c.y - a.y, c.z - a.z};
        Vec3 n{u.y * v.z - u.z * v.y, u.z * v.x - u.x * v.z, u.x * v.y - u.y * v.x};
        const double len = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
        if (len > 0) n = {n.x / len, n.y / len, n.z / len};
        for (const Vec3& p : {n, a, b, c}) {
            put(out, static_cast<float>(p.x));
            put(out, static_cast<float>(p.y));
            put(out, static_cast<float>(p.z));
        }
        out.append(2, '\0');
    }
    return out;
}

}  // namespace carve

// Headless thumbnails of the mesh, PNG and base64 (thumbnail.hpp).
#include "gcode/thumbnail.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include "base/error.hpp"
#include "base/png.hpp"

namespace carve {

namespace {

struct V3 {
    double x, y, z;
};
V3 sub(V3 a, V3 b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
double dot(V3 a, V3 b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
V3 cross(V3 a, V3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
V3 unit(V3 a) {
    const double n = std::sqrt(dot(a, a));
    return n > 0 ? V3{a.x / n, a.y / n, a.z / n} : a;
}

}  // namespace

std::vector<uint8_t> render_thumbnail(const std::vector<Vec3>& vertices,
                                      const std::vector<std::array<uint32_t, 3>>& triangles,
                                      int width, int height) {
    constexpr int kSuper = 2;  // supersampling per axis
    const int W = width * kSuper, H = height * kSuper;
    std::vector<uint8_t> out(static_cast<size_t>(width) * height * 4, 0);
    if (vertices.empty() || triangles.empty() || width <= 0 || height <= 0) return out;
    // The camera: from the front right (-y is the front of the bed), 35 degrees above.
    const double az = 45 * M_PI / 180, el = 35 * M_PI / 180;
    const V3 to_camera = {std::cos(el) * std::sin(az), -std::cos(el) * std::cos(az), std::sin(el)};
    const V3 right = unit(cross({-to_camera.x, -to_camera.y, -to_camera.z}, {0, 0, 1}));
    const V3 up = cross(right, {-to_camera.x, -to_camera.y, -to_camera.z});
    const V3 light = unit({to_camera.x - 0.3, to_camera.y, to_camera.z + 0.4});
    std::vector<V3> screen(vertices.size());  // x right, y up, z towards the camera
    double x0 = std::numeric_limits<double>::max(), x1 = -x0, y0 = x0, y1 = -x0;
    for (size_t i = 0; i < vertices.size(); ++i) {
        const V3 p{vertices[i].x, vertices[i].y, vertices[i].z};
        screen[i] = {dot(p, right), dot(p, up), dot(p, to_camera)};
        x0 = std::min(x0, screen[i].x), x1 = std::max(x1, screen[i].x);
        y0 = std::min(y0, screen[i].y), y1 = std::max(y1, screen[i].y);
    }
    // Fit with a margin of 5 % on each side, centred.
    const double margin = 0.05;
    const double scale = std::min(W * (1 - 2 * margin) / std::max(x1 - x0, 1e-9),
                                  H * (1 - 2 * margin) / std::max(y1 - y0, 1e-9));
    const double cx = (x0 + x1) / 2, cy = (y0 + y1) / 2;
    for (V3& p : screen) p = {W / 2.0 + (p.x - cx) * scale, H / 2.0 - (p.y - cy) * scale, p.z};
    std::vector<double> depth(static_cast<size_t>(W) * H, -std::numeric_limits<double>::max());
    std::vector<float> shade(static_cast<size_t>(W) * H, -1.0f);
    for (const auto& t : triangles) {
        const V3 a = screen[t[0]], b = screen[t[1]], c = screen[t[2]];
        const double area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
        if (std::abs(area) < 1e-12) continue;
        const V3 n = unit(cross(sub({vertices[t[1]].x, vertices[t[1]].y, vertices[t[1]].z},
                                    {vertices[t[0]].x, vertices[t[0]].y, vertices[t[0]].z}),
                                sub({vertices[t[2]].x, vertices[t[2]].y, vertices[t[2]].z},
                                    {vertices[t[0]].x, vertices[t[0]].y, vertices[t[0]].z})));
        // Two-sided: a mesh facing inwards still draws.
        const float s = static_cast<float>(0.3 + 0.7 * std::abs(dot(n, light)));
        const int px0 = std::max(0, static_cast<int>(std::floor(std::min({a.x, b.x, c.x}))));
        const int px1 = std::min(W - 1, static_cast<int>(std::ceil(std::max({a.x, b.x, c.x}))));
        const int py0 = std::max(0, static_cast<int>(std::floor(std::min({a.y, b.y, c.y}))));
        const int py1 = std::min(H - 1, static_cast<int>(std::ceil(std::max({a.y, b.y, c.y}))));
        for (int py = py0; py <= py1; ++py)
            for (int px = px0; px <= px1; ++px) {
                const double x = px + 0.5, y = py + 0.5;
                const double w0 = ((b.x - x) * (c.y - y) - (b.y - y) * (c.x - x)) / area;
                const double w1 = ((c.x - x) * (a.y - y) - (c.y - y) * (a.x - x)) / area;
                const double w2 = 1 - w0 - w1;
                if (w0 < 0 || w1 < 0 || w2 < 0) continue;
                const double z = w0 * a.z + w1 * b.z + w2 * c.z;
                const size_t k = static_cast<size_t>(py) * W + px;
                if (z <= depth[k]) continue;
                depth[k] = z;
                shade[k] = s;
            }
    }
    // PrusaSlicer's orange, averaged over each pixel's samples; alpha is the covered share.
    const double base[3] = {237, 107, 33};
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            double sum = 0;
            int covered = 0;
            for (int sy = 0; sy < kSuper; ++sy)
                for (int sx = 0; sx < kSuper; ++sx) {
                    const float s =
                        shade[static_cast<size_t>(y * kSuper + sy) * W + (x * kSuper + sx)];
                    if (s >= 0) sum += s, ++covered;
                }
            uint8_t* px = &out[(static_cast<size_t>(y) * width + x) * 4];
            if (covered == 0) continue;
            const double s = sum / covered;
            for (int c = 0; c < 3; ++c)
                px[c] = static_cast<uint8_t>(std::clamp(std::lround(base[c] * s), 0L, 255L));
            px[3] = static_cast<uint8_t>(255 * covered / (kSuper * kSuper));
        }
    return out;
}

std::string encode_png_rgba(const std::vector<uint8_t>& rgba, int width, int height) {
    char* data = nullptr;
    size_t size = 0;
    FILE* mem = open_memstream(&data, &size);
    if (!mem) throw OutputError("cannot make a thumbnail: out of memory");
    // Level 9: the header's size, read by every host.
    const bool ok = write_png(mem, width, height, rgba.data(), PngFormat{4, 9, false});
    std::fclose(mem);
    std::string png(data ? data : "", data ? size : 0);
    std::free(data);
    if (!ok || png.empty()) throw OutputError("cannot encode a thumbnail as PNG");
    return png;
}

std::string base64(const std::string& bytes) {
    static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) |
                           (static_cast<unsigned char>(bytes[i + 1]) << 8) |
                           static_cast<unsigned char>(bytes[i + 2]);
        out += digits[v >> 18 & 63], out += digits[v >> 12 & 63];
        out += digits[v >> 6 & 63], out += digits[v & 63];
    }
    if (i < bytes.size()) {
        unsigned v = static_cast<unsigned char>(bytes[i]) << 16;
        if (i + 1 < bytes.size()) v |= static_cast<unsigned char>(bytes[i + 1]) << 8;
        out += digits[v >> 18 & 63], out += digits[v >> 12 & 63];
        out += i + 1 < bytes.size() ? digits[v >> 6 & 63] : '=';
        out += '=';
    }
    return out;
}

std::vector<std::string> thumbnail_blocks(const std::vector<Vec3>& vertices,
                                          const std::vector<std::array<uint32_t, 3>>& triangles,
                                          const std::vector<std::pair<int, int>>& sizes) {
    constexpr size_t kLine = 76;  // "; " and 76 characters: lines of 78 as PrusaSlicer's
    std::vector<std::string> out;
    for (const auto& [w, h] : sizes) {
        const std::string text =
            base64(encode_png_rgba(render_thumbnail(vertices, triangles, w, h), w, h));
        out.push_back(fmt::format("; thumbnail begin {}x{} {}", w, h, text.size()));
        for (size_t at = 0; at < text.size(); at += kLine)
            out.push_back("; " + text.substr(at, kLine));
        out.push_back("; thumbnail end");
        out.push_back(";");
    }
    return out;
}

}  // namespace carve

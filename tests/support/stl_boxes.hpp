// Synthetic meshes for the end-to-end tests: boxes and prisms as triangle lists, written as a
// binary STL into the test program's scratch folder (support/carve_run.hpp). Several boxes in
// one list may overlap: the slicer unites them.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "support/carve_run.hpp"

namespace carve::test {

using StlTriangle = std::array<std::array<float, 3>, 3>;

// Axis-aligned box [x0,x1]x[y0,y1]x[z0,z1], twelve triangles counter-clockwise from outside.
inline void add_box(std::vector<StlTriangle>& t, float x0, float y0, float z0, float x1, float y1,
                    float z1) {
    const std::array<std::array<float, 3>, 8> v{{{x0, y0, z0},
                                                 {x1, y0, z0},
                                                 {x1, y1, z0},
                                                 {x0, y1, z0},
                                                 {x0, y0, z1},
                                                 {x1, y0, z1},
                                                 {x1, y1, z1},
                                                 {x0, y1, z1}}};
    const int f[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                          {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
    for (const auto& k : f) t.push_back({v[k[0]], v[k[1]], v[k[2]]});
}

// A vertical prism over a regular n-gon (a cylinder for large n).
inline void add_cylinder(std::vector<StlTriangle>& t, float r, float h, int n) {
    auto at = [&](int i, float z) {
        const double a = 2 * std::numbers::pi * i / n;
        return std::array<float, 3>{float(r * std::cos(a)), float(r * std::sin(a)), z};
    };
    const std::array<float, 3> bottom{0, 0, 0}, top{0, 0, h};
    for (int i = 0; i < n; ++i) {
        t.push_back({bottom, at(i + 1, 0), at(i, 0)});
        t.push_back({top, at(i, h), at(i + 1, h)});
        t.push_back({at(i, 0), at(i + 1, 0), at(i + 1, h)});
        t.push_back({at(i, 0), at(i + 1, h), at(i, h)});
    }
}

// Binary STL (little-endian host assumed, as everywhere in this project's tests).
inline std::filesystem::path write_stl(const std::string& name,
                                       const std::vector<StlTriangle>& triangles) {
    const std::filesystem::path path = scratch() / name;
    std::ofstream out(path, std::ios::binary);
    char header[80] = {};
    out.write(header, 80);
    const auto n = static_cast<std::uint32_t>(triangles.size());
    out.write(reinterpret_cast<const char*>(&n), 4);
    for (const StlTriangle& t : triangles) {
        float f[12] = {};
        for (int v = 0; v < 3; ++v)
            for (int c = 0; c < 3; ++c) f[3 + 3 * v + c] = t[v][c];
        out.write(reinterpret_cast<const char*>(f), sizeof f);
        const std::uint16_t attribute = 0;
        out.write(reinterpret_cast<const char*>(&attribute), 2);
    }
    return path;
}

}  // namespace carve::test

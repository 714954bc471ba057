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

// A solid of revolution about the z axis: `profile` is (radius, z) from the centre of its bottom
// out and up to the centre of its top (the first and last radius 0), n sides around.
inline void add_revolution(std::vector<StlTriangle>& t,
                           const std::vector<std::array<float, 2>>& profile, int n) {
    auto at = [&](size_t k, int i) {
        const double a = 2 * std::numbers::pi * (i % n) / n;
        return std::array<float, 3>{float(profile[k][0] * std::cos(a)),
                                    float(profile[k][0] * std::sin(a)), profile[k][1]};
    };
    for (size_t k = 0; k + 1 < profile.size(); ++k)
        for (int i = 0; i < n; ++i) {
            if (profile[k][0] > 0) t.push_back({at(k, i), at(k, i + 1), at(k + 1, i + 1)});
            if (profile[k + 1][0] > 0) t.push_back({at(k, i), at(k + 1, i + 1), at(k + 1, i)});
        }
}

// A cone of base radius r and height h standing on z = 0.
inline void add_cone(std::vector<StlTriangle>& t, float r, float h, int n) {
    add_revolution(t, {{0, 0}, {r, 0}, {0, h}}, n);
}

// A ball of radius r centred at height c < r, cut flat at z = 0: a dome over a belly that faces
// down; `steps` profile points from the cut to the top.
inline void add_cut_ball(std::vector<StlTriangle>& t, float r, float c, int steps, int n) {
    std::vector<std::array<float, 2>> profile{{0, 0}};
    const double from = std::asin(-double(c) / r), to = std::numbers::pi / 2;
    for (int k = 0; k <= steps; ++k) {
        const double a = from + (to - from) * k / steps;
        profile.push_back({k == steps ? 0.0f : float(r * std::cos(a)), float(c + r * std::sin(a))});
    }
    add_revolution(t, profile, n);
}

// A prism along y from y0 to y1 over a convex polygon in the (x, z) plane, counter-clockwise
// with x to the right and z up.
inline void add_prism_xz(std::vector<StlTriangle>& t, const std::vector<std::array<float, 2>>& poly,
                         float y0, float y1) {
    auto at = [&](size_t i, float y) {
        return std::array<float, 3>{poly[i % poly.size()][0], y, poly[i % poly.size()][1]};
    };
    for (size_t i = 0; i < poly.size(); ++i) {
        t.push_back({at(i, y0), at(i + 1, y1), at(i + 1, y0)});
        t.push_back({at(i, y0), at(i, y1), at(i + 1, y1)});
    }
    for (size_t i = 1; i + 1 < poly.size(); ++i) {
        t.push_back({at(0, y0), at(i, y0), at(i + 1, y0)});
        t.push_back({at(0, y1), at(i + 1, y1), at(i, y1)});
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

// A 30 x 24 x 12 mm box, hollowed with a ceiling to hold: the part of the tests that check what
// carve writes around the print (start and end G-code, headers, thumbnails, options reaching the
// file) rather than how it carves a shape. It slices in a fifth of fandisk's time under the
// sanitizers (bench/results/ci_time.md), where those tests were most of the suite's time.
inline std::string small_part() {
    static const std::string path = [] {
        std::vector<StlTriangle> t;
        add_box(t, 0, 0, 0, 30, 24, 12);
        return write_stl("small_part.stl", t).string();
    }();
    return path;
}

}  // namespace carve::test

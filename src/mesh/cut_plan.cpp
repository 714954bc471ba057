// Where the cuts go (mesh/cut.hpp): the section's area from the crossed triangles alone, the
// connectors' places on an eroded section, and --cut auto's choice of planes (the fewest
// pieces that fit, then the least cut face).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "base/error.hpp"
#include "geometry/morphology.hpp"
#include "geometry/polygon.hpp"
#include "mesh/cut.hpp"
#include "mesh/cut_detail.hpp"

namespace carve {

namespace cut_detail {

namespace {

// The solid section at z as a region (empty off the mesh).
Paths section_region(const Mesh& mesh, double z) {
    z = off_vertices(mesh, z);
    const Crossing c = cross_at(mesh, z);
    Paths region;
    for (const std::vector<uint32_t>& loop : chain(c, z)) {
        Path p;
        for (uint32_t i : loop)
            p.push_back(Point{to_units(c.points[i].x), to_units(c.points[i].y)});
        region.push_back(std::move(p));
    }
    return unite(region);
}

double distance(const Point& a, const Point& b) {
    return std::hypot(double(a.X - b.X), double(a.Y - b.Y));
}

}  // namespace

std::vector<std::pair<double, double>> connector_sites(const Mesh& mesh, double z, double hole_r,
                                                       const ConnectorSpec& spec) {
    // A hole reaches depth below the face in the piece below and above it in the piece above:
    // it must stay inside the model all that way (sampled at the ends and half way).
    Paths region = section_region(mesh, z);
    for (double f : {-1.0, -0.5, 0.5, 1.0}) {
        if (region.empty()) break;
        region = intersect(region, section_region(mesh, z + f * spec.depth_mm));
    }
    const Paths room = erode(region, to_units(hole_r + spec.margin_mm));
    std::vector<std::pair<double, double>> sites;
    const double apart = to_units(2 * hole_r + spec.margin_mm);
    for (const Paths& island : components(room)) {
        std::vector<Point> points;
        for (const Path& p : island) points.insert(points.end(), p.begin(), p.end());
        if (points.empty()) continue;
        // Two points far apart: the farthest from any, then the farthest from that one.
        auto farthest = [&](const Point& from) {
            return *std::max_element(points.begin(), points.end(),
                                     [&](const Point& a, const Point& b) {
                                         return distance(from, a) < distance(from, b);
                                     });
        };
        const Point a = farthest(points.front());
        const Point b = farthest(a);
        sites.emplace_back(to_mm(a.X), to_mm(a.Y));
        if (spec.per_island > 1 && distance(a, b) >= apart)
            sites.emplace_back(to_mm(b.X), to_mm(b.Y));
    }
    return sites;
}

}  // namespace cut_detail

using namespace cut_detail;

double section_area_mm2(const Mesh& mesh, double z) {
    z = off_vertices(mesh, z);
    double twice = 0;
    for (const auto& t : mesh.triangles) {
        const int lone = lone_corner(mesh, t, z);
        if (lone < 0) continue;
        const uint32_t a = t[size_t(lone)], b = t[size_t(lone + 1) % 3],
                       c = t[size_t(lone + 2) % 3];
        Vec3 p = edge_point(mesh, a, b, z), q = edge_point(mesh, c, a, z);
        if (mesh.vertices[a].z < z) std::swap(p, q);  // the cap below runs q -> p then
        twice += p.x * q.y - q.x * p.y;
    }
    return twice / 2;
}

namespace {

struct Box2 {
    double min_x = std::numeric_limits<double>::max(), min_y = min_x;
    double max_x = std::numeric_limits<double>::lowest(), max_y = max_x;
    void add(double x, double y) {
        min_x = std::min(min_x, x), max_x = std::max(max_x, x);
        min_y = std::min(min_y, y), max_y = std::max(max_y, y);
    }
    void add(const Box2& b) {
        if (b.min_x > b.max_x) return;
        add(b.min_x, b.min_y);
        add(b.max_x, b.max_y);
    }
    double w() const { return max_x - min_x; }
    double d() const { return max_y - min_y; }
};

// The extent in x and y of the mesh's part in each slab [bottom + k step, bottom + (k+1) step].
std::vector<Box2> slab_boxes(const Mesh& mesh, double bottom, double step, size_t slabs) {
    std::vector<Box2> boxes(slabs);
    for (const auto& t : mesh.triangles) {
        const Vec3 v[3] = {mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]};
        const double lo = std::min({v[0].z, v[1].z, v[2].z}),
                     hi = std::max({v[0].z, v[1].z, v[2].z});
        const size_t first = size_t(std::clamp((lo - bottom) / step, 0.0, double(slabs - 1)));
        const size_t last = size_t(std::clamp((hi - bottom) / step, 0.0, double(slabs - 1)));
        for (size_t k = first; k <= last; ++k) {
            // The triangle clipped to the slab: its corners inside and its edges' crossings.
            const double z0 = bottom + double(k) * step, z1 = z0 + step;
            for (int i = 0; i < 3; ++i) {
                const Vec3& a = v[i];
                const Vec3& b = v[(i + 1) % 3];
                if (a.z >= z0 && a.z <= z1) boxes[k].add(a.x, a.y);
                for (double zp : {z0, z1})
                    if ((a.z - zp) * (b.z - zp) < 0) {
                        const double f = (zp - a.z) / (b.z - a.z);
                        boxes[k].add(a.x + f * (b.x - a.x), a.y + f * (b.y - a.y));
                    }
            }
        }
    }
    return boxes;
}

}  // namespace

std::vector<double> plan_cuts(const Mesh& mesh, const CutLimits& limits,
                              const std::string& model_path) {
    const BBox3 box = bounding_box(mesh);
    const double height = box.max.z - box.min.z;
    const size_t slabs = std::max<size_t>(1, size_t(std::ceil(height / limits.step - 1e-9)));
    const std::vector<Box2> boxes = slab_boxes(mesh, box.min.z, limits.step, slabs);
    auto plane = [&](size_t k) {
        return k == slabs ? box.max.z : box.min.z + double(k) * limits.step;
    };
    auto fits = [&](const Box2& b) {
        return (b.w() <= limits.max_x && b.d() <= limits.max_y) ||
               (b.w() <= limits.max_y && b.d() <= limits.max_x);
    };
    for (size_t k = 0; k < slabs; ++k)
        if (!fits(boxes[k]))
            throw InputError(fmt::format(
                "{}: at {:.1f} to {:.1f} mm of its height the model is {:.1f} x {:.1f} mm, larger "
                "than the {:.0f} x {:.0f} mm of the bed a piece may take (the skirt's room left "
                "round it) whichever way it lies: no cut across z brings it onto the bed; scale "
                "it down or choose a larger --bed",
                model_path, plane(k) - box.min.z, plane(k + 1) - box.min.z, boxes[k].w(),
                boxes[k].d(), limits.max_x, limits.max_y));
    // Fewest pieces first, then the least cut face: best[k] ends a piece at plane k.
    constexpr double kInf = std::numeric_limits<double>::infinity();
    std::vector<int> pieces(slabs + 1, std::numeric_limits<int>::max());
    std::vector<double> face(slabs + 1, kInf);
    std::vector<size_t> from(slabs + 1, 0);
    std::vector<double> area(slabs + 1, -1);
    pieces[0] = 0;
    face[0] = 0;
    for (size_t j = 0; j < slabs; ++j) {
        if (pieces[j] == std::numeric_limits<int>::max()) continue;
        Box2 b;
        for (size_t k = j + 1; k <= slabs; ++k) {
            b.add(boxes[k - 1]);
            const double h = plane(k) - plane(j);
            if (h > limits.max_height + 1e-9 || !fits(b)) break;
            if (h < limits.min_height) continue;
            if (k < slabs && area[k] < 0) area[k] = std::abs(section_area_mm2(mesh, plane(k)));
            const int n = pieces[j] + 1;
            const double f = face[j] + (k < slabs ? area[k] : 0);
            if (n < pieces[k] || (n == pieces[k] && f < face[k])) {
                pieces[k] = n;
                face[k] = f;
                from[k] = j;
            }
        }
    }
    if (pieces[slabs] == std::numeric_limits<int>::max())
        throw InputError(fmt::format(
            "{}: no cut across z leaves every piece within {:.0f} mm of height and at least "
            "{:.1f} mm tall; choose a taller printer or scale the model down",
            model_path, limits.max_height, limits.min_height));
    std::vector<double> zs;
    for (size_t k = from[slabs]; k > 0; k = from[k]) zs.push_back(plane(k));
    std::reverse(zs.begin(), zs.end());
    return zs;
}

}  // namespace carve

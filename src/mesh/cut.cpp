// cut_across_z (mesh/cut.hpp): each plane splits the triangles it crosses into a triangle on
// one side and a quadrilateral on the other, both through the same two points on the crossed
// edges; the section's loops, chained by those points, are capped by an ear clipping that keeps
// every one of them, and each connector is a ring of the cap with a tube and an end disk.
#include "mesh/cut.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <unordered_map>

#include "base/error.hpp"
#include "mesh/cut_detail.hpp"
#include "mesh/triangulate.hpp"

namespace carve {

namespace cut_detail {

double off_vertices(const Mesh& mesh, double z) {
    // A plane through a vertex would cut an edge at its end: two loops would share a point.
    for (int tries = 0; tries < 1000; ++tries) {
        bool clear = true;
        for (const Vec3& v : mesh.vertices)
            if (std::abs(v.z - z) < 1e-7) {
                clear = false;
                break;
            }
        if (clear) return z;
        z += 3e-7;
    }
    return z;
}

Vec3 edge_point(const Mesh& mesh, uint32_t a, uint32_t b, double z) {
    if (a > b) std::swap(a, b);  // the same point from both triangles of the edge
    const Vec3& p = mesh.vertices[a];
    const Vec3& q = mesh.vertices[b];
    const double f = (z - p.z) / (q.z - p.z);
    return {p.x + f * (q.x - p.x), p.y + f * (q.y - p.y), z};
}

Crossing cross_at(const Mesh& mesh, double z) {
    Crossing c;
    auto point = [&](uint32_t a, uint32_t b) {
        const uint64_t key = (uint64_t(std::min(a, b)) << 32) | std::max(a, b);
        const auto [it, added] = c.point_of_edge.emplace(key, uint32_t(c.points.size()));
        if (added) {
            c.points.push_back(edge_point(mesh, a, b, z));
            c.next.push_back(kNoVertex);
        }
        return it->second;
    };
    for (const auto& t : mesh.triangles) {
        const int lone = lone_corner(mesh, t, z);
        if (lone < 0) continue;
        const uint32_t a = t[size_t(lone)], b = t[size_t(lone + 1) % 3],
                       cc = t[size_t(lone + 2) % 3];
        const uint32_t p = point(a, b), q = point(cc, a);
        // The cap of the piece below runs against the sides' edge between the two points.
        const bool below = mesh.vertices[a].z < z;
        const uint32_t from = below ? q : p, to = below ? p : q;
        if (c.next[from] != kNoVertex)
            throw InputError(
                fmt::format("the section at z = {:.3f} mm is not a closed curve: "
                            "the mesh is not a closed surface there",
                            z));
        c.next[from] = to;
    }
    return c;
}

int lone_corner(const Mesh& mesh, const std::array<uint32_t, 3>& t, double z) {
    const bool b0 = mesh.vertices[t[0]].z < z, b1 = mesh.vertices[t[1]].z < z,
               b2 = mesh.vertices[t[2]].z < z;
    if (b0 == b1 && b1 == b2) return -1;
    return b1 == b2 ? 0 : (b0 == b2 ? 1 : 2);
}

std::vector<std::vector<uint32_t>> chain(const Crossing& c, double z) {
    std::vector<std::vector<uint32_t>> loops;
    std::vector<char> seen(c.points.size(), 0);
    for (uint32_t s = 0; s < c.points.size(); ++s) {
        if (seen[s]) continue;
        std::vector<uint32_t> loop;
        for (uint32_t p = s; !seen[p]; p = c.next[p]) {
            if (c.next[p] == kNoVertex)
                throw InputError(fmt::format(
                    "the section at z = {:.3f} mm is not a closed curve: the mesh is open there",
                    z));
            seen[p] = 1;
            loop.push_back(p);
        }
        loops.push_back(std::move(loop));
    }
    return loops;
}

}  // namespace cut_detail

namespace {

using namespace cut_detail;

constexpr int kRing = 32;  // sides of a connector's circle

// A connector's circle in a cap: a hole (into the piece) or a pin (out of it), its far end
// at z_end.
struct Feature {
    double x = 0, y = 0, r = 0, z_end = 0;
};

double loop_area(const std::vector<XY>& loop) {
    double a = 0;
    for (size_t i = 0, j = loop.size() - 1; i < loop.size(); j = i++)
        a += loop[j].x * loop[i].y - loop[i].x * loop[j].y;
    return a / 2;
}

bool inside(const std::vector<XY>& loop, double x, double y) {
    bool in = false;
    for (size_t i = 0, j = loop.size() - 1; i < loop.size(); j = i++)
        if ((loop[i].y > y) != (loop[j].y > y) &&
            x < (loop[j].x - loop[i].x) * (y - loop[i].y) / (loop[j].y - loop[i].y) + loop[i].x)
            in = !in;
    return in;
}

// The cap of the piece below the plane (counter-clockwise from above) in ids: the crossing's
// points, then each feature's ring (clockwise from above, as a hole) from `ring_base` on.
struct Cap {
    std::vector<std::array<uint32_t, 3>> triangles;
    std::vector<std::vector<uint32_t>> rings;  // ids, in the direction the triangles run
    std::vector<Vec3> ring_points;             // coordinates of ids from ring_base
    uint32_t ring_base = 0;
};

Cap build_cap(const Crossing& c, const std::vector<std::vector<uint32_t>>& loops, double z,
              const std::vector<Feature>& features) {
    Cap cap;
    cap.ring_base = uint32_t(c.points.size());
    // A point in line with its neighbours is left out of the ear clipping (where it would make
    // a triangle of no area) and put back by splitting the triangle over its edge.
    std::unordered_map<uint64_t, std::vector<uint32_t>> left_out;
    std::vector<std::vector<XY>> outers, holes;
    for (const std::vector<uint32_t>& loop : loops) {
        std::vector<XY> ring;
        std::vector<size_t> at;  // where each kept point is in the loop
        const size_t n = loop.size();
        for (size_t i = 0; i < n; ++i) {
            const Vec3& a = c.points[loop[(i + n - 1) % n]];
            const Vec3& b = c.points[loop[i]];
            const Vec3& d = c.points[loop[(i + 1) % n]];
            const double turn = (b.x - a.x) * (d.y - a.y) - (b.y - a.y) * (d.x - a.x);
            if (n > 3 && std::abs(turn) < 1e-12) continue;
            ring.push_back({b.x, b.y, loop[i]});
            at.push_back(i);
        }
        if (ring.size() < 3) continue;  // a sliver of no area
        // The points left out between two kept ones, in order.
        for (size_t k = 0; k < ring.size(); ++k) {
            const uint32_t from = ring[k].id, to = ring[(k + 1) % ring.size()].id;
            std::vector<uint32_t> between;
            for (size_t i = (at[k] + 1) % n; loop[i] != to; i = (i + 1) % n)
                between.push_back(loop[i]);
            if (!between.empty()) left_out[(uint64_t(from) << 32) | to] = std::move(between);
        }
        (loop_area(ring) > 0 ? outers : holes).push_back(std::move(ring));
    }
    std::vector<std::vector<std::vector<XY>>> holes_of(outers.size());
    auto owner = [&](double x, double y) {
        int best = -1;
        for (size_t o = 0; o < outers.size(); ++o)
            if (inside(outers[o], x, y) &&
                (best < 0 || loop_area(outers[o]) < loop_area(outers[size_t(best)])))
                best = int(o);
        return best;
    };
    for (std::vector<XY>& h : holes) {
        const int o = owner(h[0].x, h[0].y);
        if (o < 0)
            throw InputError(
                fmt::format("the section at z = {:.3f} mm has a hole outside "
                            "every contour: the mesh crosses itself there",
                            z));
        holes_of[size_t(o)].push_back(std::move(h));
    }
    for (const Feature& f : features) {
        std::vector<XY> ring;
        std::vector<uint32_t> ids;
        for (int k = 0; k < kRing; ++k) {
            const double a = -2 * std::numbers::pi * k / kRing;
            const uint32_t id = cap.ring_base + uint32_t(cap.ring_points.size());
            cap.ring_points.push_back({f.x + f.r * std::cos(a), f.y + f.r * std::sin(a), z});
            ring.push_back({cap.ring_points.back().x, cap.ring_points.back().y, id});
            ids.push_back(id);
        }
        const int o = owner(f.x, f.y);
        if (o < 0) throw std::logic_error("a connector outside its cut face");
        holes_of[size_t(o)].push_back(std::move(ring));
        cap.rings.push_back(std::move(ids));
    }
    for (size_t o = 0; o < outers.size(); ++o) {
        std::vector<std::array<uint32_t, 3>> t;
        try {
            t = triangulate(outers[o], holes_of[o]);
        } catch (const std::runtime_error& e) {
            throw InputError(
                fmt::format("the section at z = {:.3f} mm cannot be capped: {}", z, e.what()));
        }
        cap.triangles.insert(cap.triangles.end(), t.begin(), t.end());
    }
    if (left_out.empty()) return cap;
    // Each triangle over edges that left points out: a fan from its centroid through them all.
    std::vector<std::array<uint32_t, 3>> fixed;
    auto point_of = [&](uint32_t id) {
        return id < cap.ring_base ? c.points[id] : cap.ring_points[id - cap.ring_base];
    };
    for (const auto& t : cap.triangles) {
        std::vector<uint32_t> around;
        for (int k = 0; k < 3; ++k) {
            around.push_back(t[size_t(k)]);
            const auto it = left_out.find((uint64_t(t[size_t(k)]) << 32) | t[size_t(k + 1) % 3]);
            if (it != left_out.end())
                around.insert(around.end(), it->second.begin(), it->second.end());
        }
        if (around.size() == 3) {
            fixed.push_back(t);
            continue;
        }
        const Vec3 a = point_of(t[0]), b = point_of(t[1]), d = point_of(t[2]);
        const uint32_t centre = cap.ring_base + uint32_t(cap.ring_points.size());
        cap.ring_points.push_back({(a.x + b.x + d.x) / 3, (a.y + b.y + d.y) / 3, z});
        for (size_t k = 0; k < around.size(); ++k)
            fixed.push_back({centre, around[k], around[(k + 1) % around.size()]});
    }
    cap.triangles = std::move(fixed);
    return cap;
}

// One side of the plane as a mesh of its own, its vertices added as they are used.
struct Side {
    Mesh mesh;
    std::vector<uint32_t> of_vertex, of_point, of_ring;
    uint32_t vertex(const Mesh& m, uint32_t v) {
        if (of_vertex[v] == kNoVertex) {
            of_vertex[v] = uint32_t(mesh.vertices.size());
            mesh.vertices.push_back(m.vertices[v]);
        }
        return of_vertex[v];
    }
    uint32_t point(const Crossing& c, uint32_t p) {
        if (of_point[p] == kNoVertex) {
            of_point[p] = uint32_t(mesh.vertices.size());
            mesh.vertices.push_back(c.points[p]);
        }
        return of_point[p];
    }
};

// The cap (flipped for the piece above) and its connectors' tubes and end disks.
void add_cap(Side& side, const Crossing& c, const Cap& cap, const std::vector<Feature>& features,
             bool above) {
    std::vector<uint32_t> ring_vertex(cap.ring_points.size());
    for (size_t k = 0; k < cap.ring_points.size(); ++k) {
        ring_vertex[k] = uint32_t(side.mesh.vertices.size());
        side.mesh.vertices.push_back(cap.ring_points[k]);
    }
    auto vertex = [&](uint32_t id) {
        return id < cap.ring_base ? side.point(c, id) : ring_vertex[id - cap.ring_base];
    };
    for (const auto& t : cap.triangles) {
        const uint32_t a = vertex(t[0]), b = vertex(t[1]), d = vertex(t[2]);
        side.mesh.triangles.push_back(above ? std::array<uint32_t, 3>{a, d, b}
                                            : std::array<uint32_t, 3>{a, b, d});
    }
    for (size_t f = 0; f < features.size(); ++f) {
        std::vector<uint32_t> ring;
        for (uint32_t id : cap.rings[f]) ring.push_back(vertex(id));
        if (above) std::reverse(ring.begin(), ring.end());
        // The tube runs against the cap along the ring, the end disk against the tube.
        std::vector<uint32_t> far(ring.size());
        for (size_t k = 0; k < ring.size(); ++k) {
            Vec3 p = side.mesh.vertices[ring[k]];
            p.z = features[f].z_end;
            far[k] = uint32_t(side.mesh.vertices.size());
            side.mesh.vertices.push_back(p);
        }
        const uint32_t centre = uint32_t(side.mesh.vertices.size());
        side.mesh.vertices.push_back({features[f].x, features[f].y, features[f].z_end});
        for (size_t k = 0; k < ring.size(); ++k) {
            const size_t l = (k + 1) % ring.size();
            side.mesh.triangles.push_back({ring[l], ring[k], far[k]});
            side.mesh.triangles.push_back({ring[l], far[k], far[l]});
            side.mesh.triangles.push_back({centre, far[l], far[k]});
        }
    }
}

std::pair<Mesh, Mesh> split(const Mesh& mesh, double z, const std::vector<Feature>& below_features,
                            const std::vector<Feature>& above_features) {
    const Crossing c = cross_at(mesh, z);
    const std::vector<std::vector<uint32_t>> loops = chain(c, z);
    Side sides[2];
    for (Side& s : sides) {
        s.of_vertex.assign(mesh.vertices.size(), kNoVertex);
        s.of_point.assign(c.points.size(), kNoVertex);
    }
    auto point = [&](uint32_t a, uint32_t b) {
        return c.point_of_edge.at((uint64_t(std::min(a, b)) << 32) | std::max(a, b));
    };
    for (const auto& t : mesh.triangles) {
        const int lone = lone_corner(mesh, t, z);
        if (lone < 0) {
            Side& s = sides[mesh.vertices[t[0]].z < z ? 0 : 1];
            s.mesh.triangles.push_back(
                {s.vertex(mesh, t[0]), s.vertex(mesh, t[1]), s.vertex(mesh, t[2])});
            continue;
        }
        const uint32_t a = t[size_t(lone)], b = t[size_t(lone + 1) % 3],
                       d = t[size_t(lone + 2) % 3];
        const uint32_t p = point(a, b), q = point(d, a);
        Side& one = sides[mesh.vertices[a].z < z ? 0 : 1];
        Side& two = sides[mesh.vertices[a].z < z ? 1 : 0];
        one.mesh.triangles.push_back({one.vertex(mesh, a), one.point(c, p), one.point(c, q)});
        const uint32_t pp = two.point(c, p), bb = two.vertex(mesh, b), dd = two.vertex(mesh, d),
                       qq = two.point(c, q);
        two.mesh.triangles.push_back({pp, bb, dd});
        two.mesh.triangles.push_back({pp, dd, qq});
    }
    add_cap(sides[0], c, build_cap(c, loops, z, below_features), below_features, false);
    add_cap(sides[1], c, build_cap(c, loops, z, above_features), above_features, true);
    return {std::move(sides[0].mesh), std::move(sides[1].mesh)};
}

// Every edge run once each way: closed, and oriented throughout.
bool closed(const Mesh& mesh) {
    std::unordered_map<uint64_t, int> edges;
    for (const auto& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) ++edges[(uint64_t(t[size_t(k)]) << 32) | t[size_t(k + 1) % 3]];
    for (const auto& [key, n] : edges) {
        const auto it = edges.find((key << 32) | (key >> 32));
        if (n != 1 || it == edges.end() || it->second != 1) return false;
    }
    return true;
}

}  // namespace

std::vector<MeshPiece> cut_across_z(const Mesh& mesh, std::vector<double> zs,
                                    const ConnectorSpec& spec) {
    std::sort(zs.begin(), zs.end());
    const BBox3 box = bounding_box(mesh);
    for (size_t k = 0; k < zs.size(); ++k) {
        if (!(zs[k] > box.min.z && zs[k] < box.max.z))
            throw InputError(
                fmt::format("a cut at z = {:.2f} mm misses the model (z {:.2f} to "
                            "{:.2f} mm)",
                            zs[k], box.min.z, box.max.z));
        if (k > 0 && zs[k] - zs[k - 1] < 1.0)
            throw InputError(fmt::format("cuts at z = {:.2f} and {:.2f} mm are closer than 1 mm",
                                         zs[k - 1], zs[k]));
    }
    std::vector<MeshPiece> pieces;
    MeshPiece rest;
    rest.mesh = mesh;
    rest.z_from = box.min.z;
    const double hole_r = spec.diameter_mm / 2 + spec.clearance_mm;
    // A ring of straight sides lies inside its circle: a hole's corners on the circle around
    // the hole's true size, a pin's inside its own.
    const double hole_ring = hole_r / std::cos(std::numbers::pi / kRing);
    const double pin_ring = spec.diameter_mm / 2;
    const double pin_height = spec.depth_mm - spec.clearance_mm;
    for (double z_given : zs) {
        const double z = off_vertices(rest.mesh, z_given);
        std::vector<Feature> below, above;
        std::vector<Connector> below_c, above_c;
        if (spec.kind != ConnectorKind::None)
            for (const auto& [x, y] : connector_sites(rest.mesh, z, hole_r, spec)) {
                const bool pin = spec.kind == ConnectorKind::Pin;
                below.push_back(
                    {x, y, pin ? pin_ring : hole_ring, pin ? z + pin_height : z - spec.depth_mm});
                above.push_back({x, y, hole_ring, z + spec.depth_mm});
                below_c.push_back({x, y, z, pin ? spec.diameter_mm : 2 * hole_r,
                                   pin ? pin_height : spec.depth_mm, pin});
                above_c.push_back({x, y, z, 2 * hole_r, spec.depth_mm, false, {0, 0, -1}});
            }
        auto [lower, upper] = split(rest.mesh, z, below, above);
        MeshPiece piece;
        piece.mesh = std::move(lower);
        piece.z_from = rest.z_from;
        piece.z_to = z_given;
        piece.connectors = std::move(rest.connectors);
        piece.connectors.insert(piece.connectors.end(), below_c.begin(), below_c.end());
        pieces.push_back(std::move(piece));
        rest.mesh = std::move(upper);
        rest.z_from = z_given;
        rest.connectors = std::move(above_c);
    }
    rest.z_to = box.max.z;
    pieces.push_back(std::move(rest));
    for (size_t k = 0; k < pieces.size(); ++k)
        if (!closed(pieces[k].mesh))
            throw InputError(
                fmt::format("piece {} of the cut (z {:.2f} to {:.2f} mm) is not "
                            "closed: the mesh crosses itself at a cut; try another "
                            "height",
                            k + 1, pieces[k].z_from, pieces[k].z_to));
    return pieces;
}

}  // namespace carve

// The candidate orientations of --orient auto: axis-aligned turns and the convex hull's largest
// faces laid on the bed (see orient.hpp).
#include "mesh/orient.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include "mesh/shells.hpp"

namespace carve {

namespace {

using shells::cross;
using shells::dot;
using shells::sub;

double norm(const Vec3& a) {
    return std::sqrt(dot(a, a));
}
Vec3 scaled(const Vec3& a, double s) {
    return {a.x * s, a.y * s, a.z * s};
}

// A facet of the hull under construction: its corners (counter-clockwise seen from outside),
// its plane and the points not yet on the hull that lie above it.
struct HullFacet {
    uint32_t v[3];
    Vec3 normal;  // unit, outward
    double offset = 0;
    double area = 0;
    bool alive = true;
    std::vector<uint32_t> outside;
};

class QuickHull {
  public:
    QuickHull(const std::vector<Vec3>& points, double eps) : p_(points), eps_(eps) {}

    // False when the points span no volume.
    bool build() {
        uint32_t s[4];
        if (!simplex(s)) return false;
        Vec3 centre{};
        for (uint32_t i : s)
            centre = {centre.x + p_[i].x / 4, centre.y + p_[i].y / 4, centre.z + p_[i].z / 4};
        const uint32_t tri[4][3] = {
            {s[0], s[1], s[2]}, {s[0], s[1], s[3]}, {s[0], s[2], s[3]}, {s[1], s[2], s[3]}};
        std::vector<size_t> made;
        for (const auto& t : tri) {
            HullFacet f = facet(t[0], t[1], t[2]);
            if (dot(f.normal, centre) - f.offset > 0) f = facet(t[0], t[2], t[1]);
            made.push_back(push(std::move(f)));
        }
        std::vector<uint32_t> all(p_.size());
        for (uint32_t i = 0; i < all.size(); ++i) all[i] = i;
        assign(all, made);
        while (!open_.empty()) {
            const size_t f = open_.back();
            open_.pop_back();
            if (facets_[f].alive && !facets_[f].outside.empty()) add_point(f);
            // A hull has fewer than twice as many facets as points: more means rounding has
            // broken it, and no hull face is proposed rather than a wrong one.
            if (facets_.size() > 4 * p_.size() + 64) return false;
        }
        return true;
    }
    const std::vector<HullFacet>& facets() const { return facets_; }

  private:
    HullFacet facet(uint32_t a, uint32_t b, uint32_t c) const {
        HullFacet f;
        f.v[0] = a, f.v[1] = b, f.v[2] = c;
        const Vec3 n = cross(sub(p_[b], p_[a]), sub(p_[c], p_[a]));
        const double len = norm(n);
        f.area = len / 2;
        f.normal = len > 0 ? scaled(n, 1 / len) : Vec3{0, 0, 1};
        f.offset = dot(f.normal, p_[a]);
        return f;
    }
    double height(const HullFacet& f, uint32_t i) const { return dot(f.normal, p_[i]) - f.offset; }

    bool simplex(uint32_t s[4]) const {
        // The farthest pair among the extremes along the axes, the point farthest from their
        // line, then the one farthest from the plane of the three.
        uint32_t ext[6] = {0, 0, 0, 0, 0, 0};
        for (uint32_t i = 0; i < p_.size(); ++i) {
            const double c[3] = {p_[i].x, p_[i].y, p_[i].z};
            for (int k = 0; k < 3; ++k) {
                const double lo[3] = {p_[ext[2 * k]].x, p_[ext[2 * k]].y, p_[ext[2 * k]].z};
                const double hi[3] = {p_[ext[2 * k + 1]].x, p_[ext[2 * k + 1]].y,
                                      p_[ext[2 * k + 1]].z};
                if (c[k] < lo[k]) ext[2 * k] = i;
                if (c[k] > hi[k]) ext[2 * k + 1] = i;
            }
        }
        double best = -1;
        for (uint32_t a : ext)
            for (uint32_t b : ext)
                if (const double d = norm(sub(p_[a], p_[b])); d > best)
                    best = d, s[0] = a, s[1] = b;
        if (best <= eps_) return false;
        const Vec3 dir = scaled(sub(p_[s[1]], p_[s[0]]), 1 / best);
        best = -1;
        for (uint32_t i = 0; i < p_.size(); ++i)
            if (const double d = norm(cross(sub(p_[i], p_[s[0]]), dir)); d > best)
                best = d, s[2] = i;
        if (best <= eps_) return false;
        const HullFacet f = facet(s[0], s[1], s[2]);
        best = -1;
        for (uint32_t i = 0; i < p_.size(); ++i)
            if (const double d = std::fabs(height(f, i)); d > best) best = d, s[3] = i;
        return best > eps_;
    }

    // Each point goes to the first of `to` it lies above; the others are inside the hull.
    void assign(const std::vector<uint32_t>& points, const std::vector<size_t>& to) {
        for (uint32_t i : points)
            for (size_t f : to)
                if (height(facets_[f], i) > eps_) {
                    facets_[f].outside.push_back(i);
                    break;
                }
        for (size_t f : to)
            if (!facets_[f].outside.empty()) open_.push_back(f);
    }

    // The rim of the patch `visible` (its facets marked dead): its edges whose twin lives.
    std::vector<std::pair<uint32_t, uint32_t>> rim(const std::vector<size_t>& visible) const {
        std::vector<std::pair<uint32_t, uint32_t>> out;
        for (size_t f : visible)
            for (int e = 0; e < 3; ++e) {
                const uint32_t a = facets_[f].v[e], b = facets_[f].v[(e + 1) % 3];
                const auto twin = edge_.find(key(b, a));
                if (twin != edge_.end() && facets_[twin->second].alive) out.push_back({a, b});
            }
        return out;
    }
    // True when `horizon` passes a vertex twice; then the living facets at that vertex no
    // lower than the eye's rounding join `visible` and `horizon` is walked again.
    bool horizon_pinched(std::vector<std::pair<uint32_t, uint32_t>>& horizon,
                         std::vector<size_t>& visible, uint32_t eye) {
        std::unordered_set<uint32_t> starts, pinched;
        for (const auto& [a, b] : horizon)
            if (!starts.insert(a).second) pinched.insert(a);
        if (pinched.empty()) return false;
        for (size_t f = 0; f < facets_.size(); ++f) {
            HullFacet& g = facets_[f];
            if (!g.alive || height(g, eye) < -eps_) continue;
            if (pinched.count(g.v[0]) || pinched.count(g.v[1]) || pinched.count(g.v[2])) {
                g.alive = false;
                visible.push_back(f);
            }
        }
        horizon = rim(visible);
        return true;
    }

    void add_point(size_t from) {
        uint32_t eye = facets_[from].outside.front();
        for (uint32_t i : facets_[from].outside)
            if (height(facets_[from], i) > height(facets_[from], eye)) eye = i;
        // The facets the eye sees, walked across their edges from the first so that they form
        // one patch whatever rounding says of facets elsewhere; its rim is the horizon.
        std::vector<size_t> visible{from};
        std::vector<std::pair<uint32_t, uint32_t>> horizon;
        facets_[from].alive = false;  // marks it visited; every visible facet dies anyway
        for (size_t k = 0; k < visible.size(); ++k) {
            const HullFacet& f = facets_[visible[k]];
            for (int e = 0; e < 3; ++e) {
                const uint32_t a = f.v[e], b = f.v[(e + 1) % 3];
                const auto twin = edge_.find(key(b, a));
                if (twin == edge_.end()) continue;  // already dead: inside the patch
                HullFacet& g = facets_[twin->second];
                if (!g.alive) continue;
                if (height(g, eye) > eps_) {
                    g.alive = false;
                    visible.push_back(twin->second);
                } else {
                    horizon.push_back({a, b});
                }
            }
        }
        // A horizon through one vertex twice is a patch pinched there: rounding called a facet
        // beside it hidden between two that see the eye (coplanar points, as a CAD part's flat
        // faces hold), and the new facets would share an edge three ways. The facets about that
        // vertex that are level with the eye within rounding join the patch; if it is still
        // pinched, the eye is dropped (the hull stays closed, a little smaller).
        // A new facet facing away from the one it replaces along its horizon edge is a sliver
        // turned inside out: the eye lies level with the hull there within rounding, and is
        // dropped too.
        bool drop = false;
        for (int round = 0; !drop && horizon_pinched(horizon, visible, eye); ++round)
            drop = round == 4;
        for (size_t k = 0; !drop && k < horizon.size(); ++k) {
            const auto [a, b] = horizon[k];
            drop = dot(facet(a, b, eye).normal, facets_[edge_.at(key(a, b))].normal) <= 0;
        }
        if (drop) {
            for (size_t f : visible) facets_[f].alive = true;
            std::erase(facets_[from].outside, eye);
            if (!facets_[from].outside.empty()) open_.push_back(from);
            return;
        }
        std::vector<uint32_t> orphans;
        for (size_t f : visible) {
            HullFacet& old = facets_[f];
            for (int e = 0; e < 3; ++e) edge_.erase(key(old.v[e], old.v[(e + 1) % 3]));
            orphans.insert(orphans.end(), old.outside.begin(), old.outside.end());
            old.outside.clear();
            old.outside.shrink_to_fit();
        }
        std::vector<size_t> made;
        for (const auto& [a, b] : horizon) made.push_back(push(facet(a, b, eye)));
        std::erase(orphans, eye);
        assign(orphans, made);
        compact();
    }

    // Dead facets dropped once they outnumber the living, so that the scans stay short.
    void compact() {
        size_t alive = 0;
        for (const HullFacet& f : facets_) alive += f.alive;
        if (facets_.size() < 64 || 2 * alive > facets_.size()) return;
        std::vector<size_t> renumber(facets_.size(), SIZE_MAX);
        std::vector<HullFacet> kept;
        for (size_t f = 0; f < facets_.size(); ++f)
            if (facets_[f].alive) renumber[f] = kept.size(), kept.push_back(std::move(facets_[f]));
        facets_ = std::move(kept);
        for (auto& [k, f] : edge_) f = renumber[f];
        std::vector<size_t> open;
        for (size_t f : open_)
            if (renumber[f] != SIZE_MAX) open.push_back(renumber[f]);
        open_ = std::move(open);
    }

    static uint64_t key(uint32_t a, uint32_t b) { return (uint64_t(a) << 32) | b; }
    // A living facet, its edges recorded so that its neighbours find it.
    size_t push(HullFacet f) {
        const size_t i = facets_.size();
        for (int e = 0; e < 3; ++e) edge_[key(f.v[e], f.v[(e + 1) % 3])] = i;
        facets_.push_back(std::move(f));
        return i;
    }

    const std::vector<Vec3>& p_;
    const double eps_;
    std::vector<HullFacet> facets_;
    std::vector<size_t> open_;
    std::unordered_map<uint64_t, size_t> edge_;  // directed edge -> the living facet it bounds
};

Rotation axis_angle(const Vec3& axis, double angle) {
    // Rodrigues' formula.
    const double c = std::cos(angle), s = std::sin(angle), t = 1 - c;
    const double x = axis.x, y = axis.y, z = axis.z;
    Rotation r;
    r.m = {{{t * x * x + c, t * x * y - s * z, t * x * z + s * y},
            {t * x * y + s * z, t * y * y + c, t * y * z - s * x},
            {t * x * z - s * y, t * y * z + s * x, t * z * z + c}}};
    return r;
}

}  // namespace

Vec3 Rotation::apply(const Vec3& v) const {
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
            m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
}

bool Rotation::identity() const {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (std::fabs(m[size_t(i)][size_t(j)] - (i == j ? 1.0 : 0.0)) > 1e-12) return false;
    return true;
}

double Rotation::angle_deg() const {
    const double c = std::clamp((m[0][0] + m[1][1] + m[2][2] - 1) / 2, -1.0, 1.0);
    return std::acos(c) * 180 / std::numbers::pi;
}

Vec3 Rotation::axis() const {
    const Vec3 a{m[2][1] - m[1][2], m[0][2] - m[2][0], m[1][0] - m[0][1]};
    if (const double len = norm(a); len > 1e-9) return scaled(a, 1 / len);
    if (angle_deg() < 1) return {0, 0, 1};
    // A half turn: the axis is the column of m + I of largest length.
    Vec3 best{0, 0, 1};
    double best_len = 0;
    for (int j = 0; j < 3; ++j) {
        const Vec3 col{m[0][size_t(j)] + (j == 0), m[1][size_t(j)] + (j == 1),
                       m[2][size_t(j)] + (j == 2)};
        if (const double len = norm(col); len > best_len)
            best_len = len, best = scaled(col, 1 / len);
    }
    return best;
}

Rotation lay_down(const Vec3& down) {
    const Vec3 bed{0, 0, -1};
    const Vec3 axis = cross(down, bed);
    const double s = norm(axis), c = dot(down, bed);
    if (s < 1e-12) return c > 0 ? Rotation{} : axis_angle({1, 0, 0}, std::numbers::pi);
    return axis_angle(scaled(axis, 1 / s), std::atan2(s, c));
}

Rotation compose(const Rotation& then, const Rotation& first) {
    Rotation r;
    for (size_t i = 0; i < 3; ++i)
        for (size_t j = 0; j < 3; ++j) {
            r.m[i][j] = 0;
            for (size_t k = 0; k < 3; ++k) r.m[i][j] += then.m[i][k] * first.m[k][j];
        }
    return r;
}

Rotation quarter_turn_z() {
    return axis_angle({0, 0, 1}, std::numbers::pi / 2);
}

std::vector<HullPlane> hull_planes(const std::vector<Vec3>& points) {
    if (points.size() < 4) return {};
    BBox3 box{points[0], points[0]};
    for (const Vec3& p : points) {
        box.min = {std::min(box.min.x, p.x), std::min(box.min.y, p.y), std::min(box.min.z, p.z)};
        box.max = {std::max(box.max.x, p.x), std::max(box.max.y, p.y), std::max(box.max.z, p.z)};
    }
    // Single-precision coordinates (STL) are good to about 1e-7 of the model's size.
    const double eps = 1e-6 * std::max({box.max.x - box.min.x, box.max.y - box.min.y,
                                        box.max.z - box.min.z, 1e-3});
    QuickHull hull(points, eps);
    if (!hull.build()) return {};
    std::vector<const HullFacet*> facets;
    for (const HullFacet& f : hull.facets())
        if (f.alive) facets.push_back(&f);
    std::sort(facets.begin(), facets.end(),
              [](const HullFacet* a, const HullFacet* b) { return a->area > b->area; });
    // On a convex hull one direction has one supporting plane: facets within a degree of one
    // another lie in (nearly) one plane, which a model stands on as a whole.
    const double same = std::cos(std::numbers::pi / 180);
    std::vector<HullPlane> planes;
    for (const HullFacet* f : facets) {
        auto it = std::find_if(planes.begin(), planes.end(),
                               [&](const HullPlane& p) { return dot(p.normal, f->normal) > same; });
        if (it == planes.end())
            planes.push_back({f->normal, f->area});
        else
            it->area_mm2 += f->area;
    }
    std::stable_sort(planes.begin(), planes.end(), [](const HullPlane& a, const HullPlane& b) {
        return a.area_mm2 > b.area_mm2;
    });
    return planes;
}

std::vector<OrientationCandidate> orientation_candidates(const Mesh& mesh, int hull_faces) {
    std::vector<OrientationCandidate> out;
    auto add = [&](std::string name, const Vec3& down) {
        for (const OrientationCandidate& c : out)
            if (dot(c.down, down) > std::cos(2 * std::numbers::pi / 180)) return;
        out.push_back({std::move(name), down, lay_down(down)});
    };
    add("as given", {0, 0, -1});
    add("x+180", {0, 0, 1});
    add("x+90", {0, -1, 0});
    add("x-90", {0, 1, 0});
    add("y+90", {1, 0, 0});
    add("y-90", {-1, 0, 0});
    const std::vector<HullPlane> planes = hull_planes(mesh.vertices);
    for (size_t k = 0; k < planes.size() && k < size_t(std::max(hull_faces, 0)); ++k)
        add("hull face " + std::to_string(k + 1), planes[k].normal);
    return out;
}

std::string describe(const OrientationCandidate& c) {
    // No "-0.000": a component that prints as zero is zero.
    auto tidy = [](double v) { return std::fabs(v) < 5e-4 ? 0.0 : v; };
    if (c.rotation.identity()) return c.name;
    const Vec3 a = c.rotation.axis();
    char text[96];
    std::snprintf(text, sizeof text, " (%.1f deg about %.3f,%.3f,%.3f)", c.rotation.angle_deg(),
                  tidy(a.x), tidy(a.y), tidy(a.z));
    return c.name + text;
}

void rotate_mesh(Mesh& mesh, const Rotation& r) {
    for (Vec3& v : mesh.vertices) v = r.apply(v);
}

}  // namespace carve

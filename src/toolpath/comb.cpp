// Combing: point location, segment tests and detours inside the comb region (see comb.hpp);
// which way a travel goes, given these answers, is comb_travel.cpp's.
//
// Boundary edges sit in a uniform grid; a segment query walks the cells the segment passes
// (Amanatides-Woo), so testing a travel costs the edges near it, not the whole layer. A blocked
// travel is replaced, for every boundary contour it crosses, by a walk along that contour the
// shorter way from the first to the last crossing (the part of the segment in between leaves
// the region into the hole or the outside that contour bounds, so the walk replaces all of it),
// and the walk is then pulled tight by skipping every waypoint the previous one can see.
#include "toolpath/comb.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/polygon.hpp"

namespace carve {

namespace {

// How far (units) waypoints are moved off the boundary into the region: a point exactly on an
// edge would make every segment from it "touch" the boundary.
constexpr double kNudge = 20.0;

long long cross(const Point& o, const Point& a, const Point& b) {
    return (a.X - o.X) * (b.Y - o.Y) - (a.Y - o.Y) * (b.X - o.X);
}

int sign(long long v) {
    return (v > 0) - (v < 0);
}

bool on_segment(const Point& p, const Point& q, const Point& r) {  // r collinear with p-q
    return std::min(p.X, q.X) <= r.X && r.X <= std::max(p.X, q.X) && std::min(p.Y, q.Y) <= r.Y &&
           r.Y <= std::max(p.Y, q.Y);
}

// Closed segments a-b and p-q share a point.
bool segments_meet(const Point& a, const Point& b, const Point& p, const Point& q) {
    const int o1 = sign(cross(a, b, p)), o2 = sign(cross(a, b, q));
    const int o3 = sign(cross(p, q, a)), o4 = sign(cross(p, q, b));
    if (o1 != o2 && o3 != o4) return true;
    if (o1 == 0 && on_segment(a, b, p)) return true;
    if (o2 == 0 && on_segment(a, b, q)) return true;
    if (o3 == 0 && on_segment(p, q, a)) return true;
    if (o4 == 0 && on_segment(p, q, b)) return true;
    return false;
}

// The point of edge u-v nearest p, and its squared distance from p.
struct Nearest {
    double x, y, d2;
};

Nearest nearest_on_edge(const Point& u, const Point& v, const Point& p) {
    const double ex = double(v.X - u.X), ey = double(v.Y - u.Y);
    const double l2 = ex * ex + ey * ey;
    double t = l2 > 0 ? (double(p.X - u.X) * ex + double(p.Y - u.Y) * ey) / l2 : 0;
    t = std::clamp(t, 0.0, 1.0);
    const double qx = double(u.X) + t * ex, qy = double(u.Y) + t * ey;
    return {qx, qy,
            (qx - double(p.X)) * (qx - double(p.X)) + (qy - double(p.Y)) * (qy - double(p.Y))};
}

}  // namespace

Comber::Comber(const Paths& region) {
    // Islands: an outer contour and the holes inside it. In a normalised region a hole lies in
    // the smallest outer contour that holds its first vertex.
    std::vector<int> outers;
    for (const Path& p : region) {
        if (p.size() < 3) continue;
        Contour c;
        c.pts = p;
        double a = 0;
        for (size_t i = 0; i < p.size(); ++i)
            a += double(cross(Point(0, 0), p[i], p[(i + 1) % p.size()]));
        if (a == 0) continue;
        c.hole = a < 0;
        c.arc.resize(p.size());
        for (size_t i = 0; i < p.size(); ++i) {
            c.arc[i] = c.length;
            c.length += distance(p[i], p[(i + 1) % p.size()]);
        }
        if (!c.hole) outers.push_back(int(contours_.size()));
        contours_.push_back(std::move(c));
    }
    if (contours_.empty()) return;
    auto contains = [&](const Path& poly, const Point& pt) {
        bool in = false;
        for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
            const Point& u = poly[i];
            const Point& v = poly[j];
            if ((u.Y > pt.Y) != (v.Y > pt.Y)) {
                const double x =
                    double(u.X) + double(pt.Y - u.Y) * double(v.X - u.X) / double(v.Y - u.Y);
                if (x > double(pt.X)) in = !in;
            }
        }
        return in;
    };
    std::vector<double> outer_area(contours_.size(), 0);
    for (int o : outers) {
        const Path& p = contours_[o].pts;
        double a = 0;
        for (size_t i = 0; i < p.size(); ++i)
            a += double(cross(Point(0, 0), p[i], p[(i + 1) % p.size()]));
        outer_area[o] = a;
        contours_[o].island = o;
    }
    // Boxes first: a hole can only lie in an outer contour whose box holds its first vertex.
    std::vector<BBox2> box(contours_.size());
    for (size_t k = 0; k < contours_.size(); ++k) {
        BBox2& b = box[k];
        b.min_x = b.max_x = contours_[k].pts[0].X;
        b.min_y = b.max_y = contours_[k].pts[0].Y;
        for (const Point& q : contours_[k].pts) {
            b.min_x = std::min(b.min_x, q.X), b.max_x = std::max(b.max_x, q.X);
            b.min_y = std::min(b.min_y, q.Y), b.max_y = std::max(b.max_y, q.Y);
        }
    }
    for (Contour& c : contours_) {
        if (!c.hole) continue;
        int best = -1;
        const Point& v = c.pts.front();
        for (int o : outers) {
            const BBox2& b = box[o];
            if (v.X < b.min_x || v.X > b.max_x || v.Y < b.min_y || v.Y > b.max_y) continue;
            if ((best < 0 || outer_area[o] < outer_area[best]) && contains(contours_[o].pts, v))
                best = o;
        }
        c.island = best;  // -1: a stray hole, an obstacle of no island
    }
    // Island ids 0..n-1 in the order of their outer contours.
    std::vector<int> id(contours_.size(), -1);
    for (size_t k = 0; k < outers.size(); ++k) id[outers[k]] = int(k);
    islands_ = int(outers.size());
    for (Contour& c : contours_) c.island = c.island >= 0 ? id[c.island] : -1;
    island_contours_.resize(outers.size());
    for (size_t k = 0; k < contours_.size(); ++k)
        if (contours_[k].island >= 0) island_contours_[contours_[k].island].push_back(int(k));
    island_box_.resize(outers.size());
    for (size_t k = 0; k < outers.size(); ++k) island_box_[k] = box[outers[k]];

    // The grid: a few edges per cell.
    double min_x = std::numeric_limits<double>::max(), min_y = min_x;
    double max_x = std::numeric_limits<double>::lowest(), max_y = max_x;
    for (size_t c = 0; c < contours_.size(); ++c)
        for (size_t i = 0; i < contours_[c].pts.size(); ++i) {
            const Point& p = contours_[c].pts[i];
            min_x = std::min(min_x, double(p.X)), max_x = std::max(max_x, double(p.X));
            min_y = std::min(min_y, double(p.Y)), max_y = std::max(max_y, double(p.Y));
            edges_.emplace_back(int(c), int(i));
        }
    const double w = max_x - min_x + 1, h = max_y - min_y + 1;
    cell_ = std::max(50.0, std::sqrt(w * h / double(edges_.size())) * 1.5);
    x0_ = min_x, y0_ = min_y;
    nx_ = int(w / cell_) + 1, ny_ = int(h / cell_) + 1;
    cells_.resize(size_t(nx_) * size_t(ny_));
    stamp_.assign(edges_.size(), 0);
    for (size_t e = 0; e < edges_.size(); ++e) {
        const Path& p = contours_[edges_[e].first].pts;
        const Point& u = p[edges_[e].second];
        const Point& v = p[(edges_[e].second + 1) % p.size()];
        const int cx0 = int((double(std::min(u.X, v.X)) - x0_) / cell_);
        const int cx1 = int((double(std::max(u.X, v.X)) - x0_) / cell_);
        const int cy0 = int((double(std::min(u.Y, v.Y)) - y0_) / cell_);
        const int cy1 = int((double(std::max(u.Y, v.Y)) - y0_) / cell_);
        for (int y = cy0; y <= cy1; ++y)
            for (int x = cx0; x <= cx1; ++x) cells_[size_t(y) * nx_ + x].push_back(int(e));
    }
}

template <class F>
bool Comber::for_edges_along(const Point& a, const Point& b, F&& f) const {
    if (++query_ == 0) {
        std::fill(stamp_.begin(), stamp_.end(), 0u);
        query_ = 1;
    }
    // The segment in grid coordinates, clipped to the grid's box (Liang-Barsky).
    double ax = (double(a.X) - x0_) / cell_, ay = (double(a.Y) - y0_) / cell_;
    double bx = (double(b.X) - x0_) / cell_, by = (double(b.Y) - y0_) / cell_;
    const double dx = bx - ax, dy = by - ay;
    double t0 = 0, t1 = 1;
    auto clip = [&](double p, double q) {
        if (p == 0) return q >= 0;
        const double r = q / p;
        if (p < 0) {
            if (r > t1) return false;
            t0 = std::max(t0, r);
        } else {
            if (r < t0) return false;
            t1 = std::min(t1, r);
        }
        return true;
    };
    if (!clip(-dx, ax) || !clip(dx, double(nx_) - ax) || !clip(-dy, ay) ||
        !clip(dy, double(ny_) - ay))
        return false;
    const double sx = ax + t0 * dx, sy = ay + t0 * dy;
    const double ex = ax + t1 * dx, ey = ay + t1 * dy;
    auto cell_of = [](double v, int n) { return std::clamp(int(std::floor(v)), 0, n - 1); };
    int cx = cell_of(sx, nx_), cy = cell_of(sy, ny_);
    const int gx = cell_of(ex, nx_), gy = cell_of(ey, ny_);
    auto visit = [&](int x, int y) {
        if (x < 0 || y < 0 || x >= nx_ || y >= ny_) return false;
        for (int e : cells_[size_t(y) * nx_ + x]) {
            if (stamp_[e] == query_) continue;
            stamp_[e] = query_;
            if (f(e)) return true;
        }
        return false;
    };
    if (visit(cx, cy)) return true;
    const int step_x = dx > 0 ? 1 : -1, step_y = dy > 0 ? 1 : -1;
    const double inf = std::numeric_limits<double>::infinity();
    const double tdx = dx != 0 ? std::abs(1 / dx) : inf, tdy = dy != 0 ? std::abs(1 / dy) : inf;
    // Parameter (of the whole segment) where the walk crosses the next vertical / horizontal line.
    double tmx = dx != 0 ? ((dx > 0 ? std::floor(sx) + 1 - ax : ax - std::floor(sx)) * tdx) : inf;
    double tmy = dy != 0 ? ((dy > 0 ? std::floor(sy) + 1 - ay : ay - std::floor(sy)) * tdy) : inf;
    if (dx < 0 && sx == std::floor(sx) && t0 > 0) tmx = t0 + tdx;  // entered on a cell line
    if (dy < 0 && sy == std::floor(sy) && t0 > 0) tmy = t0 + tdy;
    for (int guard = 2 * (nx_ + ny_) + 4; (cx != gx || cy != gy) && guard > 0; --guard) {
        if (std::abs(tmx - tmy) < 1e-9) {
            // Through a cell corner: the two side cells too, in case rounding took the wrong one.
            if (visit(cx + step_x, cy) || visit(cx, cy + step_y)) return true;
            cx += step_x, cy += step_y, tmx += tdx, tmy += tdy;
        } else if (tmx < tmy) {
            cx += step_x, tmx += tdx;
        } else {
            cy += step_y, tmy += tdy;
        }
        if (visit(cx, cy)) return true;
        if (cx < 0 || cy < 0 || cx >= nx_ || cy >= ny_) break;
    }
    if (cx != gx || cy != gy) return visit(gx, gy);
    return false;
}

int Comber::island_of(const Point& p) const {
    if (contours_.empty()) return -1;
    const double gy = (double(p.Y) - y0_) / cell_;
    if (gy < 0 || gy >= ny_) return -1;
    // Crossings of a horizontal ray from p, counted per contour (odd: p is inside it); towards
    // the nearer side of the grid, which has fewer cells to walk.
    std::vector<int> odd;
    const double right_end = x0_ + cell_ * nx_;
    const bool rightwards = right_end - double(p.X) <= double(p.X) - x0_;
    const Point far(Coord(rightwards ? right_end + 10 : x0_ - 10), p.Y);
    for_edges_along(p, far, [&](int e) {
        const Path& c = contours_[edges_[e].first].pts;
        const Point& u = c[edges_[e].second];
        const Point& v = c[(edges_[e].second + 1) % c.size()];
        if ((u.Y > p.Y) != (v.Y > p.Y)) {
            const double x =
                double(u.X) + double(p.Y - u.Y) * double(v.X - u.X) / double(v.Y - u.Y);
            if (rightwards ? x > double(p.X) : x < double(p.X)) {
                auto it = std::find(odd.begin(), odd.end(), edges_[e].first);
                if (it == odd.end())
                    odd.push_back(edges_[e].first);
                else
                    odd.erase(it);
            }
        }
        return false;
    });
    int island = -1;
    for (int c : odd)
        if (!contours_[c].hole) {
            const int i = contours_[c].island;
            const bool in_hole = std::any_of(odd.begin(), odd.end(), [&](int h) {
                return contours_[h].hole && contours_[h].island == i;
            });
            if (!in_hole) island = i;
        }
    return island;
}

Point Comber::inside_edge_point(int contour, int edge, double x, double y) const {
    const Path& c = contours_[contour].pts;
    const Point& u = c[edge];
    const Point& v = c[(edge + 1) % c.size()];
    const double len = std::max(1.0, distance(u, v));
    // The region lies to the left of every edge (outer contours counter-clockwise, holes
    // clockwise).
    const double nx = -double(v.Y - u.Y) / len, ny = double(v.X - u.X) / len;
    return Point(Coord(std::llround(x + nx * kNudge)), Coord(std::llround(y + ny * kNudge)));
}

Point Comber::inside_vertex(int contour, int vertex) const {
    const Path& c = contours_[contour].pts;
    const size_t n = c.size();
    const Point& prev = c[(vertex + n - 1) % n];
    const Point& p = c[vertex];
    const Point& next = c[(vertex + 1) % n];
    auto left_normal = [](const Point& u, const Point& v, double& x, double& y) {
        const double len = std::max(1.0, distance(u, v));
        x = -double(v.Y - u.Y) / len, y = double(v.X - u.X) / len;
    };
    double ax, ay, bx, by;
    left_normal(prev, p, ax, ay);
    left_normal(p, next, bx, by);
    double mx = ax + bx, my = ay + by;
    const double m = std::hypot(mx, my);
    if (m < 1e-6) {
        mx = ax, my = ay;
    } else {
        mx /= m, my /= m;
    }
    // Along the bisector, far enough that both edges stay kNudge away (capped for spikes).
    const double c_half = std::max(0.3, mx * ax + my * ay);
    const double d = kNudge / c_half;
    return Point(Coord(std::llround(double(p.X) + mx * d)),
                 Coord(std::llround(double(p.Y) + my * d)));
}

std::optional<Comber::Located> Comber::locate(const Point& p, Coord reach) const {
    if (contours_.empty()) return std::nullopt;
    // A point inside but on the boundary (a cover line ending on the comb region's edge) is
    // moved off it too: every segment from it would touch the boundary.
    const int inside = island_of(p);
    reach = std::max<Coord>(reach, Coord(2 * kNudge));
    // The nearest boundary point within reach, from the cells of the box around p.
    const int cx0 = std::max(0, int((double(p.X - reach) - x0_) / cell_));
    const int cx1 = std::min(nx_ - 1, int((double(p.X + reach) - x0_) / cell_));
    const int cy0 = std::max(0, int((double(p.Y - reach) - y0_) / cell_));
    const int cy1 = std::min(ny_ - 1, int((double(p.Y + reach) - y0_) / cell_));
    if (cx0 > cx1 || cy0 > cy1 || double(p.X + reach) < x0_ || double(p.Y + reach) < y0_)
        return std::nullopt;
    double best = double(reach) * double(reach);
    int best_e = -1;
    double bx = 0, by = 0;
    for (int y = cy0; y <= cy1; ++y)
        for (int x = cx0; x <= cx1; ++x)
            for (int e : cells_[size_t(y) * nx_ + x]) {
                const Path& c = contours_[edges_[e].first].pts;
                const Nearest q =
                    nearest_on_edge(c[edges_[e].second], c[(edges_[e].second + 1) % c.size()], p);
                if (q.d2 < best) best = q.d2, best_e = e, bx = q.x, by = q.y;
            }
    if (best_e < 0 || (inside >= 0 && best >= kNudge * kNudge))
        return inside >= 0 ? std::optional<Located>(Located{p, inside}) : std::nullopt;
    const int c = edges_[best_e].first, i = edges_[best_e].second;
    for (const Point& q : {inside_edge_point(c, i, bx, by), inside_vertex(c, i),
                           inside_vertex(c, int((i + 1) % contours_[c].pts.size()))}) {
        if (distance(q, p) > double(reach) + 2 * kNudge) continue;
        // Strictly inside: a point moved along one edge's normal from a convex corner lies
        // on the other edge, and every segment from it would touch the boundary.
        if (const int k = island_of(q); k >= 0 && visible(q, q)) return Located{q, k};
    }
    return inside >= 0 ? std::optional<Located>(Located{p, inside}) : std::nullopt;
}

bool Comber::visible(const Point& a, const Point& b) const {
    if (contours_.empty()) return false;
    return !for_edges_along(a, b, [&](int e) {
        const Path& c = contours_[edges_[e].first].pts;
        return segments_meet(a, b, c[edges_[e].second], c[(edges_[e].second + 1) % c.size()]);
    });
}

std::vector<Comber::Hit> Comber::crossings(const Point& a, const Point& b) const {
    std::vector<Hit> hits;
    const double dx = double(b.X - a.X), dy = double(b.Y - a.Y);
    for_edges_along(a, b, [&](int e) {
        const int ci = edges_[e].first, vi = edges_[e].second;
        const Path& c = contours_[ci].pts;
        const Point& u = c[vi];
        const Point& v = c[(vi + 1) % c.size()];
        if (!segments_meet(a, b, u, v)) return false;
        const double ex = double(v.X - u.X), ey = double(v.Y - u.Y);
        const double den = dx * ey - dy * ex;
        double t = 0;
        if (den != 0) {
            t = (double(u.X - a.X) * ey - double(u.Y - a.Y) * ex) / den;
        } else {  // collinear overlap: the nearer end of the edge
            const double l2 = std::max(1.0, dx * dx + dy * dy);
            t = std::min((double(u.X - a.X) * dx + double(u.Y - a.Y) * dy) / l2,
                         (double(v.X - a.X) * dx + double(v.Y - a.Y) * dy) / l2);
        }
        t = std::clamp(t, 0.0, 1.0);
        hits.push_back(
            {t, ci, vi, inside_edge_point(ci, vi, double(a.X) + t * dx, double(a.Y) + t * dy)});
        return false;
    });
    std::sort(hits.begin(), hits.end(), [](const Hit& x, const Hit& y) { return x.t < y.t; });
    return hits;
}

std::optional<Path> Comber::route(const Point& a, const Point& b) const {
    if (visible(a, b)) return Path{b};
    const std::vector<Hit> hits = crossings(a, b);
    Path pts{a};
    for (size_t i = 0; i < hits.size();) {
        const Hit& h1 = hits[i];
        size_t j = i;
        for (size_t k = i + 1; k < hits.size(); ++k)
            if (hits[k].contour == h1.contour) j = k;
        if (j == i) {  // grazed a contour once: the pull below keeps the path clear of it
            ++i;
            continue;
        }
        const Hit& h2 = hits[j];
        const Contour& c = contours_[h1.contour];
        const int n = int(c.pts.size());
        auto pos = [&](const Hit& h) {
            const Point& u = c.pts[h.edge];
            return c.arc[h.edge] + distance(u, h.at);
        };
        const double p1 = pos(h1), p2 = pos(h2);
        double forward = p2 - p1;
        if (forward < 0) forward += c.length;
        pts.push_back(h1.at);
        if (forward <= c.length - forward) {
            int count = (h2.edge - h1.edge + n) % n;
            if (count == 0 && p2 < p1) count = n;
            for (int s = 1; s <= count; ++s)
                pts.push_back(inside_vertex(h1.contour, (h1.edge + s) % n));
        } else {
            int count = (h1.edge - h2.edge + n) % n;
            if (count == 0 && p2 > p1) count = n;
            for (int s = 0; s < count; ++s)
                pts.push_back(inside_vertex(h1.contour, (h1.edge - s + n) % n));
        }
        pts.push_back(h2.at);
        i = j + 1;
    }
    pts.push_back(b);
    // Pull tight: from each kept point, the furthest of the following ones it can see (the
    // last point first: most detours need one or two waypoints).
    Path out;
    for (size_t i = 0; i + 1 < pts.size();) {
        if (!visible(pts[i], pts[i + 1])) return std::nullopt;
        size_t j = i + 1;
        if (j + 1 < pts.size() && visible(pts[i], pts.back())) {
            j = pts.size() - 1;
        } else {
            while (j + 1 < pts.size() && visible(pts[i], pts[j + 1])) ++j;
        }
        out.push_back(pts[j]);
        i = j;
    }
    return out;
}

std::optional<Point> Comber::last_exit(const Point& a, const Point& b, int island) const {
    const std::vector<Hit> hits = crossings(a, b);
    for (size_t k = hits.size(); k-- > 0;)
        if (contours_[hits[k].contour].island == island) return hits[k].at;
    return std::nullopt;
}

std::optional<Point> Comber::first_entry(const Point& a, const Point& b, int island) const {
    for (const Hit& h : crossings(a, b))
        if (contours_[h.contour].island == island) return h.at;
    return std::nullopt;
}

std::optional<Point> Comber::nearest_in(const Point& p, int island) const {
    if (island < 0 || island >= islands_) return std::nullopt;
    double best = std::numeric_limits<double>::max();
    int bc = -1, be = -1;
    double bx = 0, by = 0;
    for (int c : island_contours_[island]) {
        const Path& pts = contours_[c].pts;
        for (size_t i = 0; i < pts.size(); ++i) {
            const Nearest q = nearest_on_edge(pts[i], pts[(i + 1) % pts.size()], p);
            if (q.d2 < best) best = q.d2, bc = c, be = int(i), bx = q.x, by = q.y;
        }
    }
    if (bc < 0) return std::nullopt;
    // The nearest of the candidates that lie strictly inside: where the nearest boundary point
    // is a corner, the point moved off the edge lies on the next edge, and the first vertex of
    // the edge may be its far end (a travel to the nearest island then crossed from the far
    // corner of a rectangle).
    std::optional<Point> best_q;
    double best_d = std::numeric_limits<double>::max();
    for (const Point& q : {inside_edge_point(bc, be, bx, by), inside_vertex(bc, be),
                           inside_vertex(bc, int((be + 1) % contours_[bc].pts.size()))})
        if (const double d = distance(q, p); d < best_d && island_of(q) == island && visible(q, q))
            best_q = q, best_d = d;
    return best_q;
}

Comber::Gap Comber::closest(int a, int b) const {
    if (a < 0 || b < 0 || a >= islands_ || b >= islands_ || a == b) return {};
    const size_t n = size_t(islands_);
    if (closest_.empty()) closest_.resize(n * n);
    std::optional<Gap>& known = closest_[size_t(a) * n + size_t(b)];
    if (!known) known = find_closest(a, b);
    return *known;
}

Comber::Gap Comber::find_closest(int a, int b) const {
    Gap g;
    const BBox2& p = island_box_[a];
    const BBox2& q = island_box_[b];
    const double dx = double(std::max({Coord(0), p.min_x - q.max_x, q.min_x - p.max_x}));
    const double dy = double(std::max({Coord(0), p.min_y - q.max_y, q.min_y - p.max_y}));
    if (std::hypot(dx, dy) > kFarGap) {
        g.d = std::hypot(dx, dy);
        return g;
    }
    // Between two polygons the nearest pair has a vertex of one at one end: every vertex of
    // each against every edge of the other.
    double best = std::numeric_limits<double>::max();
    for (int from : {a, b})
        for (int c : island_contours_[from])
            for (const Point& v : contours_[c].pts) {
                // A vertex further from the other island's box than the best pair so far has
                // nothing nearer in it: most vertices face away.
                const BBox2& o = island_box_[from == a ? b : a];
                const double vx = double(std::max({Coord(0), o.min_x - v.X, v.X - o.max_x}));
                const double vy = double(std::max({Coord(0), o.min_y - v.Y, v.Y - o.max_y}));
                if (vx * vx + vy * vy >= best) continue;
                for (int d : island_contours_[from == a ? b : a]) {
                    const Path& e = contours_[d].pts;
                    for (size_t i = 0; i < e.size(); ++i) {
                        const Nearest n = nearest_on_edge(e[i], e[(i + 1) % e.size()], v);
                        if (n.d2 >= best) continue;
                        best = n.d2;
                        const Point w(Coord(std::llround(n.x)), Coord(std::llround(n.y)));
                        g.on_a = from == a ? v : w;
                        g.on_b = from == a ? w : v;
                    }
                }
            }
    g.d = std::sqrt(best);
    return g;
}

std::vector<int> Comber::stepping_stones(int a, int b) const {
    // A plate of many parts: all the gaps and a search per travel would cost more than the
    // stepping stones save.
    constexpr int kMaxIslands = 64;
    if (a < 0 || b < 0 || a >= islands_ || b >= islands_ || a == b || islands_ > kMaxIslands)
        return {a, b};
    const size_t n = size_t(islands_);
    if (gaps_.empty()) {
        gaps_.assign(n * n, 0);
        for (size_t i = 0; i < n; ++i)
            for (size_t j = i + 1; j < n; ++j)
                gaps_[i * n + j] = gaps_[j * n + i] = gap(int(i), int(j));
    }
    // Dijkstra on the gaps (a few islands: the quadratic form).
    std::vector<double> dist(n, std::numeric_limits<double>::max());
    std::vector<int> prev(n, -1);
    std::vector<char> done(n, 0);
    dist[size_t(a)] = 0;
    for (size_t round = 0; round < n; ++round) {
        size_t u = n;
        for (size_t k = 0; k < n; ++k)
            if (!done[k] && (u == n || dist[k] < dist[u])) u = k;
        if (u == n || u == size_t(b)) break;
        done[u] = 1;
        for (size_t k = 0; k < n; ++k) {
            // A wide gap is never crossed for a stepping stone: kFarGap's boxes only bound it.
            const double g = gaps_[u * n + k];
            if (done[k] || (g > kFarGap && k != size_t(b))) continue;
            if (dist[u] + g < dist[k]) dist[k] = dist[u] + g, prev[k] = int(u);
        }
    }
    std::vector<int> path;
    for (int k = b; k >= 0; k = prev[size_t(k)]) path.push_back(k);
    if (path.back() != a) return {a, b};
    std::reverse(path.begin(), path.end());
    return path;
}

}  // namespace carve

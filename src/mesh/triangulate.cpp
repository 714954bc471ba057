// Ear clipping with holes bridged into the outer ring first (the scheme of mapbox's earcut,
// written for carve's needs): no point is ever dropped, since a cap that left out a boundary
// vertex would leave a crack in the cut piece. Quadratic in the vertices, which a cut's
// section (thousands of points) affords.
#include "mesh/triangulate.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <stdexcept>

namespace carve {

namespace {

struct Node {
    uint32_t id = 0;
    double x = 0, y = 0;
    Node* prev = nullptr;
    Node* next = nullptr;
};

double cross(const Node* a, const Node* b, const Node* c) {
    return (b->x - a->x) * (c->y - a->y) - (b->y - a->y) * (c->x - a->x);
}
double cross(double ax, double ay, double bx, double by, double cx, double cy) {
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
}
bool same_place(const Node* a, const Node* b) {
    return a->x == b->x && a->y == b->y;
}
// Inside or on the triangle, whichever way it turns.
bool in_triangle(double ax, double ay, double bx, double by, double cx, double cy, double px,
                 double py) {
    const double d1 = cross(px, py, ax, ay, bx, by), d2 = cross(px, py, bx, by, cx, cy),
                 d3 = cross(px, py, cx, cy, ax, ay);
    return (d1 >= 0 && d2 >= 0 && d3 >= 0) || (d1 <= 0 && d2 <= 0 && d3 <= 0);
}
int sign(double v) {
    return (v > 0) - (v < 0);
}
bool on_segment(const Node* p, const Node* q, const Node* r) {
    return q->x <= std::max(p->x, r->x) && q->x >= std::min(p->x, r->x) &&
           q->y <= std::max(p->y, r->y) && q->y >= std::min(p->y, r->y);
}
bool segments_cross(const Node* p1, const Node* q1, const Node* p2, const Node* q2) {
    const int o1 = sign(cross(p1, q1, p2)), o2 = sign(cross(p1, q1, q2));
    const int o3 = sign(cross(p2, q2, p1)), o4 = sign(cross(p2, q2, q1));
    if (o1 != o2 && o3 != o4) return true;
    if (o1 == 0 && on_segment(p1, p2, q1)) return true;
    if (o2 == 0 && on_segment(p1, q2, q1)) return true;
    if (o3 == 0 && on_segment(p2, p1, q2)) return true;
    if (o4 == 0 && on_segment(p2, q1, q2)) return true;
    return false;
}

class Earcut {
  public:
    std::vector<std::array<uint32_t, 3>> triangles;

    Node* ring(const std::vector<XY>& points) {
        Node* last = nullptr;
        for (const XY& p : points) {
            Node* n = &nodes_.emplace_back();
            n->id = p.id;
            n->x = p.x;
            n->y = p.y;
            if (!last) {
                n->prev = n->next = n;
            } else {
                n->next = last->next;
                n->prev = last;
                last->next->prev = n;
                last->next = n;
            }
            last = n;
        }
        return last ? last->next : nullptr;
    }

    Node* bridge_hole(Node* hole, Node* outer) {
        Node* bridge = hole_bridge(hole, outer);
        if (!bridge) throw std::runtime_error("a hole of the section lies outside its contour");
        Node* reverse = split(bridge, hole);
        filter(reverse);
        return filter(bridge);
    }

    // Removes a point on the spot of its successor, and one whose neighbours line up with it
    // (that one as a triangle of zero area, so that its edges keep their partners).
    Node* filter(Node* start) {
        if (!start) return start;
        Node* end = start;
        Node* p = start;
        bool again;
        do {
            again = false;
            if (p == p->next || p->next == p->prev) return p;
            if (same_place(p, p->next) && p->id == p->next->id) {
                remove(p);
                p = end = p->prev;
                again = true;
            } else if (cross(p->prev, p, p->next) == 0) {
                if (p->prev->id != p->next->id)
                    triangles.push_back({p->prev->id, p->id, p->next->id});
                remove(p);
                p = end = p->prev;
                again = true;
            } else {
                p = p->next;
            }
        } while (again || p != end);
        return end;
    }

    void clip(Node* ear, int pass) {
        if (!ear) return;
        Node* stop = ear;
        while (ear->prev != ear->next) {
            Node* prev = ear->prev;
            Node* next = ear->next;
            if (is_ear(ear)) {
                triangles.push_back({prev->id, ear->id, next->id});
                remove(ear);
                ear = next->next;
                stop = next->next;
                continue;
            }
            ear = next;
            if (ear == stop) {
                if (pass == 0)
                    clip(filter(ear), 1);
                else
                    split_and_clip(ear);
                return;
            }
        }
    }

  private:
    std::deque<Node> nodes_;

    static void remove(Node* p) {
        p->next->prev = p->prev;
        p->prev->next = p->next;
    }

    static bool is_ear(const Node* ear) {
        const Node* a = ear->prev;
        const Node* b = ear;
        const Node* c = ear->next;
        if (cross(a, b, c) <= 0) return false;  // reflex, or flat
        const double min_x = std::min({a->x, b->x, c->x}), max_x = std::max({a->x, b->x, c->x});
        const double min_y = std::min({a->y, b->y, c->y}), max_y = std::max({a->y, b->y, c->y});
        for (const Node* p = c->next; p != a; p = p->next) {
            if (p->x < min_x || p->x > max_x || p->y < min_y || p->y > max_y) continue;
            if (same_place(p, a) || same_place(p, b) || same_place(p, c)) continue;
            if (in_triangle(a->x, a->y, b->x, b->y, c->x, c->y, p->x, p->y) &&
                cross(p->prev, p, p->next) <= 0)
                return false;
        }
        return true;
    }

    static bool locally_inside(const Node* a, const Node* b) {
        if (cross(a->prev, a, a->next) > 0)
            return cross(a, a->next, b) >= 0 && cross(a, b, a->prev) >= 0;
        return cross(a, b, a->prev) > 0 || cross(a, a->next, b) > 0;
    }
    static bool middle_inside(const Node* a, const Node* b) {
        const double px = (a->x + b->x) / 2, py = (a->y + b->y) / 2;
        bool inside = false;
        const Node* p = a;
        do {
            const Node* q = p->next;
            if (((p->y > py) != (q->y > py)) && q->y != p->y &&
                px < (q->x - p->x) * (py - p->y) / (q->y - p->y) + p->x)
                inside = !inside;
            p = q;
        } while (p != a);
        return inside;
    }
    static bool crosses_ring(const Node* a, const Node* b) {
        const Node* p = a;
        do {
            const Node* q = p->next;
            if (p->id != a->id && q->id != a->id && p->id != b->id && q->id != b->id &&
                segments_cross(p, q, a, b))
                return true;
            p = q;
        } while (p != a);
        return false;
    }
    static bool valid_diagonal(const Node* a, const Node* b) {
        return a->next->id != b->id && a->prev->id != b->id && !crosses_ring(a, b) &&
               locally_inside(a, b) && locally_inside(b, a) && middle_inside(a, b);
    }

    // Joins a and b by two opposite edges: the ring splits in two, returned as b's copy.
    Node* split(Node* a, Node* b) {
        Node* a2 = &nodes_.emplace_back(*a);
        Node* b2 = &nodes_.emplace_back(*b);
        Node* an = a->next;
        Node* bp = b->prev;
        a->next = b;
        b->prev = a;
        a2->next = an;
        an->prev = a2;
        b2->next = a2;
        a2->prev = b2;
        bp->next = b2;
        b2->prev = bp;
        return b2;
    }

    void split_and_clip(Node* start) {
        Node* a = start;
        do {
            for (Node* b = a->next->next; b != a->prev; b = b->next)
                if (a->id != b->id && valid_diagonal(a, b)) {
                    Node* c = split(a, b);
                    a = filter(a);
                    c = filter(c);
                    clip(a, 0);
                    clip(c, 0);
                    return;
                }
            a = a->next;
        } while (a != start);
        throw std::runtime_error("the section's contours cross each other");
    }

    // The outer point the hole's leftmost point sees along a ray to the left (earcut's
    // findHoleBridge).
    static Node* hole_bridge(const Node* hole, Node* outer) {
        const double hx = hole->x, hy = hole->y;
        double qx = -std::numeric_limits<double>::infinity();
        Node* m = nullptr;
        Node* p = outer;
        do {
            if (hy <= p->y && hy >= p->next->y && p->next->y != p->y) {
                const double x = p->x + (hy - p->y) * (p->next->x - p->x) / (p->next->y - p->y);
                if (x <= hx && x > qx) {
                    qx = x;
                    m = p->x < p->next->x ? p : p->next;
                    if (x == hx) return m;
                }
            }
            p = p->next;
        } while (p != outer);
        if (!m) return nullptr;
        const Node* stop = m;
        const double mx = m->x, my = m->y;
        double best = std::numeric_limits<double>::infinity();
        p = m;
        do {
            if (hx >= p->x && p->x >= mx && hx != p->x &&
                in_triangle(hy < my ? hx : qx, hy, mx, my, hy < my ? qx : hx, hy, p->x, p->y)) {
                const double tan = std::abs(hy - p->y) / (hx - p->x);
                if (locally_inside(p, hole) && (tan < best || (tan == best && p->x > m->x))) {
                    m = p;
                    best = tan;
                }
            }
            p = p->next;
        } while (p != stop);
        return m;
    }
};

Node* leftmost(Node* start) {
    Node* best = start;
    for (Node* p = start->next; p != start; p = p->next)
        if (p->x < best->x || (p->x == best->x && p->y < best->y)) best = p;
    return best;
}

}  // namespace

std::vector<std::array<uint32_t, 3>> triangulate(const std::vector<XY>& outer,
                                                 const std::vector<std::vector<XY>>& holes) {
    Earcut e;
    if (outer.size() < 3) return {};
    Node* ring = e.ring(outer);
    std::vector<Node*> starts;
    for (const std::vector<XY>& h : holes) {
        if (h.size() < 3) continue;
        starts.push_back(leftmost(e.ring(h)));
    }
    std::sort(starts.begin(), starts.end(),
              [](const Node* a, const Node* b) { return a->x < b->x; });
    for (Node* h : starts) ring = e.bridge_hole(h, ring);
    e.clip(ring, 0);
    return std::move(e.triangles);
}

}  // namespace carve

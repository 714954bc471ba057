// Circle events of Boost.Polygon's segment Voronoi builder, computed where Boost's own fast
// formulas lose their accuracy on our contours (internal to the skeleton; tests check it
// against Boost's exact arithmetic).
//
// A circle event is the circle through/tangent to three sites (points or segments) whose
// rightmost point is when the beach line loses an arc. Boost computes it in doubles with an
// error estimate and, where the estimate fails, again in big integers. On the contours of a
// slice (arcs of the element's dilations; thin parts with nearly antiparallel sides) the
// estimate failed for most events, and the big-integer path was most of the Voronoi time.
#pragma once

#include <boost/polygon/voronoi.hpp>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <utility>

namespace carve::skel {

namespace bp = boost::polygon;

using BoostPredicates = bp::detail::voronoi_predicates<bp::detail::voronoi_ctype_traits<int32_t>>;

// Boost's circle formation functor with two changes, each falling back to Boost's own code
// (fast formula, then big integers) wherever it cannot vouch for its result:
//
// - Every PSS and SSS event is computed on its sites translated next to the origin (an exact
//   integer shift) and moved back. Boost's formulas take products of absolute coordinates, so
//   its error estimate grows with the distance from the origin over the circle's size.
// - PSS events whose point is an endpoint of one of the segments, and SSS events, are solved
//   by formulas that stay well conditioned across thin parts (below), in long double, with a
//   first-order bound on the rounding error. The circle is kept when the bound is within
//   kUlps (half of what Boost's fast path accepts); these are the same equations as Boost's,
//   whose solution is unique, so only the rounding differs.
//
// On cat's medial axes (1569 regions) the Voronoi time fell from 1.51 to 0.50 s, the axes
// unchanged; the exact path is left with the PSS events whose point is no segment's endpoint
// and with PPS events.
template <typename Site, typename Circle>
class LocalCircles {
    using F = long double;  // 64-bit significand with GCC on x86; where it is double, the
                            // bounds just pass less often
    static constexpr double kEps = 0x1p-53;  // unit roundoff of double
    static constexpr double kUlps = 32;      // accepted relative error; Boost's fast path: 64
    static constexpr F kWideEps = std::numeric_limits<F>::epsilon() / 2;
    // Whether an absolute error bound `err` (in units of kWideEps) keeps `value`, once rounded
    // to double, within kUlps of it.
    static bool within(F err, F value) {
        return err * kWideEps <= (kUlps - 1) * kEps * std::abs(value);
    }

  public:
    using Lazy = BoostPredicates::lazy_circle_formation_functor<Site, Circle>;

    void ppp(const Site& a, const Site& b, const Site& c, Circle& circle) {
        lazy_.ppp(a, b, c, circle);
    }
    void pps(const Site& a, const Site& b, const Site& c, int index, Circle& circle) {
        lazy_.pps(a, b, c, index, circle);
    }
    void pss(const Site& a, const Site& b, const Site& c, int index, Circle& circle) {
        Shift shift;
        if (!shift.fit({&a, &b, &c})) return lazy_.pss(a, b, c, index, circle);
        const Site a0 = shift(a), b0 = shift(b), c0 = shift(c);
        if (!at_endpoint(a0, b0, c0, circle)) lazy_.pss(a0, b0, c0, index, circle);
        shift.back(circle);
    }
    void sss(const Site& a, const Site& b, const Site& c, Circle& circle) {
        Shift shift;
        if (!shift.fit({&a, &b, &c})) return lazy_.sss(a, b, c, circle);
        const Site a0 = shift(a), b0 = shift(b), c0 = shift(c);
        if (!three_lines(a0, b0, c0, circle)) lazy_.sss(a0, b0, c0, circle);
        shift.back(circle);
    }

    // A PSS event (point, segment, segment, in Boost's order) whose point P is an endpoint of
    // one of the segments: on our contours most are, a contour vertex and the sides facing it
    // across the part. Boost's formula starts from where the two segments' lines cross, far
    // away for the nearly antiparallel sides of a thin part, and its terms cancel. Here the
    // bisector of P and its own (open) segment, direction v, is that segment's normal at P, so
    // C = P + mu (-vy, vx); and Boost's centre has equal signed distances to the two oriented
    // lines, mu |v| = (cross(w, P - Q) + mu v . w) / |w| with w, Q the other segment's
    // direction and start:  mu = cross(w, P - Q) / (|v| |w| - v . w).  The denominator has no
    // cancellation (for v . w > 0 it is computed as cross(v, w)^2 / (|v| |w| + v . w)).
    // Returns false, leaving `circle` alone, when it does not apply or cannot vouch for the
    // result; the sites should be near the origin but not at it (see Shift).
    static bool at_endpoint(const Site& point, const Site& s2, const Site& s3, Circle& circle) {
        const auto p = point.point0();
        const Site* on = &s2;
        const Site* other = &s3;
        if (p != s2.point0() && p != s2.point1()) {
            if (p != s3.point0() && p != s3.point1()) return false;
            std::swap(on, other);
        }
        const int64_t px = p.x(), py = p.y();
        const int64_t vx = int64_t(on->x1()) - on->x0(), vy = int64_t(on->y1()) - on->y0();
        const int64_t wx = int64_t(other->x1()) - other->x0();
        const int64_t wy = int64_t(other->y1()) - other->y0();
        const int64_t qx = px - other->x0(), qy = py - other->y0();
        constexpr int64_t kMax = int64_t(1) << 30;  // keeps every product below 2^61
        for (int64_t d : {vx, vy, wx, wy, qx, qy})
            if (d >= kMax || d <= -kMax) return false;
        const int64_t vv = vx * vx + vy * vy, ww = wx * wx + wy * wy;
        const int64_t dot = vx * wx + vy * wy;
        const F len_v = std::sqrt(F(vv));
        const F vw = len_v * std::sqrt(F(ww));  // 4 eps
        F den;                                  // |v| |w| - v . w
        F den_err;                              // its relative error, in eps
        if (dot <= 0) {
            den = vw - F(dot), den_err = 5;
        } else {
            const int64_t cross = vx * wy - vy * wx;
            if (cross == 0) return false;
            den = F(cross) * F(cross) / (vw + F(dot)), den_err = 9;
        }
        const F mu = F(wx * qy - wy * qx) / den;  // 2 + den_err eps
        const F ax = mu * F(vy), ay = mu * F(vx);
        const F x = F(px) - ax, y = F(py) + ay;
        const F r = std::abs(mu) * len_v;
        const F lower = x + r;
        // Absolute error bounds in units of kWideEps: each product carries mu's error plus one
        // rounding.
        const F e = den_err + 3;
        const F err_x = e * std::abs(ax) + std::abs(x);
        const F err_y = e * std::abs(ay) + std::abs(y);
        const F err_lower = err_x + (e + 2) * r + std::abs(lower);
        if (!(within(err_x, x) && within(err_y, y) && within(err_lower, lower))) return false;
        circle.x(double(x));
        circle.y(double(y));
        circle.lower_x(double(lower));
        return true;
    }

    // SSS events. Boost solves right_k(C) = R for the three oriented lines (right_k: signed
    // distance to the right of segment k) by Cramer's rule on the lines' equations, whose
    // constant terms are cross products of absolute coordinates: on the sides of a thin part
    // they cancel and the event was redone in big integers. The same system solved relative to
    // an endpoint O of the first segment, with unit right normals n_k and h_k = n_k . (Q_k - O)
    // for the nearer endpoint Q_k of segment k (h_1 = 0), is the 2 x 2 system
    //   (n_2 - n_1) . X = h_2,   (n_3 - n_1) . X = h_3,   C = O + X,   R = n_1 . X,
    // whose terms are all of the circle's own size. Each step's rounding is bounded (first
    // order, in units of kWideEps). Returns false, leaving `circle` alone, when the system is
    // nearly singular or the bound is not within kUlps.
    static bool three_lines(const Site& s1, const Site& s2, const Site& s3, Circle& circle) {
        struct V2 {
            F x, y;
        };
        const auto normal = [](const Site& s) {  // components within 3 (|n| = 1)
            const F dx = F(s.x1()) - s.x0(), dy = F(s.y1()) - s.y0();
            const F len = std::sqrt(dx * dx + dy * dy);
            return V2{dy / len, -dx / len};
        };
        const F ox = s1.x0(), oy = s1.y0();
        // h = n . (Q - O) with Q - O exact (|coordinates| < 2^31): within 5 (|qx| + |qy|).
        struct H {
            F value, err;
        };
        const auto offset = [&](const Site& s, const V2& n) {
            const F ax = s.x0() - ox, ay = s.y0() - oy, bx = s.x1() - ox, by = s.y1() - oy;
            const bool first = std::abs(ax) + std::abs(ay) <= std::abs(bx) + std::abs(by);
            const F qx = first ? ax : bx, qy = first ? ay : by;
            return H{n.x * qx + n.y * qy, 5 * (std::abs(qx) + std::abs(qy))};
        };
        const V2 n1 = normal(s1), n2 = normal(s2), n3 = normal(s3);
        const H h2 = offset(s2, n2), h3 = offset(s3, n3);
        const V2 u{n2.x - n1.x, n2.y - n1.y}, w{n3.x - n1.x, n3.y - n1.y};  // within 7 each
        constexpr F eu = 7;
        const F det = u.x * w.y - u.y * w.x;
        const F e_det = eu * (std::abs(u.x) + std::abs(u.y) + std::abs(w.x) + std::abs(w.y)) +
                        2 * (std::abs(u.x * w.y) + std::abs(u.y * w.x)) + 1;
        if (!(std::abs(det) > 64 * e_det * kWideEps)) return false;  // nearly singular, or NaN
        const F nx = h2.value * w.y - h3.value * u.y;
        const F ny = h3.value * u.x - h2.value * w.x;
        const F e_nx = h2.err * std::abs(w.y) + eu * std::abs(h2.value) + h3.err * std::abs(u.y) +
                       eu * std::abs(h3.value) +
                       2 * (std::abs(h2.value * w.y) + std::abs(h3.value * u.y));
        const F e_ny = h3.err * std::abs(u.x) + eu * std::abs(h3.value) + h2.err * std::abs(w.x) +
                       eu * std::abs(h2.value) +
                       2 * (std::abs(h3.value * u.x) + std::abs(h2.value * w.x));
        const F xx = nx / det, xy = ny / det;
        const F e_xx = (e_nx + std::abs(xx) * e_det) / std::abs(det) + std::abs(xx);
        const F e_xy = (e_ny + std::abs(xy) * e_det) / std::abs(det) + std::abs(xy);
        const F r = n1.x * xx + n1.y * xy;
        const F e_r = 3 * (std::abs(xx) + std::abs(xy)) + std::abs(n1.x) * e_xx +
                      std::abs(n1.y) * e_xy + 2 * (std::abs(n1.x * xx) + std::abs(n1.y * xy));
        if (!(r >= 0)) return false;
        const F x = ox + xx, y = oy + xy, lower = x + r;
        const F err_x = e_xx + std::abs(x), err_y = e_xy + std::abs(y);
        const F err_lower = err_x + e_r + std::abs(lower);
        if (!(within(err_x, x) && within(err_y, y) && within(err_lower, lower))) return false;
        circle.x(double(x));
        circle.y(double(y));
        circle.lower_x(double(lower));
        return true;
    }

  private:
    // Puts the sites' box at [span, 2 span] on both axes: near the origin, but with the centres
    // of the circles they make (near the sites) well away from the axes x = 0 and y = 0, where
    // the relative error of a centre coordinate would blow up.
    struct Shift {
        int64_t ox = 0, oy = 0;
        bool fit(std::initializer_list<const Site*> sites) {
            int64_t min_x = INT64_MAX, min_y = INT64_MAX, max_x = INT64_MIN, max_y = INT64_MIN;
            for (const Site* s : sites)
                for (const auto& p : {s->point0(), s->point1()}) {
                    min_x = std::min<int64_t>(min_x, p.x()),
                    max_x = std::max<int64_t>(max_x, p.x());
                    min_y = std::min<int64_t>(min_y, p.y()),
                    max_y = std::max<int64_t>(max_y, p.y());
                }
            const int64_t span = std::max(max_x - min_x, max_y - min_y) + 1;
            if (span > (int64_t(1) << 28)) return false;  // keep 2 span within int32
            ox = min_x - span, oy = min_y - span;
            return true;
        }
        Site operator()(const Site& s) const {
            return Site(int32_t(s.x0() - ox), int32_t(s.y0() - oy), int32_t(s.x1() - ox),
                        int32_t(s.y1() - oy));
        }
        void back(Circle& c) const {
            c.x(c.x() + double(ox));
            c.y(c.y() + double(oy));
            c.lower_x(c.lower_x() + double(ox));
        }
    };
    Lazy lazy_;
};

// Boost's predicates with LocalCircles for the circle events.
struct LocalPredicates : BoostPredicates {
    template <typename Site, typename Circle>
    using circle_formation_predicate = BoostPredicates::circle_formation_predicate<
        Site, Circle, BoostPredicates::circle_existence_predicate<Site>,
        LocalCircles<Site, Circle>>;
};

}  // namespace carve::skel

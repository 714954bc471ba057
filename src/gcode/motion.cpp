// Trapezoidal time estimate with junction deviation cornering (see motion.hpp).
#include "gcode/motion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace carve {

double trapezoid_time(double length, double v_entry, double v_nominal, double v_exit,
                      double accel) {
    if (length <= 0) return 0;
    if (v_nominal <= 0) return std::numeric_limits<double>::infinity();
    if (accel <= 0) return length / v_nominal;
    v_entry = std::min(v_entry, v_nominal);
    v_exit = std::min(v_exit, v_nominal);
    const double d_accel = (v_nominal * v_nominal - v_entry * v_entry) / (2 * accel);
    const double d_decel = (v_nominal * v_nominal - v_exit * v_exit) / (2 * accel);
    if (d_accel + d_decel <= length)
        return (v_nominal - v_entry) / accel + (v_nominal - v_exit) / accel +
               (length - d_accel - d_decel) / v_nominal;
    // Triangle: the peak speed is where the acceleration and deceleration ramps meet.
    const double peak =
        std::sqrt(std::max(0.0, (2 * accel * length + v_entry * v_entry + v_exit * v_exit) / 2));
    return std::max(0.0, (peak - v_entry) / accel) + std::max(0.0, (peak - v_exit) / accel);
}

void MotionPlanner::move(double dx, double dy, double speed, double accel, double e_per_mm) {
    const double len = std::hypot(dx, dy);
    if (len <= 0) return;
    const double ux = dx / len, uy = dy / len;
    // An axis limit caps the move along its direction: the axis's share of the move's speed or
    // acceleration may not exceed it.
    auto cap = [](double v, double axis_limit, double share) {
        return share > 1e-12 ? std::min(v, axis_limit / share) : v;
    };
    auto capped = [&](const MachineLimits& m) {
        return Capped{cap(cap(speed, m.feed_x, std::abs(ux)), m.feed_y, std::abs(uy)),
                      cap(cap(accel, m.accel_x, std::abs(ux)), m.accel_y, std::abs(uy))};
    };
    const Capped normal = capped(limits_);
    blocks_.push_back({len, ux, uy, e_per_mm, normal, dual_ ? capped(stealth_) : normal});
}

namespace {

// Marlin 2's acos of its JD_HANDLE_SMALL_SEGMENTS, a polynomial (planner.cpp: within 0.033 rad,
// and never below 0.033, so that a straight junction does not divide by 0): the angle between
// two directions whose cosine is t.
double marlin_acos(double t) {
    const double asinx =
        0.032843707 +
        t * (-1.451838349 +
             t * (29.66153956 +
                  t * (-131.1123477 + t * (262.8130562 + t * (-242.7199627 + t * 84.31466202)))));
    return std::numbers::pi / 2 - asinx;
}

}  // namespace

double MotionPlanner::junction_speed(const Block& p, const Block& q, bool stealth,
                                     bool small_segments) const {
    const MachineLimits& m = stealth ? stealth_ : limits_;
    const Capped& a = stealth ? p.stealth : p.normal;
    const Capped& b = stealth ? q.stealth : q.normal;
    double v = std::min(a.speed, b.speed);
    if (m.junction_deviation <= 0) {
        // Classic jerk: the change of each axis's speed at v stays within its jerk.
        const double cx = std::abs(p.ux - q.ux), cy = std::abs(p.uy - q.uy);
        if (cx > 1e-12) v = std::min(v, m.jerk_x / cx);
        if (cy > 1e-12) v = std::min(v, m.jerk_y / cy);
        return v;
    }
    const double cos_theta = -(p.ux * q.ux + p.uy * q.uy);
    if (cos_theta > 0.999999) return 0;  // reversal
    if (cos_theta > -0.999999) {
        const double sin_half = std::sqrt(0.5 * (1 - cos_theta));
        const double acc = std::min(a.accel, b.accel);
        v = std::min(v, std::sqrt(acc * m.junction_deviation * sin_half / (1 - sin_half)));
        // Marlin 2's JD_HANDLE_SMALL_SEGMENTS (on in its default Configuration.h): into a move
        // shorter than 1 mm turning by less than 45 degrees, the speed of a circle through it,
        // v^2 = a * length / angle.
        if (small_segments && q.length < 1 && cos_theta < -0.7071067812)
            v = std::min(v, std::sqrt(q.length * acc / marlin_acos(-cos_theta)));
    }
    return v;
}

double MotionPlanner::safe_speed(const Block& b, bool stealth) const {
    const MachineLimits& m = stealth ? stealth_ : limits_;
    if (m.junction_deviation > 0) return 0;
    double v = stealth ? b.stealth.speed : b.normal.speed;
    if (std::abs(b.ux) > 1e-12) v = std::min(v, m.jerk_x / std::abs(b.ux));
    if (std::abs(b.uy) > 1e-12) v = std::min(v, m.jerk_y / std::abs(b.uy));
    return v;
}

void MotionPlanner::stop() {
    const double t = plan(blocks_, false);
    done_ += t;
    done_stealth_ += dual_ ? plan(blocks_, true) : t;
    // The cooling's plan differs where the firmware's has more than the junction rule (Klipper's
    // lookahead, Marlin 2's small segments).
    const bool own = limits_.square_corner_velocity > 0 || limits_.junction_deviation > 0;
    done_cooling_ += own ? plan(blocks_, false, false) : t;
    blocks_.clear();
}

void MotionPlanner::dwell(double seconds, double cooling_seconds) {
    stop();
    done_ += seconds;
    done_stealth_ += seconds;
    done_cooling_ += cooling_seconds < 0 ? seconds : cooling_seconds;
}

double MotionPlanner::time() const {
    return done_ + plan(blocks_, false);
}

double MotionPlanner::time_stealth() const {
    return done_stealth_ + plan(blocks_, dual_);
}

double MotionPlanner::time_cooling() const {
    return done_cooling_ + plan(blocks_, false, false);
}

double MotionPlanner::plan(const std::vector<Block>& b, bool stealth, bool firmware) const {
    if (firmware && (stealth ? stealth_ : limits_).square_corner_velocity > 0)
        return plan_klipper(b, stealth);
    const size_t n = b.size();
    if (n == 0) return 0;
    auto accel = [&](size_t i) { return stealth ? b[i].stealth.accel : b[i].normal.accel; };
    // entry[i]: speed at the start of block i; entry[n] = 0 (rest at the end).
    std::vector<double> entry(n + 1, 0.0);
    entry[0] = safe_speed(b[0], stealth);
    entry[n] = safe_speed(b[n - 1], stealth);
    for (size_t i = 1; i < n; ++i) entry[i] = junction_speed(b[i - 1], b[i], stealth, firmware);
    // Backward: each block must be able to slow down to the next entry speed.
    for (size_t i = n; i-- > 0;)
        entry[i] =
            std::min(entry[i], std::sqrt(entry[i + 1] * entry[i + 1] + 2 * accel(i) * b[i].length));
    // Forward: and to reach its exit speed from its entry speed.
    for (size_t i = 0; i < n; ++i)
        entry[i + 1] =
            std::min(entry[i + 1], std::sqrt(entry[i] * entry[i] + 2 * accel(i) * b[i].length));
    double t = 0;
    for (size_t i = 0; i < n; ++i) {
        const Capped& c = stealth ? b[i].stealth : b[i].normal;
        t += trapezoid_time(b[i].length, entry[i], c.speed, entry[i + 1], c.accel);
    }
    return t;
}

// Klipper's LookAheadQueue.flush() over moves that start and end at rest, in squared speeds
// as toolhead.py has them; the junctions as its Move.calc_junction().
double MotionPlanner::plan_klipper(const std::vector<Block>& b, bool stealth) const {
    const MachineLimits& m = stealth ? stealth_ : limits_;
    const size_t n = b.size();
    if (n == 0) return 0;
    // Klipper's junction_deviation times the acceleration: the same for every move, whatever
    // M204 set.
    const double jd_accel =
        m.square_corner_velocity * m.square_corner_velocity * (std::sqrt(2.0) - 1);
    auto cap = [&](size_t i) -> const Capped& { return stealth ? b[i].stealth : b[i].normal; };
    std::vector<double> cruise_max(n), delta(n), mcr_delta(n), max_start(n, 0.0),
        max_mcr_start(n, 0.0);
    for (size_t i = 0; i < n; ++i) {
        cruise_max[i] = cap(i).speed * cap(i).speed;
        delta[i] = 2 * b[i].length * cap(i).accel;
        mcr_delta[i] = delta[i] * (1 - m.min_cruise_ratio);
    }
    for (size_t i = 1; i < n; ++i) {
        double v2 = std::min({cruise_max[i], cruise_max[i - 1], max_start[i - 1] + delta[i - 1]});
        // The extruder's own corner (extruder.py's calc_junction).
        const double de = std::abs(b[i].e_per_mm - b[i - 1].e_per_mm);
        if (de > 0 && m.extruder_corner_velocity > 0)
            v2 = std::min(v2, std::pow(m.extruder_corner_velocity / de, 2));
        const double cos_theta = -(b[i].ux * b[i - 1].ux + b[i].uy * b[i - 1].uy);
        const double sin_d2 = std::sqrt(std::max(0.5 * (1 - cos_theta), 0.0));
        const double cos_d2 = std::sqrt(std::max(0.5 * (1 + cos_theta), 0.0));
        if (1 - sin_d2 > 0 && cos_d2 > 0) {
            // The approximated circle touches both moves no further than their middles.
            const double quarter_tan = 0.25 * sin_d2 / cos_d2;
            v2 = std::min({v2, sin_d2 / (1 - sin_d2) * jd_accel, delta[i] * quarter_tan,
                           delta[i - 1] * quarter_tan});
        }
        max_start[i] = v2;
        max_mcr_start[i] = std::min(v2, max_mcr_start[i - 1] + mcr_delta[i - 1]);
    }
    // Backward: start speeds reachable from the rest at the end; each run of moves that
    // accelerate then decelerate cruises at most at the peak of the pseudo acceleration.
    std::vector<double> start(n), cruise(n, -1), next_start(n);
    double next_v2 = 0, next_mcr = 0, peak = 0;
    int pending = 0;
    for (size_t i = n; i-- > 0;) {
        const double reachable = next_v2 + delta[i];
        start[i] = std::min(max_start[i], reachable);
        next_start[i] = next_v2;
        ++pending;
        const double reach_mcr = next_mcr + mcr_delta[i];
        const double mcr_start = std::min(max_mcr_start[i], reach_mcr);
        if (mcr_start < reach_mcr) {
            if (mcr_start + mcr_delta[i] > next_mcr || pending > 1)
                peak = (mcr_start + reach_mcr) * 0.5;
            cruise[i] = std::min({(start[i] + reachable) * 0.5, cruise_max[i], peak});
            pending = 0;
        }
        next_v2 = start[i];
        next_mcr = mcr_start;
    }
    // Forward: a move that cannot accelerate keeps the cruise of the one before.
    double t = 0, prev_cruise = 0;
    for (size_t i = 0; i < n; ++i) {
        const double c = cruise[i] < 0 ? std::min(prev_cruise, start[i]) : cruise[i];
        t += trapezoid_time(b[i].length, std::sqrt(std::min(start[i], c)), std::sqrt(c),
                            std::sqrt(std::min(next_start[i], c)), cap(i).accel);
        prev_cruise = c;
    }
    return t;
}

}  // namespace carve

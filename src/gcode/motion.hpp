// Print time estimate from the moves (private to the G-code stage).
//
// Each move follows a trapezoidal speed profile: accelerate at the move's acceleration, cruise
// at its nominal speed, decelerate. Consecutive moves are joined at a junction speed given by
// the junction deviation rule (Marlin 2 and Klipper both derive their cornering speed from it):
//   v_j^2 = a * delta * sin(theta / 2) / (1 - sin(theta / 2)),
// theta being the angle between the reversed incoming and the outgoing direction (pi for a
// straight continuation, 0 for a reversal), capped by both moves' nominal speeds. A backward
// and a forward pass over the buffered moves make every entry speed reachable, as a firmware
// planner does. The buffer is emptied whenever the machine stops (retraction, Z move, end).
// With classic jerk instead (junction deviation 0, Prusa firmware), the junction speed is the
// highest at which no axis changes speed by more than its jerk, and a move may start or end at
// its axes' jerk ("safe speed"). With junction deviation, a move under 1 mm that turns by less
// than 45 degrees enters at most at the speed of the circle through it (Marlin 2's
// JD_HANDLE_SMALL_SEGMENTS); the cooling times its layers without that limit, as before it was
// modelled, so that no feed rate changes. The machine's axis limits (M201, M203) cap each move's
// acceleration and speed by its direction, as the firmware does.
// Klipper plans otherwise (its toolhead.py): a corner's speed is the smaller of its square corner
// velocity rule and a centripetal limit that shrinks with the moves' lengths, and its
// minimum_cruise_ratio caps each run of accelerating and decelerating moves at the peak that
// a pseudo acceleration of (1 - ratio) times the real one would reach, so that short moves
// (curves, infill) spend part of their length cruising, and a junction lets the extruder change
// speed by at most its instantaneous_corner_velocity. With square_corner_velocity set, the
// planner plans as Klipper does.
#pragma once

#include <limits>
#include <vector>

namespace carve {

// Marlin's default JUNCTION_DEVIATION_MM.
constexpr double kJunctionDeviationMm = 0.013;
// Klipper's defaults ([printer] square_corner_velocity, minimum_cruise_ratio), which its stock
// configs keep.
constexpr double kKlipperSquareCornerVelocity = 5.0;
constexpr double kKlipperMinCruiseRatio = 0.5;
// [extruder] instantaneous_corner_velocity: the extruder's speed change a junction allows.
constexpr double kKlipperExtruderCornerVelocity = 1.0;

// Time of a move of `length` that enters at v_entry, cruises at most at v_nominal and leaves at
// v_exit, with constant acceleration; the entry and exit speeds must be mutually reachable.
double trapezoid_time(double length, double v_entry, double v_nominal, double v_exit, double accel);

// The limits the planner obeys, as the G-code states them (M201 X Y, M203 X Y, M205).
struct MachineLimits {
    static constexpr double kNone = std::numeric_limits<double>::infinity();
    double accel_x = kNone, accel_y = kNone;           // mm/s^2
    double feed_x = kNone, feed_y = kNone;             // mm/s
    double jerk_x = 8, jerk_y = 8;                     // mm/s, with junction_deviation 0 only
    double junction_deviation = kJunctionDeviationMm;  // mm; 0 = classic jerk
    double square_corner_velocity = 0;                 // mm/s; > 0: Klipper's lookahead instead
    double min_cruise_ratio = 0;                       // Klipper's minimum_cruise_ratio, with it
    double extruder_corner_velocity = 0;               // mm/s of filament; with it too
    bool operator==(const MachineLimits&) const = default;
};

class MotionPlanner {
  public:
    explicit MotionPlanner(double junction_deviation_mm = kJunctionDeviationMm) {
        limits_.junction_deviation = junction_deviation_mm;
    }
    explicit MotionPlanner(const MachineLimits& limits) : limits_(limits) {}
    // With `stealth`, the same moves are also timed under a second set of limits (a Prusa
    // printer's stealth mode, M73 Q/S): time_stealth() and take_done_stealth(). Without it those
    // are the normal figures.
    MotionPlanner(const MachineLimits& limits, const MachineLimits& stealth)
        : limits_(limits), stealth_(stealth), dual_(true) {}

    // An XY move (mm) at nominal speed (mm/s) and acceleration (mm/s^2), extruding e_per_mm
    // of filament per mm (Klipper's junctions limit the extruder's change of speed).
    void move(double dx, double dy, double speed, double accel, double e_per_mm = 0);
    // The machine comes to rest: plans and times the buffered moves.
    void stop();
    // Time spent at rest (retractions, Z moves), after an implicit stop; the cooling's time
    // (time_cooling) takes cooling_seconds instead where given.
    void dwell(double seconds, double cooling_seconds = -1);
    // Total time so far, including the buffered moves (planned as if stopping after them).
    double time() const;
    // The time of the moves planned so far, which starts again from 0; the buffered moves stay
    // (their time depends on the moves still to come). The emitter takes it at each layer's
    // end, so that a layer's times do not depend on how long the print before it took.
    double take_done() {
        const double d = done_;
        done_ = done_cooling_ = 0;
        return d;
    }
    double time_stealth() const;
    // Total time so far as the junction deviation (or jerk) rule plans it, whatever the
    // firmware's model: the cooling times its layers by it, so that a Klipper model of the
    // estimate changes no feed rate the cooling chose before. take_done() starts it from 0
    // too, as time(): the same sums, to the last bit, as before that model.
    double time_cooling() const;
    // Taken with take_done(), at the same places.
    double take_done_stealth() {
        const double d = done_stealth_;
        done_stealth_ = 0;
        return d;
    }
    bool operator==(const MotionPlanner&) const = default;

  private:
    // A move's speed and acceleration as each mode's limits cap them.
    struct Capped {
        double speed, accel;
        bool operator==(const Capped&) const = default;
    };
    struct Block {
        double length, ux, uy, e_per_mm;
        Capped normal, stealth;
        bool operator==(const Block&) const = default;
    };
    double plan(const std::vector<Block>& blocks, bool stealth, bool firmware = true) const;
    double plan_klipper(const std::vector<Block>& blocks, bool stealth) const;
    // small_segments: Marlin 2's limit on short moves (the estimate's, not the cooling's).
    double junction_speed(const Block& p, const Block& q, bool stealth, bool small_segments) const;
    double safe_speed(const Block& b, bool stealth) const;  // entry from, or exit to, rest

    MachineLimits limits_, stealth_;
    bool dual_ = false;
    double done_ = 0, done_stealth_ = 0, done_cooling_ = 0;
    std::vector<Block> blocks_;
};

}  // namespace carve

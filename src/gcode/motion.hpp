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
#pragma once

#include <vector>

namespace carve {

// Marlin's default JUNCTION_DEVIATION_MM.
constexpr double kJunctionDeviationMm = 0.013;

// Time of a move of `length` that enters at v_entry, cruises at most at v_nominal and leaves at
// v_exit, with constant acceleration; the entry and exit speeds must be mutually reachable.
double trapezoid_time(double length, double v_entry, double v_nominal, double v_exit, double accel);

class MotionPlanner {
  public:
    explicit MotionPlanner(double junction_deviation_mm = kJunctionDeviationMm)
        : deviation_(junction_deviation_mm) {}

    // An XY move (mm) at nominal speed (mm/s) and acceleration (mm/s^2).
    void move(double dx, double dy, double speed, double accel);
    // The machine comes to rest: plans and times the buffered moves.
    void stop();
    // Time spent at rest (retractions, Z moves), after an implicit stop.
    void dwell(double seconds);
    // Total time so far, including the buffered moves (planned as if stopping after them).
    double time() const;

  private:
    struct Block {
        double length, ux, uy, speed, accel;
    };
    double plan(const std::vector<Block>& blocks) const;

    double deviation_;
    double done_ = 0;
    std::vector<Block> blocks_;
};

}  // namespace carve

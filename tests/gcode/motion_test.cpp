// The estimate's Klipper model (motion.hpp): the times of Klipper 84104bbb's own toolhead.py
// (LookAheadQueue.flush over Move objects, square_corner_velocity 5, minimum_cruise_ratio 0.5,
// the extruder's instantaneous_corner_velocity 1)
// for the same moves, and the cooling's times left as the junction deviation rule gives them;
// a retraction's time as Klipper and Marlin run a filament-only move.
#include "gcode/motion.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "config/settings.hpp"
#include "gcode/limits.hpp"

namespace carve {
namespace {

MachineLimits klipper_limits() {
    MachineLimits m;
    m.square_corner_velocity = kKlipperSquareCornerVelocity;
    m.min_cruise_ratio = kKlipperMinCruiseRatio;
    m.extruder_corner_velocity = kKlipperExtruderCornerVelocity;
    return m;
}

TEST(KlipperModel, ShortMoveCruisesAtThePseudoAccelerationsPeak) {
    // 10 mm at 200 mm/s, 1000 mm/s^2: the peak is sqrt(a * L / 2), not sqrt(a * L), and the
    // middle half of the move cruises there. Klipper: 0.212132034356 s.
    MotionPlanner k(klipper_limits());
    k.move(10, 0, 200, 1000);
    k.stop();
    EXPECT_NEAR(k.time(), 0.212132034356, 1e-9);
    MotionPlanner jd;
    jd.move(10, 0, 200, 1000);
    jd.stop();
    EXPECT_NEAR(jd.time(), 2 * std::sqrt(10000.0) / 1000, 1e-9);
}

TEST(KlipperModel, SquareCornerAtTheSquareCornerVelocity) {
    // Two 100 mm legs at 100 mm/s, 1000 mm/s^2, turning 90 degrees at 5 mm/s: 2.19025 s.
    MotionPlanner k(klipper_limits());
    k.move(100, 0, 100, 1000);
    k.move(0, 100, 100, 1000);
    EXPECT_NEAR(k.time(), 2.19025, 1e-9);
}

TEST(KlipperModel, CurvesAndInfillAsKlippersLookahead) {
    // Twice round a 40-gon of radius 10 at 150 mm/s then 30 mm straight on, 3000 mm/s^2;
    // a zigzag of 5 mm lines 0.4 mm apart at 100 mm/s. Klipper: 2.008293184584 s, 2.096236814991 s.
    MotionPlanner circle(klipper_limits()), zigzag(klipper_limits());
    for (int k = 0; k < 80; ++k) {
        const double a0 = 2 * std::numbers::pi * k / 40, a1 = 2 * std::numbers::pi * (k + 1) / 40;
        circle.move(10 * (std::cos(a1) - std::cos(a0)), 10 * (std::sin(a1) - std::sin(a0)), 150,
                    3000);
    }
    circle.move(0, 30, 150, 3000);
    for (int k = 0; k < 20; ++k) {
        zigzag.move(k % 2 == 0 ? 5 : -5, 0, 100, 3000);
        zigzag.move(0, 0.4, 100, 3000);
    }
    EXPECT_NEAR(circle.time(), 2.008293184584, 1e-9);
    EXPECT_NEAR(zigzag.time(), 2.096236814991, 1e-9);
}

TEST(KlipperModel, ExtruderCornerAtItsInstantaneousCornerVelocity) {
    // Straight on from a travel into a line of 0.05 mm of filament per mm: the extruder's
    // speed may jump by 1 mm/s, so the junction is 20 mm/s: 1.164 s. Widths changing within a
    // line (0.03, 0.04, then a corner): Klipper 0.195715910679 s.
    MotionPlanner k(klipper_limits()), widths(klipper_limits()), jd;
    k.move(50, 0, 100, 1000, 0);
    k.move(50, 0, 100, 1000, 0.05);
    EXPECT_NEAR(k.time(), 1.164, 1e-9);
    widths.move(5, 0, 100, 3000, 0.03);
    widths.move(5, 0, 100, 3000, 0.04);
    widths.move(5, 1, 100, 3000, 0.04);
    EXPECT_NEAR(widths.time(), 0.195715910679, 1e-9);
    // Marlin's planner has no such limit.
    jd.move(50, 0, 100, 1000, 0);
    jd.move(50, 0, 100, 1000, 0.05);
    EXPECT_NEAR(jd.time(), trapezoid_time(100, 0, 100, 0, 1000), 1e-9);
}

TEST(KlipperModel, CoolingKeepsTheJunctionDeviationTimes) {
    MotionPlanner k(klipper_limits()), jd;
    for (MotionPlanner* p : {&k, &jd}) {
        p->move(10, 0, 200, 1000);
        p->move(0, 10, 200, 1000);
        p->dwell(0.5);
        p->move(-10, 0, 200, 1000);
    }
    EXPECT_NEAR(k.time_cooling(), jd.time(), 1e-12);
    EXPECT_NEAR(jd.time_cooling(), jd.time(), 1e-12);
    EXPECT_GT(k.time(), jd.time() + 0.01);
}

// Marlin 2's JD_HANDLE_SMALL_SEGMENTS: twice round a 160-gon of radius 20 (0.785 mm chords,
// 2.25 degrees a corner) at 150 mm/s and 300 mm/s^2. The junction deviation alone lets the
// corners through at 142 mm/s; Marlin holds each to the circle's sqrt(a * length / angle), its
// angle from a polynomial within 0.033 rad (57 to 84 mm/s). The cooling keeps the old times.
TEST(MarlinModel, SmallSegmentsAtTheSpeedOfTheirCircle) {
    MotionPlanner p;
    for (int k = 0; k < 320; ++k) {
        const double a0 = 2 * std::numbers::pi * k / 160, a1 = 2 * std::numbers::pi * (k + 1) / 160;
        p.move(20 * (std::cos(a1) - std::cos(a0)), 20 * (std::sin(a1) - std::sin(a0)), 150, 300);
    }
    const double length = 320 * 2 * 20 * std::sin(std::numbers::pi / 160);
    EXPECT_GT(p.time(), length / 84);
    EXPECT_LT(p.time(), length / 57 + 2 * 84.0 / 300);
    EXPECT_LT(p.time_cooling(), length / 142 + 2 * 142.0 / 300);
    EXPECT_GT(p.time_cooling(), length / 142.5);
}

// A filament-only move on Klipper (the klipper preset's 0.8 mm at 35 mm/s; 5 mm at 40 mm/s) at
// extruder.py's max_extrude_only_accel, 3000 x 0.64 / 2.405 mm^2: Klipper 84104bbb's batch
// mode times them 0.063315110 s and 0.175110039 s, whatever M204 S is in force. Marlin with
// classic jerk (the ender3 preset) starts and ends it at the E jerk, at M204 R; with junction
// deviation from rest.
TEST(RetractTime, AsEachFirmwareRunsAFilamentOnlyMove) {
    Settings k;
    k.flavor = GcodeFlavor::Klipper;
    k.max_feedrate_x = 350, k.max_acceleration_x = 3000, k.acceleration = 500;
    k.retract_length = 0.8, k.retract_speed = 35;
    EXPECT_NEAR(retract_time(k), 0.063315110, 1e-8);
    k.retract_length = 5, k.retract_speed = 40;
    EXPECT_NEAR(retract_time(k), 0.175110039, 1e-8);
    Settings m;
    m.retract_length = 5, m.retract_speed = 40, m.retract_acceleration = 1000;
    m.max_jerk_e = 5, m.max_acceleration_e = 5000, m.max_feedrate_e = 60;
    m.junction_deviation = 0;
    EXPECT_NEAR(retract_time(m), 2 * 35.0 / 1000 + (5 - 2 * (40.0 * 40 - 25) / 2000) / 40, 1e-12);
    m.junction_deviation = 0.013;
    EXPECT_NEAR(retract_time(m), trapezoid_time(5, 0, 40, 0, 1000), 1e-12);
    m.max_feedrate_e = 20, m.max_acceleration_e = 300;  // M203 E and M201 E cap it
    EXPECT_NEAR(retract_time(m), trapezoid_time(5, 0, 20, 0, 300), 1e-12);
}

}  // namespace
}  // namespace carve

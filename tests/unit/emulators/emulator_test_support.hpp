// SPDX-License-Identifier: MIT
// Truth trajectories shared by the emulator tests.
#pragma once

#include <numbers>

#include "nav/emulators/truth.hpp"

namespace nav::emulators::testing {

/// At rest, level, heading start_yaw_rad, for ever: f_b = (0, 0, -g), omega_b = 0.
inline TruthTrajectory stationary_truth(double start_yaw_rad) {
  TrajectorySpec spec;
  spec.start_yaw_rad = start_yaw_rad;
  return *TruthTrajectory::build(spec);
}

/// 10 m straight at 1.2 m/s, then an arc of arc_rad on a 5 m radius, with a 6 s roll and
/// pitch motion of the given amplitudes: every gyro axis moves.
inline TruthTrajectory manoeuvring_truth(double start_yaw_rad, double arc_rad, double roll_rad,
                                         double pitch_rad) {
  TrajectorySpec spec;
  spec.start_yaw_rad = start_yaw_rad;
  spec.max_accel_mps2 = 0.3;
  Segment s1;
  s1.length_m = 10.0;
  s1.speed_mps = 1.2;
  Segment s2;
  s2.kind = Segment::Kind::kArc;
  s2.radius_m = 5.0;
  s2.angle_rad = arc_rad;
  s2.speed_mps = 1.2;
  spec.segments = {s1, s2};
  spec.motion.roll_amplitude_rad = roll_rad;
  spec.motion.pitch_amplitude_rad = pitch_rad;
  spec.motion.period_s = 6.0;
  return *TruthTrajectory::build(spec);
}

/// A surface run with a turn (1.5 m/s, starting at (-30, 12) m heading -100 deg): 20 m
/// straight, then a 270 deg arc of 15 m radius; the heading sweeps through every quadrant.
inline TruthTrajectory surface_turn_truth() {
  TrajectorySpec spec;
  spec.start_p_n = Vec3{-30.0, 12.0, 0.0};
  spec.start_yaw_rad = -100.0 * std::numbers::pi / 180.0;
  spec.max_accel_mps2 = 0.3;
  Segment s1;
  s1.length_m = 20.0;
  s1.speed_mps = 1.5;
  Segment s2;
  s2.kind = Segment::Kind::kArc;
  s2.radius_m = 15.0;
  s2.angle_rad = 270.0 * std::numbers::pi / 180.0;
  s2.speed_mps = 1.5;
  spec.segments = {s1, s2};
  return *TruthTrajectory::build(spec);
}

/// At 1 m/s: run_m at the surface, dive to 5 m at 0.5 m/s, run_m underwater, climb back,
/// final_run_m at the surface; speed changes limited to max_accel_mps2.
inline TruthTrajectory diving_truth(double run_m, double final_run_m, double max_accel_mps2) {
  TrajectorySpec spec;
  spec.max_accel_mps2 = max_accel_mps2;
  Segment run;
  run.length_m = run_m;
  run.speed_mps = 1.0;
  Segment down;
  down.kind = Segment::Kind::kDepth;
  down.depth_change_m = 5.0;
  down.depth_rate_mps = 0.5;
  down.speed_mps = 1.0;
  Segment up = down;
  up.depth_change_m = -5.0;
  Segment final_run = run;
  final_run.length_m = final_run_m;
  spec.segments = {run, down, run, up, final_run};
  return *TruthTrajectory::build(spec);
}

}  // namespace nav::emulators::testing

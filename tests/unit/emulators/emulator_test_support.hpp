// SPDX-License-Identifier: MIT
// Truth trajectories shared by the emulator tests.
#pragma once

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

}  // namespace nav::emulators::testing

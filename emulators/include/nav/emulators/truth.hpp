// SPDX-License-Identifier: MIT
// Truth trajectory generator: a vehicle following path segments with a speed profile.
//
// The horizontal path is a sequence of segments (straight, arc, turn in place, depth change).
// Speed changes between segments follow a quintic "smootherstep" ramp limited by the
// vehicle's acceleration; arcs blend their curvature in and out over a transition length so
// that the angular rate is continuous; turns in place and depth changes follow smootherstep
// profiles. An optional sinusoidal roll/pitch motion (sea state, sway) is superimposed.
// Position, velocity, attitude, angular rate and specific force are evaluated analytically
// (position by Gauss-Legendre quadrature of the analytic velocity), so they agree with each
// other: integrating omega_b and f_b reproduces the path (tests/unit/truth_test.cpp).
//
// Frames: n = NED at the datum (treated as inertial: no Earth rate, no transport rate),
// b = FRD. After the last segment the vehicle keeps its final heading, speed and depth rate 0.
#pragma once

#include <vector>

#include "nav/common/frames.hpp"
#include "nav/common/result.hpp"
#include "nav/common/time.hpp"

namespace nav::emulators {

/// One path segment. Which fields matter depends on the kind.
struct Segment {
  enum class Kind { kStraight, kArc, kTurn, kDepth };
  Kind kind = Kind::kStraight;
  double length_m = 0.0;        ///< straight/arc: path length [m]
  double speed_mps = 0.0;       ///< straight/arc/depth: horizontal speed to hold [m/s]
  double radius_m = 0.0;        ///< arc: radius [m] (> 0)
  double angle_rad = 0.0;       ///< arc/turn: heading change, + towards starboard [rad]
  double rate_radps = 0.0;      ///< turn: peak yaw rate [rad/s] (> 0)
  double depth_change_m = 0.0;  ///< depth: change, + deeper [m]
  double depth_rate_mps = 0.0;  ///< depth: peak vertical speed [m/s] (> 0)
};

/// Superimposed sinusoidal attitude motion (zero amplitude = none).
struct AttitudeMotion {
  double roll_amplitude_rad = 0.0;   ///< [rad]
  double pitch_amplitude_rad = 0.0;  ///< [rad]
  double period_s = 10.0;            ///< [s] (> 0)
};

/// Everything that defines a truth trajectory.
struct TrajectorySpec {
  Vec3 start_p_n = Vec3::Zero();   ///< start position, NED [m]
  double start_yaw_rad = 0.0;      ///< start heading [rad]
  double max_accel_mps2 = 0.2;     ///< speed ramps: peak longitudinal acceleration [m/s^2]
  double arc_transition_m = 1.0;   ///< arcs: curvature blend length at each end [m]
  double gravity_mps2 = 9.80665;   ///< gravity magnitude, down [m/s^2]
  std::vector<Segment> segments;
  AttitudeMotion motion;
};

/// Truth at one instant.
struct TruthSample {
  Duration t{};                    ///< scenario time [ns]
  Vec3 p_n = Vec3::Zero();         ///< position, NED [m]; depth = p_n.z()
  Vec3 v_n = Vec3::Zero();         ///< velocity, NED [m/s]
  Vec3 a_n = Vec3::Zero();         ///< acceleration, NED [m/s^2]
  Quat q_nb = Quat::Identity();    ///< attitude body -> NED
  Vec3 omega_b = Vec3::Zero();     ///< angular rate of b w.r.t. n, in b [rad/s]
  Vec3 f_b = Vec3::Zero();         ///< specific force a - g, in b [m/s^2]
  double distance_m = 0.0;         ///< horizontal distance travelled since start [m]
};

/// A built trajectory; cheap to evaluate at any time.
class TruthTrajectory {
 public:
  /// Validates the spec (lengths, radii, rates positive; ramps fit in segments) and builds.
  static Result<TruthTrajectory> build(const TrajectorySpec& spec);

  /// Time at which the last segment ends.
  Duration path_duration() const;

  /// Truth at scenario time t >= 0.
  TruthSample at(Duration t) const;

  // Private members: chosen by the implementation (truth.cpp).
};

}  // namespace nav::emulators

// SPDX-License-Identifier: MIT
// The path-segments truth kind (truth_kind.hpp): a vehicle following path segments with a
// speed profile.
//
// The horizontal path is a sequence of segments (straight, arc, turn in place, depth change).
// Speed changes between segments follow a quintic "smootherstep" ramp limited by the
// vehicle's acceleration; arcs blend their curvature in and out over a transition length so
// that the angular rate is continuous; turns in place and depth changes follow smootherstep
// profiles. An optional sinusoidal roll/pitch motion (sea state, sway) is superimposed.
// Position, velocity, attitude, angular rate and specific force are evaluated analytically
// (position by Gauss-Legendre quadrature of the analytic velocity), so they agree with each
// other: integrating omega_b and f_b reproduces the path (tests/unit/emulators/truth_test.cpp).
//
// Frames: n = NED at the datum (treated as inertial: no Earth rate, no transport rate),
// b = FRD. The vehicle starts at rest at start_p_n / start_yaw_rad. After the last segment it
// keeps its final heading and speed, with depth rate 0.
//
// Segment semantics (build() rejects anything else with a message naming the segment):
// - every segment except a turn starts with a speed ramp from the current speed to speed_mps;
//   on straights and arcs the ramp distance counts toward the segment length;
// - arc: length radius*|angle|; the curvature is blended in and out by smootherstep over
//   min(arc_transition_m, length/2) at each end and scaled so the heading change is exactly
//   angle_rad (peak curvature angle / (length - transition));
// - turn: speed ramps to 0 along the current heading, then yaw follows smootherstep with peak
//   rate rate_radps;
// - depth: depth follows smootherstep with peak vertical speed depth_rate_mps while the vehicle
//   keeps its heading; the speed ramp must fit inside the depth change.
#pragma once

#include <cstddef>
#include <vector>

#include "nav/common/frames.hpp"
#include "nav/common/result.hpp"
#include "nav/common/time.hpp"
#include "nav/emulators/truth_kind.hpp"

namespace nav::emulators {

/// One path segment. Which fields matter depends on the kind.
struct Segment {
  enum class Kind { kStraight, kArc, kTurn, kDepth };
  Kind kind = Kind::kStraight;
  double length_m = 0.0;        ///< straight: path length [m]; arc: 0 or radius*|angle| [m]
  double speed_mps = 0.0;       ///< straight/arc (> 0), depth (>= 0): horizontal speed [m/s]
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

/// The path-segments truth kind: a built trajectory, cheap to evaluate at any time.
class TruthTrajectory final : public Truth {
 public:
  /// An empty trajectory: at rest at the origin, level, heading North, forever (the same as
  /// building a spec without segments).
  TruthTrajectory() = default;

  /// Validates the spec (lengths, radii, rates positive; ramps fit in segments) and builds.
  static Result<TruthTrajectory> build(const TrajectorySpec& spec);

  /// Time at which the last segment ends.
  Duration path_duration() const;

  /// Truth at scenario time t >= 0.
  TruthSample at(Duration t) const override;

 private:
  /// One segment as planned by build(). Times are scenario seconds, distances horizontal
  /// path length; the speed ramp occupies [t0_s, t0_s + ramp_s).
  struct Piece {
    Segment::Kind kind = Segment::Kind::kStraight;
    double t0_s = 0.0;            ///< segment start [s]
    double t1_s = 0.0;            ///< segment end [s]
    double s0_m = 0.0;            ///< horizontal distance travelled at the start [m]
    double yaw0_rad = 0.0;        ///< heading at the start (unwrapped) [rad]
    double u0_mps = 0.0;          ///< horizontal speed at the start [m/s]
    double u1_mps = 0.0;          ///< speed held after the ramp [m/s]
    double ramp_s = 0.0;          ///< speed ramp duration [s]
    double ramp_m = 0.0;          ///< distance covered during the ramp [m]
    double length_m = 0.0;        ///< straight/arc: path length [m]
    double kappa_peak = 0.0;      ///< arc: peak signed curvature, + starboard [1/m]
    double transition_m = 0.0;    ///< arc: curvature blend length at each end [m]
    double turn_rad = 0.0;        ///< turn: heading change [rad]
    double turn_s = 0.0;          ///< turn: yaw profile duration (after the ramp) [s]
    double depth_change_m = 0.0;  ///< depth: change, + deeper [m]
    double depth_s = 0.0;         ///< depth: duration of the depth profile [s]
  };

  /// Path kinematics at one instant, before the attitude motion is superimposed.
  struct PathState {
    double s_m = 0.0;             ///< horizontal distance travelled [m]
    double u_mps = 0.0;           ///< horizontal speed [m/s]
    double u_dot_mps2 = 0.0;      ///< its time derivative [m/s^2]
    double yaw_rad = 0.0;         ///< path heading (unwrapped) [rad]
    double yaw_rate_radps = 0.0;  ///< its time derivative [rad/s]
    double z_dot_mps = 0.0;       ///< vertical velocity, + down [m/s]
    double z_ddot_mps2 = 0.0;     ///< vertical acceleration, + down [m/s^2]
  };

  /// Path kinematics at t_s [s] (any t_s >= 0, including after the last segment).
  PathState path_state(double t_s) const;
  /// Velocity, NED, at t_s [m/s].
  Vec3 velocity_n(double t_s) const;
  /// Integral of velocity_n over [a_s, b_s] by 5-point Gauss-Legendre [m]; exact enough only
  /// when no breakpoint lies strictly inside.
  Vec3 integrate_velocity(double a_s, double b_s) const;
  /// Position, NED, at t_s [m].
  Vec3 position_n(double t_s) const;
  /// Builds the segment plan; an error names the segment and what is wrong.
  Result<void> plan(const TrajectorySpec& spec);
  /// Builds the position knots (uniform grid plus every breakpoint).
  void build_knots(std::vector<double> breakpoints_s);

  TrajectorySpec spec_;
  std::vector<Piece> pieces_;
  double end_t_s_ = 0.0;                  ///< time the last segment ends [s]
  PathState end_state_;                   ///< path state from end_t_s_ on
  std::vector<double> knot_t_s_{0.0};     ///< knot times, sorted, first 0, last end_t_s_ [s]
  std::vector<Vec3> knot_p_n_{Vec3(Vec3::Zero())};  ///< position at each knot, NED [m]
  std::vector<std::size_t> grid_knot_{0};  ///< index of the knot at each uniform grid time
};

}  // namespace nav::emulators

// SPDX-License-Identifier: MIT
// TruthTrajectory: self-consistency (strapdown re-integration of omega_b and f_b, finite
// differences), closure of arcs, segment semantics, and rejection of invalid specs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>

#include "nav/common/frames.hpp"
#include "nav/common/units.hpp"
#include "nav/emulators/truth.hpp"

namespace nav::emulators {
namespace {

using std::chrono::milliseconds;
using units::deg_to_rad;
constexpr double kPi = std::numbers::pi;

Segment straight(double length_m, double speed_mps) {
  Segment s;
  s.kind = Segment::Kind::kStraight;
  s.length_m = length_m;
  s.speed_mps = speed_mps;
  return s;
}

Segment arc(double radius_m, double angle_rad, double speed_mps) {
  Segment s;
  s.kind = Segment::Kind::kArc;
  s.radius_m = radius_m;
  s.angle_rad = angle_rad;
  s.speed_mps = speed_mps;
  return s;
}

Segment turn(double angle_rad, double rate_radps) {
  Segment s;
  s.kind = Segment::Kind::kTurn;
  s.angle_rad = angle_rad;
  s.rate_radps = rate_radps;
  return s;
}

Segment depth(double change_m, double rate_mps, double speed_mps) {
  Segment s;
  s.kind = Segment::Kind::kDepth;
  s.depth_change_m = change_m;
  s.depth_rate_mps = rate_mps;
  s.speed_mps = speed_mps;
  return s;
}

/// Every segment kind, speed changes between them (including a ramp inside an arc and to and
/// from rest) and sea-state attitude motion; about 83 s long.
TrajectorySpec full_spec() {
  TrajectorySpec spec;
  spec.start_p_n = Vec3{10.0, -5.0, 2.0};
  spec.start_yaw_rad = 0.3;
  spec.max_accel_mps2 = 0.3;
  spec.arc_transition_m = 2.0;
  spec.segments = {straight(15.0, 1.5),
                   arc(10.0, deg_to_rad(90.0), 1.0),
                   turn(deg_to_rad(-120.0), 0.3),
                   depth(3.0, 0.3, 0.8),
                   arc(8.0, deg_to_rad(-60.0), 1.2),
                   straight(10.0, 1.2)};
  spec.motion.roll_amplitude_rad = deg_to_rad(5.0);
  spec.motion.pitch_amplitude_rad = deg_to_rad(3.0);
  spec.motion.period_s = 7.0;
  return spec;
}

TruthTrajectory build_ok(const TrajectorySpec& spec) {
  auto r = TruthTrajectory::build(spec);
  EXPECT_TRUE(r.has_value()) << (r ? "" : r.error().detail);
  return *r;
}

Duration secs(double s) { return from_seconds(s); }

// ---------------------------------------------------------------------------------------------
// Strapdown RK4 re-integration (the acceptance test of the generator).

struct NavState {
  Vec3 p_n = Vec3::Zero();
  Vec3 v_n = Vec3::Zero();
  Eigen::Vector4d q = Eigen::Vector4d::Zero();  ///< q_nb coefficients (x, y, z, w)
};

struct NavRate {
  Vec3 p_dot;
  Vec3 v_dot;
  Eigen::Vector4d q_dot;
};

Quat to_quat(const Eigen::Vector4d& c) {
  Quat q;
  q.coeffs() = c;
  return q;
}

/// p_dot = v, v_dot = R_nb f_b + g_n, q_dot = 1/2 q (x) [0, omega_b].
NavRate strapdown_rate(const NavState& x, const Vec3& omega_b, const Vec3& f_b, double g) {
  const Quat q = to_quat(x.q);
  NavRate r;
  r.p_dot = x.v_n;
  r.v_dot = q * f_b + Vec3{0.0, 0.0, g};
  r.q_dot = 0.5 * (q * Quat(0.0, omega_b.x(), omega_b.y(), omega_b.z())).coeffs();
  return r;
}

NavState step(const NavState& x, const NavRate& r, double h) {
  NavState y;
  y.p_n = x.p_n + h * r.p_dot;
  y.v_n = x.v_n + h * r.v_dot;
  y.q = x.q + h * r.q_dot;
  return y;
}

TEST(TruthTrajectory, StrapdownRk4ReintegrationReproducesTruth) {
  const TrajectorySpec spec = full_spec();
  const TruthTrajectory traj = build_ok(spec);
  ASSERT_GE(to_seconds(traj.path_duration()), 60.0);

  const double g = spec.gravity_mps2;
  const Duration h = std::chrono::microseconds(5000);  // 200 Hz
  const double h_s = to_seconds(h);
  // The whole path plus 5 s of the straight continuation (>= 60 s as required).
  const auto n_steps = static_cast<int>((traj.path_duration() + std::chrono::seconds(5)) / h);

  const TruthSample t0 = traj.at(Duration{0});
  NavState x;
  x.p_n = t0.p_n;
  x.v_n = t0.v_n;
  x.q = t0.q_nb.coeffs();

  double max_p_err = 0.0, max_v_err = 0.0, max_att_err = 0.0;
  TruthSample a = t0;
  for (int k = 0; k < n_steps; ++k) {
    const Duration t = h * k;
    const TruthSample m = traj.at(t + h / 2);
    const TruthSample b = traj.at(t + h);
    const NavRate k1 = strapdown_rate(x, a.omega_b, a.f_b, g);
    const NavRate k2 = strapdown_rate(step(x, k1, h_s / 2), m.omega_b, m.f_b, g);
    const NavRate k3 = strapdown_rate(step(x, k2, h_s / 2), m.omega_b, m.f_b, g);
    const NavRate k4 = strapdown_rate(step(x, k3, h_s), b.omega_b, b.f_b, g);
    x.p_n += h_s / 6 * (k1.p_dot + 2 * k2.p_dot + 2 * k3.p_dot + k4.p_dot);
    x.v_n += h_s / 6 * (k1.v_dot + 2 * k2.v_dot + 2 * k3.v_dot + k4.v_dot);
    x.q += h_s / 6 * (k1.q_dot + 2 * k2.q_dot + 2 * k3.q_dot + k4.q_dot);
    x.q.normalize();

    max_p_err = std::max(max_p_err, (x.p_n - b.p_n).norm());
    max_v_err = std::max(max_v_err, (x.v_n - b.v_n).norm());
    max_att_err = std::max(max_att_err, attitude_error_angle(to_quat(x.q), b.q_nb));
    a = b;
  }
  const double final_p_err = (x.p_n - a.p_n).norm();
  const double final_att_err = attitude_error_angle(to_quat(x.q), a.q_nb);
  std::printf("RK4 %d steps (%.1f s): position err final %.3e mm max %.3e mm; velocity err "
              "max %.3e mm/s; attitude err final %.3e deg max %.3e deg\n",
              n_steps, n_steps * h_s, final_p_err * 1e3, max_p_err * 1e3, max_v_err * 1e3,
              units::rad_to_deg(final_att_err), units::rad_to_deg(max_att_err));
  EXPECT_LT(final_p_err, 1e-3);
  EXPECT_LT(max_p_err, 1e-3);
  EXPECT_LT(max_v_err, 1e-4);
  EXPECT_LT(units::rad_to_deg(final_att_err), 0.01);
  EXPECT_LT(units::rad_to_deg(max_att_err), 0.01);
  // The path really went somewhere: it is not a trivially small test.
  EXPECT_GT(a.distance_m, 50.0);
  EXPECT_NEAR(a.p_n.z(), spec.start_p_n.z() + 3.0, 1e-9);
}

// ---------------------------------------------------------------------------------------------
// Finite-difference consistency.

TEST(TruthTrajectory, DerivativesMatchFiniteDifferences) {
  const TruthTrajectory traj = build_ok(full_spec());
  const Duration d = milliseconds(1);
  const double d_s = to_seconds(d);
  const double end_s = to_seconds(traj.path_duration()) + 3.0;
  int checked = 0;
  for (double t_s = 0.05; t_s < end_s; t_s += 0.137) {
    const Duration t = secs(t_s);
    const TruthSample x = traj.at(t);
    const TruthSample lo = traj.at(t - d);
    const TruthSample hi = traj.at(t + d);
    const Vec3 v_fd = (hi.p_n - lo.p_n) / (2 * d_s);
    const Vec3 a_fd = (hi.v_n - lo.v_n) / (2 * d_s);
    const Eigen::AngleAxisd rot(lo.q_nb.conjugate() * hi.q_nb);  // exp(omega_b 2d)
    const Vec3 omega_fd = rot.axis() * rot.angle() / (2 * d_s);
    const double speed_fd = (hi.distance_m - lo.distance_m) / (2 * d_s);
    ASSERT_LT((v_fd - x.v_n).norm(), 1e-6) << "t = " << t_s;
    ASSERT_LT((a_fd - x.a_n).norm(), 1e-5) << "t = " << t_s;
    ASSERT_LT((omega_fd - x.omega_b).norm(), 1e-6) << "t = " << t_s;
    ASSERT_NEAR(speed_fd, x.v_n.head<2>().norm(), 1e-6) << "t = " << t_s;
    const Vec3 f_expected = x.q_nb.conjugate() * (x.a_n - Vec3{0.0, 0.0, 9.80665});
    ASSERT_LT((x.f_b - f_expected).norm(), 1e-12);
    ++checked;
  }
  EXPECT_GT(checked, 600);
}

TEST(TruthTrajectory, PositionIsTheIntegralOfVelocity) {
  // Independent reference: composite Simpson over 5 ms steps of the generator's v_n (error
  // ~h^4 v''''/180, far below 1e-9 m), compared with at().p_n every 0.5 s.
  const TruthTrajectory traj = build_ok(full_spec());
  const Duration h = milliseconds(5);
  const double h_s = to_seconds(h);
  Vec3 p = traj.at(Duration{0}).p_n;
  double max_err = 0.0;
  const auto n_steps = (traj.path_duration() + std::chrono::seconds(2)) / h;
  for (std::int64_t k = 0; k < n_steps; ++k) {
    const Duration t = h * k;
    p += h_s / 6 * (traj.at(t).v_n + 4 * traj.at(t + h / 2).v_n + traj.at(t + h).v_n);
    if ((k + 1) % 100 == 0) max_err = std::max(max_err, (p - traj.at(t + h).p_n).norm());
  }
  std::printf("position vs Simpson integral of v_n: max error %.3e m\n", max_err);
  EXPECT_LT(max_err, 1e-8);  // << 1 um
}

TEST(TruthTrajectory, RatesAreContinuousAcrossSegmentBoundaries) {
  TrajectorySpec spec = full_spec();
  spec.motion = AttitudeMotion{};
  const TruthTrajectory traj = build_ok(spec);
  // Sample densely; any step in omega_b or a_n would show as a jump between neighbours.
  const Duration dt = milliseconds(1);
  TruthSample prev = traj.at(Duration{0});
  double max_domega = 0.0, max_da = 0.0;
  for (Duration t = dt; t < traj.path_duration() + std::chrono::seconds(1); t += dt) {
    const TruthSample x = traj.at(t);
    max_domega = std::max(max_domega, (x.omega_b - prev.omega_b).norm());
    max_da = std::max(max_da, (x.a_n - prev.a_n).norm());
    prev = x;
  }
  // Bounded jerk and angular acceleration: the change over 1 ms stays tiny. (A step, e.g. the
  // curvature of an arc without transition, would be 1/R * u ~ 0.1 rad/s.)
  EXPECT_LT(max_domega, 2e-3);
  EXPECT_LT(max_da, 2e-3);
  std::printf("largest change over 1 ms: omega_b %.2e rad/s, a_n %.2e m/s^2\n", max_domega,
              max_da);
}

// ---------------------------------------------------------------------------------------------
// Segment semantics and closure.

TEST(TruthTrajectory, FullCircleWithoutTransitionsClosesExactly) {
  TrajectorySpec spec;
  spec.start_yaw_rad = 1.1;
  spec.max_accel_mps2 = 0.5;
  spec.arc_transition_m = 0.0;
  const double radius = 12.0;
  spec.segments = {straight(20.0, 1.0), arc(radius, 2 * kPi, 1.0)};
  const TruthTrajectory traj = build_ok(spec);
  const double arc_start_s = 1.875 * 1.0 / 0.5 + (20.0 - 0.5 * 1.875 * 1.0 / 0.5) / 1.0;
  const TruthSample start = traj.at(secs(arc_start_s));
  const TruthSample end = traj.at(traj.path_duration());
  EXPECT_NEAR(to_seconds(traj.path_duration()) - arc_start_s, 2 * kPi * radius / 1.0, 1e-9);
  EXPECT_LT((end.p_n - start.p_n).norm(), 1e-6);
  // start is at the arc's first nanosecond (t rounds to ns): up to 0.5 ns * 1/12 rad/s.
  EXPECT_LT(attitude_error_angle(end.q_nb, start.q_nb), 1e-10);
  // Starboard turn: the centre lies to the right of the initial heading; every point on the
  // arc is one radius from it.
  const Vec3 centre = start.p_n + radius * Vec3{-std::sin(1.1), std::cos(1.1), 0.0};
  for (double t_s = arc_start_s; t_s < arc_start_s + 2 * kPi * radius; t_s += 0.77) {
    EXPECT_NEAR((traj.at(secs(t_s)).p_n - centre).norm(), radius, 1e-6);
  }
  // Without a transition the curvature steps on at the arc start.
  EXPECT_NEAR(traj.at(secs(arc_start_s - 1e-3)).omega_b.z(), 0.0, 1e-15);
  EXPECT_NEAR(traj.at(secs(arc_start_s + 1.0)).omega_b.z(), 1.0 / radius, 1e-12);
}

TEST(TruthTrajectory, BlendedArcTurnsExactlyItsAngleAndEndsStraight) {
  for (const double angle : {2 * kPi, -2 * kPi, deg_to_rad(45.0), deg_to_rad(-200.0)}) {
    TrajectorySpec spec;
    spec.start_yaw_rad = -0.4;
    spec.arc_transition_m = 3.0;
    spec.segments = {straight(10.0, 0.8), arc(6.0, angle, 0.8), straight(2.0, 0.8)};
    const TruthTrajectory traj = build_ok(spec);
    const TruthSample end = traj.at(traj.path_duration());
    EXPECT_NEAR(wrap_pi(euler_from_quat(end.q_nb).yaw - (-0.4 + angle)), 0.0, 1e-12);
    EXPECT_NEAR(std::atan2(end.v_n.y(), end.v_n.x()), wrap_pi(-0.4 + angle), 1e-12);
    EXPECT_NEAR(end.omega_b.z(), 0.0, 1e-15);
    EXPECT_NEAR(end.distance_m, 12.0 + 6.0 * std::abs(angle), 1e-9);
  }
}

TEST(TruthTrajectory, ShortArcShrinksItsTransitions) {
  TrajectorySpec spec;
  spec.arc_transition_m = 50.0;  // longer than the arc: both transitions shrink to half
  spec.segments = {straight(5.0, 0.5), arc(4.0, deg_to_rad(30.0), 0.5)};
  const TruthTrajectory traj = build_ok(spec);
  const TruthSample end = traj.at(traj.path_duration());
  EXPECT_NEAR(euler_from_quat(end.q_nb).yaw, deg_to_rad(30.0), 1e-12);
  EXPECT_NEAR(end.omega_b.z(), 0.0, 1e-15);
}

TEST(TruthTrajectory, StraightSpeedRampAndContinuation) {
  TrajectorySpec spec;
  spec.start_p_n = Vec3{1.0, 2.0, 3.0};
  spec.start_yaw_rad = deg_to_rad(-30.0);
  spec.max_accel_mps2 = 0.25;
  spec.segments = {straight(40.0, 2.0)};
  const TruthTrajectory traj = build_ok(spec);
  const double ramp_s = 1.875 * 2.0 / 0.25;  // 15 s, 15 m
  EXPECT_NEAR(to_seconds(traj.path_duration()), ramp_s + 25.0 / 2.0, 1e-9);
  const Vec3 dir{std::cos(spec.start_yaw_rad), std::sin(spec.start_yaw_rad), 0.0};
  // Peak acceleration at the middle of the ramp equals max_accel.
  EXPECT_NEAR(traj.at(secs(ramp_s / 2)).a_n.norm(), 0.25, 1e-12);
  // Ramp distance so far: T (u0 x + du I(x)) with I(1/2) = 5/64.
  EXPECT_NEAR(traj.at(secs(ramp_s / 2)).distance_m, ramp_s * 2.0 * 5.0 / 64.0, 1e-12);
  const TruthSample ramp_end = traj.at(secs(ramp_s));
  EXPECT_NEAR(ramp_end.distance_m, 15.0, 1e-9);
  EXPECT_LT((ramp_end.p_n - (spec.start_p_n + 15.0 * dir)).norm(), 1e-9);
  const TruthSample end = traj.at(traj.path_duration());
  EXPECT_LT((end.p_n - (spec.start_p_n + 40.0 * dir)).norm(), 1e-9);
  // After the last segment: straight on at the final heading and speed.
  const TruthSample later = traj.at(traj.path_duration() + std::chrono::seconds(100));
  EXPECT_LT((later.p_n - (spec.start_p_n + 240.0 * dir)).norm(), 1e-9);
  EXPECT_LT((later.v_n - 2.0 * dir).norm(), 1e-12);
  EXPECT_LT(later.a_n.norm(), 1e-15);
  EXPECT_NEAR(later.distance_m, 240.0, 1e-9);
  // At rest at t = 0, level: the specific force is -g along body z.
  const TruthSample first = traj.at(Duration{0});
  EXPECT_LT((first.f_b - Vec3{0.0, 0.0, -9.80665}).norm(), 1e-12);
  EXPECT_LT(first.v_n.norm(), 1e-15);
}

TEST(TruthTrajectory, TurnInPlaceStopsThenYawsAtThePeakRate) {
  TrajectorySpec spec;
  spec.max_accel_mps2 = 0.2;
  spec.segments = {straight(10.0, 1.0), turn(deg_to_rad(90.0), 0.2)};
  const TruthTrajectory traj = build_ok(spec);
  const double t_straight = 1.875 / 0.2 + (10.0 - 0.5 * 1.875 / 0.2) / 1.0;
  const double t_stop = t_straight + 1.875 / 0.2;
  const double t_yaw = 1.875 * (kPi / 2) / 0.2;
  EXPECT_NEAR(to_seconds(traj.path_duration()), t_stop + t_yaw, 1e-9);
  const TruthSample stopped = traj.at(secs(t_stop));
  EXPECT_LT(stopped.v_n.norm(), 1e-12);
  EXPECT_NEAR(stopped.p_n.x(), 10.0 + 0.5 * 1.875 / 0.2, 1e-9);  // stopping distance
  const TruthSample mid = traj.at(secs(t_stop + t_yaw / 2));
  EXPECT_NEAR(mid.omega_b.z(), 0.2, 1e-12);
  EXPECT_LT((mid.p_n - stopped.p_n).norm(), 1e-9);
  const TruthSample end = traj.at(traj.path_duration() + std::chrono::seconds(10));
  EXPECT_NEAR(euler_from_quat(end.q_nb).yaw, kPi / 2, 1e-12);
  EXPECT_LT((end.p_n - stopped.p_n).norm(), 1e-9);  // stays put afterwards (speed 0)
}

TEST(TruthTrajectory, DepthChangeFollowsSmootherstepWhileMovingOn) {
  TrajectorySpec spec;
  spec.start_p_n = Vec3{0.0, 0.0, 1.0};
  spec.max_accel_mps2 = 0.2;
  spec.segments = {depth(-0.8, 0.1, 0.5)};
  const TruthTrajectory traj = build_ok(spec);
  const double t_depth = 1.875 * 0.8 / 0.1;
  EXPECT_NEAR(to_seconds(traj.path_duration()), t_depth, 1e-9);
  EXPECT_NEAR(traj.at(secs(t_depth / 2)).v_n.z(), -0.1, 1e-12);  // peak rate, rising
  const TruthSample end = traj.at(traj.path_duration());
  EXPECT_NEAR(end.p_n.z(), 0.2, 1e-12);
  EXPECT_NEAR(end.v_n.z(), 0.0, 1e-15);
  const double ramp_s = 1.875 * 0.5 / 0.2;
  EXPECT_NEAR(end.distance_m, 0.5 * ramp_s * 0.5 + 0.5 * (t_depth - ramp_s), 1e-9);
  EXPECT_NEAR(end.p_n.x(), end.distance_m, 1e-9);
}

TEST(TruthTrajectory, EmptyPathStaysAtRest) {
  TrajectorySpec spec;
  spec.start_p_n = Vec3{3.0, 4.0, 5.0};
  spec.motion.roll_amplitude_rad = 0.1;
  const TruthTrajectory traj = build_ok(spec);
  EXPECT_EQ(traj.path_duration(), Duration{0});
  const TruthSample x = traj.at(std::chrono::seconds(42));
  EXPECT_LT((x.p_n - spec.start_p_n).norm(), 1e-15);
  EXPECT_NEAR(x.f_b.norm(), 9.80665, 1e-12);
}

TEST(TruthTrajectory, DefaultConstructedIsAtRestAtTheOrigin) {
  const TruthTrajectory traj;
  const TruthSample x = traj.at(std::chrono::seconds(3));
  EXPECT_EQ(traj.path_duration(), Duration{0});
  EXPECT_EQ(x.p_n, Vec3::Zero());
  EXPECT_EQ(x.v_n, Vec3::Zero());
  EXPECT_LT((x.f_b - Vec3{0.0, 0.0, -9.80665}).norm(), 1e-15);
}

TEST(TruthTrajectory, IsDeterministic) {
  const TruthTrajectory a = build_ok(full_spec());
  const TruthTrajectory b = build_ok(full_spec());
  for (double t_s = 0.0; t_s < 90.0; t_s += 1.3) {
    const TruthSample x = a.at(secs(t_s));
    const TruthSample y = b.at(secs(t_s));
    EXPECT_EQ(x.p_n, y.p_n);
    EXPECT_EQ(x.f_b, y.f_b);
    EXPECT_EQ(x.omega_b, y.omega_b);
  }
}

// ---------------------------------------------------------------------------------------------
// Invalid specs are refused with a message naming the segment and the problem.

void expect_rejected(const TrajectorySpec& spec, const std::string& part1,
                     const std::string& part2) {
  const auto r = TruthTrajectory::build(spec);
  ASSERT_FALSE(r.has_value()) << "accepted, expected an error about " << part2;
  EXPECT_EQ(r.error().code, ErrorCode::kInvalidArgument);
  EXPECT_NE(r.error().detail.find(part1), std::string::npos) << r.error().detail;
  EXPECT_NE(r.error().detail.find(part2), std::string::npos) << r.error().detail;
}

TEST(TruthTrajectory, RejectsInvalidSpecs) {
  TrajectorySpec s = full_spec();
  s.segments[1].radius_m = -1.0;
  expect_rejected(s, "segment 1 (arc)", "radius_m must be > 0");

  s = full_spec();
  s.segments[0].speed_mps = std::nan("");
  expect_rejected(s, "segment 0 (straight)", "finite");

  s = full_spec();
  s.segments[5].length_m = 0.0;
  expect_rejected(s, "segment 5 (straight)", "length_m must be > 0");

  s = full_spec();
  s.segments[2].rate_radps = 0.0;
  expect_rejected(s, "segment 2 (turn)", "rate_radps");

  s = full_spec();
  s.segments[3].depth_rate_mps = -0.1;
  expect_rejected(s, "segment 3 (depth)", "depth_rate_mps");

  s = full_spec();
  s.segments[4].angle_rad = 0.0;
  expect_rejected(s, "segment 4 (arc)", "angle_rad must be non-zero");

  s = full_spec();
  s.segments[4].length_m = 3.0;  // radius 8, 60 deg: 8.38 m
  expect_rejected(s, "segment 4 (arc)", "radius_m * |angle_rad|");

  s = full_spec();
  s.segments[0].length_m = 2.0;  // ramp 0 -> 1.5 m/s needs 7.03 m
  expect_rejected(s, "segment 0 (straight)", "needs 7.03125 m");

  s = full_spec();
  s.segments[3].depth_rate_mps = 10.0;  // 0.56 s of depth change, 5 s of speed ramp
  expect_rejected(s, "segment 3 (depth)", "speed ramp");

  s = full_spec();
  s.max_accel_mps2 = 0.0;
  expect_rejected(s, "trajectory", "max_accel_mps2 must be > 0");

  s = full_spec();
  s.motion.period_s = 0.0;
  expect_rejected(s, "attitude motion", "period_s must be > 0");

  s = full_spec();
  s.motion.pitch_amplitude_rad = 2.0;
  expect_rejected(s, "attitude motion", "pitch_amplitude_rad");

  s = full_spec();
  s.start_p_n.x() = std::numeric_limits<double>::infinity();
  expect_rejected(s, "trajectory", "finite");
}

}  // namespace
}  // namespace nav::emulators

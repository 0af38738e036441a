// SPDX-License-Identifier: MIT
// Truth trajectory generator (see truth.hpp).
//
// Model (all SI, n = NED, b = FRD):
//   S(x)  = 6x^5 - 15x^4 + 10x^3          quintic smootherstep, S(0)=0, S(1)=1
//   S'(x) = 30 x^2 (1-x)^2                peak S'(1/2) = 15/8
//   I(x)  = x^6 - 3x^5 + 5/2 x^4          integral of S from 0, I(1) = 1/2
//   speed ramp u0 -> u1 over T_r:  u = u0 + (u1-u0) S(tau/T_r),  T_r = 15/8 |u1-u0| / a_max,
//                                  distance during the ramp d_r = T_r (u0+u1)/2
//   arc: kappa(s) = kappa_peak * w(s), w ramps 0->1 by S over L_t at each end;
//        total turn = kappa_peak (L - L_t) = angle  =>  kappa_peak = angle / (L - L_t)
//   heading rate  psi_dot = u kappa(s)            (arc)
//                 psi = psi0 + angle S(tau/T_y),  T_y = 15/8 |angle| / rate   (turn)
//   depth         z = z0 + dz S(tau/T_d),          T_d = 15/8 |dz| / w_max
//   v_n = [u cos psi, u sin psi, z_dot]
//   a_n = [u_dot cos psi - u psi_dot sin psi, u_dot sin psi + u psi_dot cos psi, z_ddot]
//   roll = A_r sin(2 pi t/T), pitch = A_p sin(2 pi t/T + pi/2), yaw = psi
//   omega_b = [phi_dot - psi_dot sin theta,
//              theta_dot cos phi + psi_dot sin phi cos theta,
//              -theta_dot sin phi + psi_dot cos phi cos theta]      (ZYX Euler kinematics)
//   f_b = R_nb^T (a_n - [0, 0, g])
//   p_n(t) = p_n(knot) + integral of v_n from the knot to t (5-point Gauss-Legendre).
// Knots lie on a 0.1 s grid and on every breakpoint (segment ends, ramp ends, arc transition
// ends), so each quadrature interval sees an analytic integrand and the 5-point rule
// (exact to degree 9) is accurate far below a micrometre.
#include "nav/emulators/truth.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "nav/common/ensure.hpp"

namespace nav::emulators {
namespace {

constexpr double kSmootherstepPeak = 15.0 / 8.0;  ///< max of S'(x) on [0, 1] [-]
constexpr double kKnotStep_s = 0.1;               ///< uniform knot spacing [s]

double smootherstep(double x) { return x * x * x * (10.0 + x * (-15.0 + 6.0 * x)); }
double smootherstep_d1(double x) { return 30.0 * x * x * (1.0 - x) * (1.0 - x); }
double smootherstep_d2(double x) { return 60.0 * x * (1.0 - x) * (1.0 - 2.0 * x); }
double smootherstep_integral(double x) { return x * x * x * x * (2.5 + x * (-3.0 + x)); }

/// 5-point Gauss-Legendre nodes and weights on [-1, 1].
constexpr std::array<double, 5> kGlNodes = {-0.9061798459386640, -0.5384693101056831, 0.0,
                                            0.5384693101056831, 0.9061798459386640};
constexpr std::array<double, 5> kGlWeights = {0.2369268850561891, 0.4786286704993665,
                                              0.5688888888888889, 0.4786286704993665,
                                              0.2369268850561891};

std::string num(double v) {
  std::array<char, 32> buf{};
  std::snprintf(buf.data(), buf.size(), "%.6g", v);
  return buf.data();
}

const char* kind_name(Segment::Kind k) {
  switch (k) {
    case Segment::Kind::kStraight: return "straight";
    case Segment::Kind::kArc: return "arc";
    case Segment::Kind::kTurn: return "turn";
    case Segment::Kind::kDepth: return "depth";
  }
  return "unknown";
}

std::string where(std::size_t i, const Segment& seg) {
  return "segment " + std::to_string(i) + " (" + kind_name(seg.kind) + "): ";
}

tl::unexpected<Error> invalid(std::string detail) {
  return fail(ErrorCode::kInvalidArgument, std::move(detail));
}

/// Checks the spec-wide fields; segments are checked by plan().
Result<void> validate_globals(const TrajectorySpec& spec) {
  if (!spec.start_p_n.allFinite() || !std::isfinite(spec.start_yaw_rad)) {
    return invalid("trajectory: start position and yaw must be finite");
  }
  if (!std::isfinite(spec.max_accel_mps2) || spec.max_accel_mps2 <= 0.0) {
    return invalid("trajectory: max_accel_mps2 must be > 0 (got " + num(spec.max_accel_mps2) +
                   ")");
  }
  if (!std::isfinite(spec.arc_transition_m) || spec.arc_transition_m < 0.0) {
    return invalid("trajectory: arc_transition_m must be >= 0 (got " +
                   num(spec.arc_transition_m) + ")");
  }
  if (!std::isfinite(spec.gravity_mps2)) {
    return invalid("trajectory: gravity_mps2 must be finite");
  }
  const AttitudeMotion& m = spec.motion;
  if (!std::isfinite(m.roll_amplitude_rad) || !std::isfinite(m.pitch_amplitude_rad)) {
    return invalid("attitude motion: amplitudes must be finite");
  }
  if (std::abs(m.pitch_amplitude_rad) >= 0.5 * std::numbers::pi) {
    return invalid("attitude motion: |pitch_amplitude_rad| must be < pi/2 (got " +
                   num(m.pitch_amplitude_rad) + ")");
  }
  if (!std::isfinite(m.period_s) || m.period_s <= 0.0) {
    return invalid("attitude motion: period_s must be > 0 (got " + num(m.period_s) + ")");
  }
  return {};
}

/// Checks the fields a segment's kind uses.
Result<void> validate_segment(std::size_t i, const Segment& seg) {
  const std::array<double, 7> all = {seg.length_m,   seg.speed_mps,      seg.radius_m,
                                     seg.angle_rad,  seg.rate_radps,     seg.depth_change_m,
                                     seg.depth_rate_mps};
  if (!std::all_of(all.begin(), all.end(), [](double v) { return std::isfinite(v); })) {
    return invalid(where(i, seg) + "every field must be finite");
  }
  auto positive = [&](double v, const char* name) -> Result<void> {
    if (v > 0.0) return {};
    return invalid(where(i, seg) + name + " must be > 0 (got " + num(v) + ")");
  };
  switch (seg.kind) {
    case Segment::Kind::kStraight:
      if (auto r = positive(seg.length_m, "length_m"); !r) return r;
      return positive(seg.speed_mps, "speed_mps");
    case Segment::Kind::kArc: {
      if (auto r = positive(seg.radius_m, "radius_m"); !r) return r;
      if (auto r = positive(seg.speed_mps, "speed_mps"); !r) return r;
      if (seg.angle_rad == 0.0) return invalid(where(i, seg) + "angle_rad must be non-zero");
      const double arc_m = seg.radius_m * std::abs(seg.angle_rad);
      if (seg.length_m != 0.0 && std::abs(seg.length_m - arc_m) > 1e-6 * arc_m) {
        return invalid(where(i, seg) + "length_m (" + num(seg.length_m) +
                       ") must be 0 or radius_m * |angle_rad| (" + num(arc_m) + ")");
      }
      return {};
    }
    case Segment::Kind::kTurn:
      if (seg.angle_rad == 0.0) return invalid(where(i, seg) + "angle_rad must be non-zero");
      return positive(seg.rate_radps, "rate_radps");
    case Segment::Kind::kDepth:
      if (seg.depth_change_m == 0.0) {
        return invalid(where(i, seg) + "depth_change_m must be non-zero");
      }
      if (seg.speed_mps < 0.0) {
        return invalid(where(i, seg) + "speed_mps must be >= 0 (got " + num(seg.speed_mps) +
                       ")");
      }
      return positive(seg.depth_rate_mps, "depth_rate_mps");
  }
  return invalid(where(i, seg) + "unknown kind");
}

/// Heading change along an arc after s_m of its length, and the curvature there.
struct ArcShape {
  double psi_rad;
  double kappa;
};

ArcShape arc_shape(double kappa_peak, double transition_m, double length_m, double s_m) {
  const double s = std::clamp(s_m, 0.0, length_m);
  const double total = kappa_peak * (length_m - transition_m);
  if (s < transition_m) {  // blend in
    const double x = s / transition_m;
    return {kappa_peak * transition_m * smootherstep_integral(x), kappa_peak * smootherstep(x)};
  }
  if (s > length_m - transition_m) {  // blend out, mirrored
    const double y = (length_m - s) / transition_m;
    return {total - kappa_peak * transition_m * smootherstep_integral(y),
            kappa_peak * smootherstep(y)};
  }
  return {kappa_peak * (0.5 * transition_m + (s - transition_m)), kappa_peak};
}

}  // namespace

Result<TruthTrajectory> TruthTrajectory::build(const TrajectorySpec& spec) {
  if (auto r = validate_globals(spec); !r) return tl::unexpected(r.error());
  TruthTrajectory traj;
  if (auto r = traj.plan(spec); !r) return tl::unexpected(r.error());
  return traj;
}

Duration TruthTrajectory::path_duration() const { return from_seconds(end_t_s_); }

Result<void> TruthTrajectory::plan(const TrajectorySpec& spec) {
  spec_ = spec;
  pieces_.clear();
  std::vector<double> breakpoints{0.0};
  double t = 0.0;
  double s = 0.0;
  double yaw = spec.start_yaw_rad;
  double u = 0.0;  // the vehicle starts at rest
  for (std::size_t i = 0; i < spec.segments.size(); ++i) {
    const Segment& seg = spec.segments[i];
    if (auto r = validate_segment(i, seg); !r) return r;
    Piece p;
    p.kind = seg.kind;
    p.t0_s = t;
    p.s0_m = s;
    p.yaw0_rad = yaw;
    p.u0_mps = u;
    p.u1_mps = seg.kind == Segment::Kind::kTurn ? 0.0 : seg.speed_mps;
    p.ramp_s = kSmootherstepPeak * std::abs(p.u1_mps - p.u0_mps) / spec.max_accel_mps2;
    p.ramp_m = 0.5 * p.ramp_s * (p.u0_mps + p.u1_mps);
    double duration_s = 0.0;
    switch (seg.kind) {
      case Segment::Kind::kStraight:
      case Segment::Kind::kArc: {
        p.length_m = seg.kind == Segment::Kind::kArc ? seg.radius_m * std::abs(seg.angle_rad)
                                                     : seg.length_m;
        if (p.ramp_m > p.length_m) {
          return invalid(where(i, seg) + "speed ramp " + num(p.u0_mps) + " -> " +
                         num(p.u1_mps) + " m/s needs " + num(p.ramp_m) + " m at max_accel " +
                         num(spec.max_accel_mps2) + " m/s^2 but the segment is " +
                         num(p.length_m) + " m long");
        }
        duration_s = p.ramp_s + (p.length_m - p.ramp_m) / p.u1_mps;
        if (seg.kind == Segment::Kind::kArc) {
          p.transition_m = std::min(spec.arc_transition_m, 0.5 * p.length_m);
          p.kappa_peak = seg.angle_rad / (p.length_m - p.transition_m);
          yaw += seg.angle_rad;
        }
        s += p.length_m;
        break;
      }
      case Segment::Kind::kTurn:
        p.turn_rad = seg.angle_rad;
        p.turn_s = kSmootherstepPeak * std::abs(seg.angle_rad) / seg.rate_radps;
        duration_s = p.ramp_s + p.turn_s;
        yaw += seg.angle_rad;
        s += p.ramp_m;
        break;
      case Segment::Kind::kDepth:
        p.depth_change_m = seg.depth_change_m;
        p.depth_s = kSmootherstepPeak * std::abs(seg.depth_change_m) / seg.depth_rate_mps;
        if (p.ramp_s > p.depth_s) {
          return invalid(where(i, seg) + "speed ramp " + num(p.u0_mps) + " -> " +
                         num(p.u1_mps) + " m/s needs " + num(p.ramp_s) + " s at max_accel " +
                         num(spec.max_accel_mps2) + " m/s^2 but the depth change lasts " +
                         num(p.depth_s) + " s");
        }
        duration_s = p.depth_s;
        s += p.ramp_m + p.u1_mps * (p.depth_s - p.ramp_s);
        break;
    }
    p.t1_s = t + duration_s;
    pieces_.push_back(p);
    if (p.ramp_s > 0.0) breakpoints.push_back(p.t0_s + p.ramp_s);
    breakpoints.push_back(p.t1_s);
    t = p.t1_s;
    u = p.u1_mps;
  }
  end_t_s_ = t;
  // The end state must come from the plan itself (not from path_state, which defers to it).
  end_state_ = PathState{};
  end_state_.s_m = s;
  end_state_.u_mps = u;
  end_state_.yaw_rad = yaw;

  // Arc transition ends happen at times where s(t) crosses a length: find them by bisection
  // on the monotonic distance (deterministic, converges to the last representable bit).
  for (const Piece& p : pieces_) {
    if (p.kind != Segment::Kind::kArc || p.transition_m <= 0.0) continue;
    for (const double target_m : {p.transition_m, p.length_m - p.transition_m}) {
      double lo = p.t0_s;
      double hi = p.t1_s;
      for (int it = 0; it < 200 && hi - lo > 0.0; ++it) {
        const double mid = 0.5 * (lo + hi);
        if (mid <= lo || mid >= hi) break;
        if (path_state(mid).s_m - p.s0_m < target_m) {
          lo = mid;
        } else {
          hi = mid;
        }
      }
      breakpoints.push_back(hi);
    }
  }
  build_knots(std::move(breakpoints));
  return {};
}

void TruthTrajectory::build_knots(std::vector<double> breakpoints_s) {
  const auto n_grid = static_cast<std::size_t>(std::floor(end_t_s_ / kKnotStep_s)) + 1;
  std::vector<double> grid(n_grid);
  for (std::size_t j = 0; j < n_grid; ++j) grid[j] = static_cast<double>(j) * kKnotStep_s;
  std::vector<double> all = grid;
  all.insert(all.end(), breakpoints_s.begin(), breakpoints_s.end());
  all.push_back(end_t_s_);
  std::sort(all.begin(), all.end());
  all.erase(std::unique(all.begin(), all.end()), all.end());
  while (!all.empty() && all.back() > end_t_s_) all.pop_back();
  knot_t_s_ = std::move(all);

  knot_p_n_.assign(knot_t_s_.size(), spec_.start_p_n);
  for (std::size_t k = 1; k < knot_t_s_.size(); ++k) {
    knot_p_n_[k] = knot_p_n_[k - 1] + integrate_velocity(knot_t_s_[k - 1], knot_t_s_[k]);
  }
  grid_knot_.resize(n_grid);
  std::size_t k = 0;
  for (std::size_t j = 0; j < n_grid; ++j) {
    while (knot_t_s_[k] < grid[j]) ++k;
    grid_knot_[j] = k;
  }
}

TruthTrajectory::PathState TruthTrajectory::path_state(double t_s) const {
  if (pieces_.empty() || t_s >= end_t_s_) {
    PathState st = end_state_;
    st.s_m += end_state_.u_mps * (t_s - end_t_s_);
    return st;
  }
  const auto it = std::upper_bound(pieces_.begin(), pieces_.end(), t_s,
                                   [](double t, const Piece& p) { return t < p.t0_s; });
  const Piece& p = *(it == pieces_.begin() ? it : it - 1);
  const double tau = std::max(t_s - p.t0_s, 0.0);

  PathState st;
  double s_local = 0.0;
  if (tau < p.ramp_s) {
    const double x = tau / p.ramp_s;
    const double du = p.u1_mps - p.u0_mps;
    st.u_mps = p.u0_mps + du * smootherstep(x);
    st.u_dot_mps2 = du * smootherstep_d1(x) / p.ramp_s;
    s_local = p.ramp_s * (p.u0_mps * x + du * smootherstep_integral(x));
  } else {
    st.u_mps = p.u1_mps;
    s_local = p.ramp_m + p.u1_mps * (tau - p.ramp_s);
  }
  st.s_m = p.s0_m + s_local;
  st.yaw_rad = p.yaw0_rad;

  switch (p.kind) {
    case Segment::Kind::kStraight:
      break;
    case Segment::Kind::kArc: {
      const ArcShape a = arc_shape(p.kappa_peak, p.transition_m, p.length_m, s_local);
      st.yaw_rad = p.yaw0_rad + a.psi_rad;
      st.yaw_rate_radps = st.u_mps * a.kappa;  // psi_dot = u kappa(s)
      break;
    }
    case Segment::Kind::kTurn:
      if (tau >= p.ramp_s) {
        const double y = std::min((tau - p.ramp_s) / p.turn_s, 1.0);
        st.yaw_rad = p.yaw0_rad + p.turn_rad * smootherstep(y);
        st.yaw_rate_radps = p.turn_rad * smootherstep_d1(y) / p.turn_s;
      }
      break;
    case Segment::Kind::kDepth: {
      const double x = std::min(tau / p.depth_s, 1.0);
      st.z_dot_mps = p.depth_change_m * smootherstep_d1(x) / p.depth_s;
      st.z_ddot_mps2 = p.depth_change_m * smootherstep_d2(x) / (p.depth_s * p.depth_s);
      break;
    }
  }
  return st;
}

Vec3 TruthTrajectory::velocity_n(double t_s) const {
  const PathState st = path_state(t_s);
  return {st.u_mps * std::cos(st.yaw_rad), st.u_mps * std::sin(st.yaw_rad), st.z_dot_mps};
}

Vec3 TruthTrajectory::integrate_velocity(double a_s, double b_s) const {
  const double half = 0.5 * (b_s - a_s);
  const double mid = 0.5 * (a_s + b_s);
  Vec3 sum = Vec3::Zero();
  for (std::size_t i = 0; i < kGlNodes.size(); ++i) {
    sum += kGlWeights[i] * velocity_n(mid + half * kGlNodes[i]);
  }
  return half * sum;
}

Vec3 TruthTrajectory::position_n(double t_s) const {
  if (t_s >= end_t_s_) {
    const Vec3 v_end{end_state_.u_mps * std::cos(end_state_.yaw_rad),
                     end_state_.u_mps * std::sin(end_state_.yaw_rad), 0.0};
    return knot_p_n_.back() + v_end * (t_s - end_t_s_);
  }
  const auto j = std::min(static_cast<std::size_t>(std::max(t_s, 0.0) / kKnotStep_s),
                          grid_knot_.size() - 1);
  std::size_t k = grid_knot_[j];
  while (k > 0 && knot_t_s_[k] > t_s) --k;
  while (k + 1 < knot_t_s_.size() && knot_t_s_[k + 1] <= t_s) ++k;
  return knot_p_n_[k] + integrate_velocity(knot_t_s_[k], t_s);
}

TruthSample TruthTrajectory::at(Duration t) const {
  NAV_ENSURE(t.count() >= 0, "truth is defined for t >= 0 only");
  const double t_s = to_seconds(t);
  const PathState st = path_state(t_s);
  const double c = std::cos(st.yaw_rad);
  const double s = std::sin(st.yaw_rad);

  TruthSample out;
  out.t = t;
  out.p_n = position_n(t_s);
  out.v_n = Vec3{st.u_mps * c, st.u_mps * s, st.z_dot_mps};
  out.a_n = Vec3{st.u_dot_mps2 * c - st.u_mps * st.yaw_rate_radps * s,
                 st.u_dot_mps2 * s + st.u_mps * st.yaw_rate_radps * c, st.z_ddot_mps2};
  out.distance_m = st.s_m;

  const AttitudeMotion& m = spec_.motion;
  const double w = 2.0 * std::numbers::pi / m.period_s;
  const double phase = w * t_s;
  const double roll = m.roll_amplitude_rad * std::sin(phase);
  const double pitch = m.pitch_amplitude_rad * std::sin(phase + 0.5 * std::numbers::pi);
  const double roll_dot = m.roll_amplitude_rad * w * std::cos(phase);
  const double pitch_dot = m.pitch_amplitude_rad * w * std::cos(phase + 0.5 * std::numbers::pi);
  const double yaw_dot = st.yaw_rate_radps;
  out.q_nb = quat_from_euler(Euler{roll, pitch, st.yaw_rad});

  // ZYX Euler kinematics: omega_b = E(phi, theta) [phi_dot, theta_dot, psi_dot].
  const double sr = std::sin(roll), cr = std::cos(roll);
  const double sp = std::sin(pitch), cp = std::cos(pitch);
  out.omega_b = Vec3{roll_dot - yaw_dot * sp,                        //
                     pitch_dot * cr + yaw_dot * sr * cp,             //
                     -pitch_dot * sr + yaw_dot * cr * cp};

  const Vec3 g_n{0.0, 0.0, spec_.gravity_mps2};
  const Mat3 R_nb = out.q_nb.toRotationMatrix();
  out.f_b = R_nb.transpose() * (out.a_n - g_n);  // specific force f = a - g
  return out;
}

}  // namespace nav::emulators

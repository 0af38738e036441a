// SPDX-License-Identifier: MIT
// Shared by the P1 tests: a portable seeded normal generator, paper P1's stadium path as an
// analytic truth, and IMU / magnetometer / GPS data synthesised from it.
//
// Stadium (docs/papers.md, P1): start at (0, 0) heading North (+x), 3 m straight, a right-hand
// semicircle of radius 2 m (centre (3, 2)), 6 m straight South, a right-hand semicircle
// (centre (−3, 2)), 3 m North back to the start; level (roll = pitch = 0), depth 0, constant
// speed. One lap is 12 + 4π ≈ 24.57 m. Yaw is unwrapped (0, π, 2π, ... per segment).
// StadiumRun drives navigators along it at 100 Hz with 1 Hz GPS fixes.
#pragma once

#include <cmath>
#include <algorithm>
#include <cstdint>
#include <initializer_list>
#include <numbers>
#include <random>

#include "nav/common/frames.hpp"
#include "nav/estimator/complementary_attitude.hpp"
#include "nav/estimator/p1_types.hpp"

namespace nav::estimator::testing {

/// N(0, 1) by Box–Muller on a std::mt19937_64 (whose output the standard fixes, unlike
/// std::normal_distribution's): the same numbers on every platform.
class Normal {
 public:
  explicit Normal(std::uint64_t seed) : rng_(seed) {}
  double operator()() {
    const double u1 = 1.0 - unit();  // (0, 1]: log is finite
    const double u2 = unit();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }
  Vec3 vec3() {
    const double x = (*this)();
    const double y = (*this)();
    const double z = (*this)();
    return Vec3(x, y, z);
  }

 private:
  double unit() { return static_cast<double>(rng_() >> 11) * 0x1.0p-53; }  // [0, 1), 53 bit
  std::mt19937_64 rng_;
};

/// The truth at one instant.
struct Truth {
  Vec3 p_n = Vec3::Zero();  ///< NED [m]
  Vec3 v_n = Vec3::Zero();  ///< NED [m/s]
  Vec3 a_n = Vec3::Zero();  ///< NED [m/s²]
  double yaw = 0.0;         ///< unwrapped [rad]
  double yaw_rate = 0.0;    ///< [rad/s]
  Quat q_nb() const { return Quat(Eigen::AngleAxisd(yaw, Vec3::UnitZ())); }
};

/// The stadium path at speed v.
class Stadium {
 public:
  static constexpr double kRadius = 2.0;        ///< [m]
  static constexpr double kStraight1 = 3.0;     ///< [m]
  static constexpr double kStraight2 = 6.0;     ///< [m]
  static constexpr double kArc = std::numbers::pi * kRadius;                 ///< [m]
  static constexpr double kLap = 2.0 * kStraight1 + kStraight2 + 2.0 * kArc; ///< [m]

  explicit Stadium(double speed_mps) : v_(speed_mps) {}

  double lap_time_s() const { return kLap / v_; }

  Truth at(double t) const {
    const double total = v_ * t;
    const double laps = std::floor(total / kLap);
    const double s = total - laps * kLap;
    const double a_c = v_ * v_ / kRadius;
    Truth x;
    double yaw0 = 0.0;
    if (s < kStraight1) {
      x.p_n = Vec3(s, 0.0, 0.0);
      yaw0 = 0.0;
    } else if (s < kStraight1 + kArc) {
      const double u = (s - kStraight1) / kRadius;
      x.p_n = Vec3(3.0 + kRadius * std::sin(u), 2.0 - kRadius * std::cos(u), 0.0);
      x.a_n = a_c * Vec3(-std::sin(u), std::cos(u), 0.0);
      x.yaw_rate = v_ / kRadius;
      yaw0 = u;
    } else if (s < kStraight1 + kArc + kStraight2) {
      const double w = s - kStraight1 - kArc;
      x.p_n = Vec3(3.0 - w, 4.0, 0.0);
      yaw0 = std::numbers::pi;
    } else if (s < kStraight1 + 2.0 * kArc + kStraight2) {
      const double u = (s - kStraight1 - kArc - kStraight2) / kRadius;
      x.p_n = Vec3(-3.0 - kRadius * std::sin(u), 2.0 + kRadius * std::cos(u), 0.0);
      x.a_n = a_c * Vec3(std::sin(u), -std::cos(u), 0.0);
      x.yaw_rate = v_ / kRadius;
      yaw0 = std::numbers::pi + u;
    } else {
      const double w = s - kStraight1 - 2.0 * kArc - kStraight2;
      x.p_n = Vec3(-3.0 + w, 0.0, 0.0);
      yaw0 = 2.0 * std::numbers::pi;
    }
    x.yaw = yaw0 + 2.0 * std::numbers::pi * laps;
    x.v_n = v_ * Vec3(std::cos(x.yaw), std::sin(x.yaw), 0.0);
    return x;
  }

  /// A perfect IMU sample for the interval (t0, t1]: the rate that turns the yaw from t0 to
  /// t1 (exact: the rotation is about a fixed axis) and the specific force, in the body frame
  /// at the interval's middle yaw, of the mean acceleration Δv/Δt (exact in velocity; within
  /// a segment also in position up to O(Δψ²)). Where the interval straddles a segment
  /// boundary this is what an ideal integrating IMU would report, not an instant sample.
  ImuSample perfect_imu(double t0, double t1, double gravity_mps2) const {
    const Truth a = at(t0);
    const Truth b = at(t1);
    const double dt = t1 - t0;
    const Vec3 g_n(0.0, 0.0, gravity_mps2);
    const Quat q_mid(Eigen::AngleAxisd(0.5 * (a.yaw + b.yaw), Vec3::UnitZ()));
    ImuSample s;
    s.dt_s = dt;
    s.omega_b_radps = Vec3(0.0, 0.0, (b.yaw - a.yaw) / dt);
    s.f_b_mps2 = q_mid.conjugate() * ((b.v_n - a.v_n) / dt - g_n);
    return s;
  }

 private:
  double v_;
};

/// Sensor errors added to perfect data (white noise as densities, constant biases).
struct SensorErrors {
  Vec3 gyro_bias_b_radps = Vec3::Zero();   ///< [rad/s]
  Vec3 accel_bias_b_mps2 = Vec3::Zero();   ///< [m/s²]
  double gyro_noise_radps_rthz = 0.0;      ///< [rad/s/√Hz]
  double accel_noise_mps2_rthz = 0.0;      ///< [m/s²/√Hz]
  double mag_std_tesla = 0.0;              ///< per sample [T]
};

/// The perfect sample with biases and white noise, plus the magnetometer m̃_b = R_nbᵀ mⁿ + n
/// at t1 (zero when m_n is zero).
inline ImuSample noisy_imu(const ImuSample& perfect, const Quat& q_nb_t1, const Vec3& m_n,
                           const SensorErrors& e, Normal& n) {
  ImuSample s = perfect;
  const double rt = std::sqrt(perfect.dt_s);
  s.omega_b_radps += e.gyro_bias_b_radps + (e.gyro_noise_radps_rthz / rt) * n.vec3();
  s.f_b_mps2 += e.accel_bias_b_mps2 + (e.accel_noise_mps2_rthz / rt) * n.vec3();
  const Vec3 m_noise = e.mag_std_tesla * n.vec3();
  if (!m_n.isZero(0.0)) {
    s.m_b_tesla = q_nb_t1.conjugate() * m_n + m_noise;
  }
  return s;
}

/// Log of SO(3) of a unit quaternion, short path [rad].
inline Vec3 quat_log(const Quat& q_in) {
  const Quat q = q_in.w() < 0.0 ? Quat(-q_in.coeffs()) : q_in;
  const double s = q.vec().norm();
  if (s < 1e-15) {
    return 2.0 * q.vec();
  }
  return 2.0 * std::atan2(s, q.w()) * q.vec() / s;
}

/// ρ with q_true = Exp(ρ) ⊗ q_est: the NED attitude error [rad].
inline Vec3 attitude_error_n(const Quat& q_true, const Quat& q_est) {
  return quat_log(q_true * q_est.conjugate());
}

/// One simulated run of the stadium at 0.5 m/s, 100 Hz IMU, 1 Hz GPS: the initial state error
/// and the biases drawn from the filter's prior (so NEES is meaningful), white noise on every
/// sensor, GPS except during an outage (the fix is drawn either way, so the data do not
/// depend on the outage). noisy = false: perfect data and a perfect start.
class StadiumRun {
 public:
  static constexpr double kDt = 0.01;    ///< IMU period [s]
  static constexpr int kGpsEvery = 100;  ///< GPS at 1 Hz
  static constexpr double kSpeed = 0.5;  ///< [m/s]

  StadiumRun(std::uint64_t seed, const P1Params& params_in, bool noisy = true)
      : stadium_(kSpeed), noise_(seed), params_(params_in) {
    const Truth t0 = stadium_.at(0.0);
    if (!noisy) {
      params_.initial_p_n_m = t0.p_n;
      params_.initial_v_n_mps = t0.v_n;
      params_.initial_q_nb = t0.q_nb();
      return;
    }
    errors_.gyro_bias_b_radps = params_.initial_gyro_bias_std_radps * noise_.vec3();
    errors_.accel_bias_b_mps2 = params_.initial_accel_bias_std_mps2 * noise_.vec3();
    errors_.gyro_noise_radps_rthz = params_.gyro_noise_radps_rthz;
    errors_.accel_noise_mps2_rthz = params_.accel_noise_mps2_rthz;
    errors_.mag_std_tesla = params_.mag_std_tesla;
    // One draw per statement: the order of a call's arguments is unspecified (GCC takes them
    // last to first, clang first to last), and the tests' figures are from z, y, x.
    const double rho0_z = params_.initial_heading_std_rad * noise_();
    const double rho0_y = params_.initial_tilt_std_rad * noise_();
    const double rho0_x = params_.initial_tilt_std_rad * noise_();
    const Vec3 rho0(rho0_x, rho0_y, rho0_z);
    params_.initial_p_n_m = t0.p_n - params_.initial_position_std_m * noise_.vec3();
    params_.initial_v_n_mps = t0.v_n - params_.initial_velocity_std_mps * noise_.vec3();
    params_.initial_q_nb = (quat_exp(-rho0) * t0.q_nb()).normalized();  // q_true = Exp(ρ0) q̂
  }

  const P1Params& params() const { return params_; }
  const SensorErrors& errors() const { return errors_; }
  double time() const { return k_ * kDt; }
  Truth truth() const { return stadium_.at(time()); }

  /// One IMU sample to every navigator, then the GPS fix when one is due and gps_on.
  void step(std::initializer_list<P1Navigator*> navs, bool gps_on = true) {
    const double t0 = k_ * kDt;
    const double t1 = (k_ + 1) * kDt;
    const Truth x1 = stadium_.at(t1);
    const ImuSample s = noisy_imu(stadium_.perfect_imu(t0, t1, params_.gravity_mps2), x1.q_nb(),
                                  params_.mag_field_n_tesla, errors_, noise_);
    ++k_;
    const bool fix_due = k_ % kGpsEvery == 0;
    Vec3 fix = Vec3::Zero();
    if (fix_due) fix = x1.p_n + params_.gps_position_std_m * noise_.vec3();
    for (P1Navigator* nav : navs) {
      nav->on_imu(s);
      if (fix_due && gps_on) nav->on_gps_position(fix);
    }
  }
  void step(P1Navigator& nav, bool gps_on = true) { step({&nav}, gps_on); }

 private:
  Stadium stadium_;
  Normal noise_;
  P1Params params_;
  SensorErrors errors_;
  int k_ = 0;  ///< samples given so far
};

/// Position and attitude errors after the first 30 s, of one navigator.
struct Errors {
  double rms_per_axis = 0.0;  ///< [m]
  double worst_p = 0.0;       ///< [m]
  double worst_att = 0.0;     ///< [rad]
};

inline Errors run_stadium(StadiumRun& run, P1Navigator& nav, double until_s) {
  double sum_sq = 0.0;
  int n = 0;
  Errors e;
  while (run.time() < until_s) {
    run.step(nav);
    if (run.time() < 30.0) continue;
    const Truth x = run.truth();
    const P1Solution s = nav.solution();
    const double ep = (x.p_n - s.p_n).norm();
    sum_sq += ep * ep;
    ++n;
    e.worst_p = std::max(e.worst_p, ep);
    e.worst_att = std::max(e.worst_att, attitude_error_n(x.q_nb(), s.q_nb).norm());
  }
  e.rms_per_axis = std::sqrt(sum_sq / (3.0 * n));
  return e;
}

}  // namespace nav::estimator::testing

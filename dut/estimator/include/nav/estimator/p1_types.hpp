// SPDX-License-Identifier: MIT
// What the four navigators of paper P1 share: the IMU sample, the parameters, the solution and
// the navigator interface.
//
// Reference: Hwang, Lee, "Multi-filtered INS (MFINS): EKF for attitude, UPF for position",
// Trans. KIEE 60(12), 2011 (docs/papers.md, P1). The four navigators:
//   | name  | what                                                   | file              |
//   |-------|--------------------------------------------------------|-------------------|
//   | ins   | strapdown only, from the configured initial state      | p1_ins.hpp        |
//   | ekf15 | strapdown + 15-state error EKF, GPS δp and mag δmⁿ      | p1_ekf15.hpp      |
//   | upf15 | strapdown + 15-state unscented particle filter         | p1_upf15.hpp      |
//   | mfins | 9-state attitude EKF (p1_attitude_ekf.hpp) + 9-state    | p1_mfins.hpp      |
//   |       | position UPF [δp, δv, δa] (p1_position_upf.hpp)         |                   |
//
// Conventions (the whole project): n = local NED, flat and inertial (no Earth or transport
// rate), constant gravity g_n = (0, 0, +g); b = FRD; q_nb Hamilton, v_n = q_nb * v_b; the
// accelerometer measures the specific force f_b = R_nbᵀ (a_n − g_n) (level at rest:
// (0, 0, −g)). Time arrives only as ImuSample::dt_s.
//
// The paper gives no sensor rates or noise figures: every noise and initial uncertainty is a
// parameter; the defaults below are a MEMS-grade guess, not the paper's.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "nav/common/frames.hpp"
#include "nav/common/result.hpp"
#include "nav/estimator/update_report.hpp"

namespace nav::estimator {

/// One IMU sample; sensor frame = body frame (FRD). ω and f are taken as constant over the
/// interval that ends with the sample (strapdown.hpp, zero-order hold).
struct ImuSample {
  double dt_s = 0.0;                  ///< time since the previous sample, (0, max_dt_s] [s]
  Vec3 omega_b_radps = Vec3::Zero();  ///< angular rate ω̃_ib^b, body [rad/s]
  Vec3 f_b_mps2 = Vec3::Zero();       ///< specific force f̃_b, body [m/s²]
  /// Magnetic field m̃_b, body [T]. Exactly (0, 0, 0) means "no magnetometer reading in this
  /// sample" (a real field is never exactly zero): the magnetometer update is skipped.
  Vec3 m_b_tesla = Vec3::Zero();
};

/// True when every field of s is finite and 0 < dt_s ≤ max_dt_s.
bool is_valid(const ImuSample& s, double max_dt_s);

/// Parameters of the P1 navigators. Every quantity in SI; frames as stated.
struct P1Params {
  // --- initial state and environment ---
  Vec3 initial_p_n_m = Vec3::Zero();       ///< initial position, NED [m]
  Vec3 initial_v_n_mps = Vec3::Zero();     ///< initial velocity, NED [m/s]
  Quat initial_q_nb = Quat::Identity();    ///< initial attitude body→NED, unit norm [-]
  double gravity_mps2 = 9.80665;           ///< g of g_n = (0, 0, +g), NED [m/s²]
  /// Earth magnetic field mⁿ, NED [T] (the bench's default 20 µT North, 40 µT down); zero =
  /// no magnetometer update.
  Vec3 mag_field_n_tesla = Vec3(2.0e-5, 0.0, 4.0e-5);

  // --- IMU noise (continuous-time densities) ---
  double accel_noise_mps2_rthz = 2.0e-3;       ///< σ_a, velocity random walk [m/s²/√Hz]
  double gyro_noise_radps_rthz = 2.0e-4;       ///< σ_g, angle random walk [rad/s/√Hz]
  double accel_bias_walk_mps3_rthz = 1.0e-4;   ///< σ_ba, accel bias random walk [m/s³/√Hz]
  double gyro_bias_walk_radps2_rthz = 1.0e-5;  ///< σ_bg, gyro bias random walk [rad/s²/√Hz]

  // --- initial standard deviations of the error-state blocks ---
  double initial_position_std_m = 0.5;         ///< δp per axis, NED [m]
  double initial_velocity_std_mps = 0.1;       ///< δv per axis, NED [m/s]
  double initial_tilt_std_rad = 0.05;          ///< ε_N, ε_E (NED) [rad]
  double initial_heading_std_rad = 0.2;        ///< ε_D (NED) [rad]
  double initial_accel_bias_std_mps2 = 0.05;   ///< δb_acc per axis, body [m/s²]
  double initial_gyro_bias_std_radps = 5.0e-3; ///< δb_gyro per axis, body [rad/s]

  // --- measurements ---
  double gps_position_std_m = 0.2;        ///< GPS position per NED axis [m]
  double mag_std_tesla = 2.0e-7;          ///< magnetometer per body axis [T]
  /// δgⁿ of MFINS per NED axis: accelerometer white noise at the sample rate (σ_a/√dt) plus
  /// the error of the motion acceleration given to it [m/s²].
  double gravity_std_mps2 = 0.05;
  double gps_gate_nis = 0.0;      ///< χ² gate on the GPS NIS (3 dof); 0 = off [-]
  double mag_gate_nis = 0.0;      ///< χ² gate on the magnetometer NIS (3 dof); 0 = off [-]
  double gravity_gate_nis = 0.0;  ///< χ² gate on the δgⁿ NIS (3 dof); 0 = off [-]
  double max_dt_s = 1.0;          ///< an IMU interval above this is refused as invalid [s]

  // --- particle filters (upf15, mfins) ---
  int particle_count = 50;               ///< particles n, 1 .. kMaxParticles [-]
  /// Most particles validate() allows: 100 000 take about 0.4 GB (a state and two covariances
  /// each, 15 states) and tens of ms per IMU step; the paper's most is 250.
  static constexpr int kMaxParticles = 100000;
  std::uint64_t seed = 1;                ///< seed of the filter's own RNG [-]
  double resample_ess_fraction = 0.5;    ///< resample when ESS < this × n, (0, 1] [-]

  /// g_n = (0, 0, +g), NED [m/s²].
  Vec3 gravity_n() const { return Vec3(0.0, 0.0, gravity_mps2); }
};

/// Checks P1Params; the error names the first bad field and its value.
Result<void> validate(const P1Params& p);

/// A P1 navigator's current estimate, as navd's $PNVB sentences want it.
struct P1Solution {
  bool valid = false;                  ///< an estimate exists
  Quat q_nb = Quat::Identity();        ///< attitude body→NED
  Vec3 p_n = Vec3::Zero();             ///< position, NED [m]
  Vec3 v_n = Vec3::Zero();             ///< velocity, NED [m/s]
  Mat3 P_position_n = Mat3::Zero();    ///< covariance of p_n, NED [m²]
  /// Covariance of the attitude error as the NED rotation vector δθ of R_true R̂ᵀ
  /// (R_true = Exp([δθ]×) R̂), as $PNVBCOV wants [rad²].
  Mat3 P_attitude_n = Mat3::Zero();
  bool has_covariance = false;         ///< the two covariances are meaningful
};

/// Counters of a P1 navigator, for navd's exit summary and tests.
struct P1Stats {
  std::uint64_t imu_samples = 0;           ///< on_imu() calls
  std::uint64_t imu_rejected_invalid = 0;  ///< samples with NaN/Inf or dt ∉ (0, max_dt_s]
  std::uint64_t gps_fused = 0;             ///< GPS position updates fused
  std::uint64_t gps_rejected_invalid = 0;  ///< GPS fixes with NaN/Inf
  std::uint64_t gps_rejected_gate = 0;     ///< GPS updates above their NIS gate
  std::uint64_t mag_fused = 0;             ///< magnetometer updates fused
  std::uint64_t mag_rejected_gate = 0;     ///< magnetometer updates above their NIS gate
  std::uint64_t gravity_fused = 0;         ///< δgⁿ updates fused (mfins)
  std::uint64_t gravity_rejected_gate = 0; ///< δgⁿ updates above their NIS gate (mfins)
  std::uint64_t numerical_faults = 0;      ///< updates or steps refused for numerical health
};

/// The interface of the four P1 navigators. Pure math: no I/O, no clocks, never throws on
/// data. NaN/Inf input is refused (state untouched) and counted.
class P1Navigator {
 public:
  virtual ~P1Navigator() = default;

  /// Propagates over sample.dt_s (and makes the IMU-rate updates of the navigator).
  virtual void on_imu(const ImuSample& sample) = 0;
  /// A GPS position fix p̃_n, NED [m], valid at the time of the last IMU sample.
  virtual void on_gps_position(const Vec3& p_n_measured_m) = 0;
  /// The current estimate.
  virtual P1Solution solution() const = 0;
  /// The configuration name: "ins", "ekf15", "upf15", "mfins".
  virtual std::string_view name() const = 0;

  /// The measurement updates of the last on_imu() or on_gps_position() call, for $PNVBINN
  /// ("gps-position" [m], "mag" [T], "gravity" [m/s²]); empty when it made none.
  const std::vector<Innovation>& innovations() const { return innovations_; }
  /// Counters so far.
  const P1Stats& stats() const { return stats_; }

 protected:
  /// Reserves the innovation list once, so no step allocates.
  P1Navigator() { innovations_.reserve(kMaxInnovationsPerCall); }
  static constexpr std::size_t kMaxInnovationsPerCall = 4;
  std::vector<Innovation> innovations_;
  P1Stats stats_;
};

}  // namespace nav::estimator

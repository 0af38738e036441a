// SPDX-License-Identifier: MIT
// Paper P4's sea-surface beacon filter: a planar INS driven by the (DWT de-noised) horizontal
// specific force and the yaw rate, corrected by GPS RMC position, the magnetic compass and,
// optionally, RMC speed/course, in an unscented Kalman filter.
//
// Reference: [P4] Yoon, Yoon, Choi, Lee, J. Institute of Control, Robotics and Systems 19(3),
// 2013 (docs: papers.md "P4"). The paper prints the unscented transform but not its state
// vector, process model or noise values; the planar model below is this file's (decided, as
// papers.md suggests). Equation labels B1..B11 are this file's own; U1..U13 are unscented.hpp's.
//
// State x (n = 6), local NED tangent plane at the scenario datum:
//   | symbol | meaning                                   | frame | unit  | index           |
//   | N      | north position of the beacon              | NED   | m     | P4Idx::kN    0  |
//   | E      | east position                             | NED   | m     | P4Idx::kE    1  |
//   | v_N    | north velocity                            | NED   | m/s   | P4Idx::kVn   2  |
//   | v_E    | east velocity                             | NED   | m/s   | P4Idx::kVe   3  |
//   | ψ      | heading of body x (0 = North, + to East)  | NED   | rad   | P4Idx::kPsi  4  |
//   | b_gz   | yaw-gyro bias                             | body  | rad/s | P4Idx::kBgz  5  |
// ψ is kept continuous (unwrapped) in x: sigma points around ±π are then ordinary numbers and
// their weighted mean is the right one; only heading() wraps, to [0, 2π). (After a day of
// 3°/s turning ψ is ~4500 rad, where a double still resolves ~10⁻¹² rad.)
//
// Input u (the beacon INS, papers.md "Hardware"): f_x, f_y specific force along body x (the
// direction of travel) and y (starboard) [m/s²], de-noised by dwt_denoiser.hpp in the DUT or
// raw; ω_z the yaw gyro [rad/s]; dt the step [s].
// Level assumption: the beacon has gyros on yaw and pitch only. Without a roll gyro (or an
// attitude reference aiding both tilts) the tilt cannot be estimated, and pitch alone cannot
// build an attitude, so the pitch gyro is not used: the model takes the beacon as level. The
// error this makes is the wave tilt leaking gravity into f_x, f_y (g sin θ ≈ 0.85 m/s² per 5°),
// oscillating at the wave frequency (0.19 Hz in [P4]'s experiment; the level-1 DWT does not
// remove it, papers.md P4 traps). It is zero-mean and bounded, so it is carried as extra white
// acceleration noise: accel_noise_density_mps2_rthz defaults well above the sensor's own noise.
//
// Process model, discrete, accelerations held over the step (B1..B5):
//   B1  a_N = cos ψ f_x − sin ψ f_y
//   B2  a_E = sin ψ f_x + cos ψ f_y
//   B3  N⁺ = N + v_N dt + ½ a_N dt²;    E⁺ = E + v_E dt + ½ a_E dt²
//   B4  v_N⁺ = v_N + a_N dt;            v_E⁺ = v_E + a_E dt
//   B5  ψ⁺ = ψ + (ω_z − b_gz) dt;       b_gz⁺ = b_gz (random walk)
// Additive process noise Q (B6, B7) from continuous white-noise densities, each block the exact
// covariance that the noise integrated over dt adds (Van Loan for the linear sub-chains):
//   B6  per horizontal axis (N, v_N) and (E, v_E), acceleration noise of density q_a
//       [m/s²/√Hz] (the continuous white-noise-acceleration block):
//         Q_pv = q_a² [dt³/3  dt²/2; dt²/2  dt];  the two axes independent (the horizontal
//       noise is isotropic, so rotating it by ψ changes nothing)
//   B7  (ψ, b_gz): gyro white noise q_g [rad/s/√Hz], bias walk q_b [rad/s/√s]:
//         Q_ψb = [q_g² dt + q_b² dt³/3   −q_b² dt²/2;  −q_b² dt²/2   q_b² dt]
// Measurements z = h(x) + v, v ~ N(0, R), each its own update (UKF U9..U13):
//   B8  GPS position (RMC lat/lon → N, E by the caller):  h = [N, E],  R = σ_p² I₂
//   B9  compass heading ψ_c (magnetic + declination, by the caller):  h = ψ,  R = σ_c²;
//       the innovation is wrapped by passing the UKF z′ = ψ̂ + wrap_pi(ψ_c − ψ̂), where ψ̂ = x_ψ
//       is also the UT's predicted ẑ (h is linear and the sigma points are symmetric, U9), so
//       y = z′ − ẑ = wrap_pi(ψ_c − ψ̂) ∈ (−π, π]: 359° against 1° is −2°, not 358°
//   B10 RMC speed/course (optional):  z = SOG [cos COG, sin COG],  h = [v_N, v_E],  R = σ_v² I₂.
//       Fused in Cartesian form: at low speed COG is noise but SOG·(cos, sin) COG is not, so no
//       speed-dependent R is needed. COG is the track, not ψ: sideslip is allowed (f_y).
// Initialisation from the first fix and compass heading (B11):
//   B11 x₀ = [N, E, 0, 0, wrap_pi(ψ_c), 0];
//       P₀ = diag(σ_p0², σ_p0², σ_v0², σ_v0², σ_ψ0², σ_b0²)
//
// Unscented transform. [P4] prints χ₁ = x_m, χ_{i+1} = x_m + u_i, χ_{i+n+1} = x_m − u_i with
// Uᵀ U = (n + κ) P, W₁ = κ/(n+κ), W_{i>1} = 1/(2(n+κ)) (the printed k/(2(n+k)) is a typo:
// the weights must sum to one). That is unscented.hpp's U1..U3 with α = 1, β = 0 and the
// paper's κ: then λ = κ, γ = √(n + κ), W₀⁽ᵐ⁾ = W₀⁽ᶜ⁾ = κ/(n+κ), W_j = 1/(2(n+κ)); the rows u_i
// of U = γ Lᵀ are the columns γ L_i of U2 (P = L Lᵀ), so the points are the same. This file
// reuses unscented.hpp's ukf_predict / ukf_update; it is the model, not a second UKF.
// κ: [P4] does not print it. Default κ = 0 (decided): W₁ = 0, W_{i>1} = 1/12, points at
// ±√6 σ. Julier's κ = 3 − n = −3 would match the Gaussian kurtosis but gives W₁ = −1 and, with
// β = 0, a centre covariance weight of −1 that can make P⁻ indefinite; κ = 0 is the smallest κ
// with no negative weight, so it is the closest to n + κ = 3 that keeps P⁻ a sum of outer
// products plus Q (positive definite). κ ∈ (−n, 0) is accepted (validate) but not advised.
//
// Numerical health (style.md): predict returns StepStatus, each update an UpdateReport; they
// never throw. Non-finite inputs, dt <= 0 or dt > max_dt_s, and any call before initialise()
// are refused (kRejectedInvalid), the state untouched. A predict whose sigma points cannot be
// drawn (P not positive definite) or whose result is not finite is also refused, counted in
// numerical_faults() and its cause kept in last_predict_status(). Pure: no I/O, no clock.
#pragma once

#include <Eigen/Core>

#include "nav/common/result.hpp"
#include "nav/estimator/unscented.hpp"
#include "nav/estimator/update_report.hpp"

namespace nav::estimator {

/// Named indices of the P4 state (file comment's state table).
struct P4Idx {
  static constexpr int kN = 0;    ///< north position [m]
  static constexpr int kE = 1;    ///< east position [m]
  static constexpr int kVn = 2;   ///< north velocity [m/s]
  static constexpr int kVe = 3;   ///< east velocity [m/s]
  static constexpr int kPsi = 4;  ///< heading, continuous (unwrapped) [rad]
  static constexpr int kBgz = 5;  ///< yaw-gyro bias [rad/s]
  static constexpr int kPos = kN;  ///< first index of the 2-D position slice [N, E]
  static constexpr int kVel = kVn; ///< first index of the 2-D velocity slice [v_N, v_E]
  static constexpr int kDim = 6;   ///< n
};

using P4Vec = Vec<P4Idx::kDim>;              ///< x
using P4Mat = Mat<P4Idx::kDim, P4Idx::kDim>;  ///< P, Q

/// One INS sample, the beacon taken as level (file comment).
struct P4Input {
  double f_x_mps2 = 0.0;      ///< specific force along body x (direction of travel) [m/s²]
  double f_y_mps2 = 0.0;      ///< specific force along body y (starboard) [m/s²]
  double omega_z_radps = 0.0; ///< yaw rate from the yaw gyro, body z (down) [rad/s]
};

/// Every number of the P4 filter. Defaults are this file's choices; [P4] prints none.
struct P4UkfParams {
  /// κ of the paper's unscented transform (α = 1, β = 0); n + κ > 0. 0: no negative weight
  /// (file comment) [-].
  double kappa = 0.0;
  /// q_a, horizontal acceleration white noise (B6): about ten times a MEMS accelerometer's
  /// own noise, to cover the level assumption's wave-tilt error [m/s²/√Hz].
  double accel_noise_density_mps2_rthz = 0.1;
  /// q_g, yaw-gyro white noise (B7), angle random walk; of the order of a MEMS rate gyro's
  /// (≈ 0.05 °/s/√Hz) [rad/s/√Hz].
  double gyro_noise_density_radps_rthz = 1.0e-3;
  /// q_b, yaw-gyro bias random walk (B7) [rad/s/√s].
  double gyro_bias_walk_radps_rtsec = 1.0e-4;
  /// σ_p, GPS position noise per horizontal axis (B8); RMC carries no accuracy [m].
  double gps_position_std_m = 3.0;
  /// σ_c, compass heading noise (B9), 2° [rad].
  double compass_std_rad = 0.03490658503988659;
  /// σ_v, RMC velocity noise per horizontal axis (B10) [m/s].
  double gps_velocity_std_mps = 0.2;
  /// NIS gate of the GPS position update; 0 = none (chi² 2 dof, e.g. 13.8 at 99.9 %) [-].
  double gps_position_gate_nis = 0.0;
  /// NIS gate of the compass update; 0 = none (chi² 1 dof, e.g. 10.8 at 99.9 %) [-].
  double compass_gate_nis = 0.0;
  /// NIS gate of the RMC velocity update; 0 = none [-].
  double gps_velocity_gate_nis = 0.0;
  /// σ_p0, initial position σ per axis (B11): one GPS fix [m].
  double initial_position_std_m = 3.0;
  /// σ_v0, initial velocity σ per axis (B11): drifting or under thrust, unknown [m/s].
  double initial_velocity_std_mps = 1.0;
  /// σ_ψ0, initial heading σ (B11): one compass reading, 5° [rad].
  double initial_heading_std_rad = 0.08726646259971647;
  /// σ_b0, initial yaw-gyro bias σ (B11), ~1 °/s [rad/s].
  double initial_gyro_bias_std_radps = 0.02;
  /// Longest accepted predict step; longer ones are refused as a gap [s].
  double max_dt_s = 10.0;
};

/// Checks every field of p: finite; κ > −n; noise densities, σ's and max_dt_s > 0; gates >= 0.
/// The error names the field and its value.
Result<void> validate(const P4UkfParams& p);

/// The paper's unscented-transform parameters for κ: α = 1, β = 0 (file comment).
constexpr UnscentedParams p4_unscented_params(double kappa) { return {1.0, 0.0, kappa}; }

/// B1..B5: x⁺ = f(x, u, dt). No checks.
P4Vec p4_process(const P4Vec& x, const P4Input& u, double dt_s);

/// B6, B7: the additive process noise Q of one step dt [s].
P4Mat p4_process_noise(const P4UkfParams& p, double dt_s);

/// B10's z: RMC speed over ground [m/s] and course over ground (true, from North towards East)
/// [rad] as the NED velocity [v_N, v_E] [m/s].
Eigen::Vector2d rmc_velocity_ne(double sog_mps, double cog_rad);

/// Wraps an angle to [0, 2π) [rad].
double wrap_two_pi(double a_rad);

/// The P4 planar beacon UKF (file comment).
class P4BeaconUkf {
 public:
  static constexpr int kN = P4Idx::kDim;  ///< n

  /// params must pass validate() (contract, NAV_ENSURE). Not initialised: every predict and
  /// update is refused until initialise() or reset().
  explicit P4BeaconUkf(const P4UkfParams& params);

  /// B11 from the first GPS fix [N, E] [m] and compass heading [rad] (any range). Non-finite
  /// input → kRejectedInvalid, nothing changed.
  StepStatus initialise(const Eigen::Vector2d& position_ne_m, double heading_rad);
  /// Sets x, P directly. Non-finite x or P, or P not symmetric positive definite →
  /// kRejectedInvalid, nothing changed.
  StepStatus reset(const P4Vec& x0, const P4Mat& P0);
  /// True once initialise() or reset() succeeded.
  bool initialised() const { return initialised_; }

  /// B1..B7 through ukf_predict (U7, U8). Refused (state untouched): not initialised,
  /// non-finite u or dt, dt <= 0, dt > max_dt_s, or a numerical fault (counted).
  StepStatus predict(const P4Input& u, double dt_s);

  /// B8: GPS position [N, E] [m], R = σ_p² I₂, gate gps_position_gate_nis.
  UpdateReport<2> update_gps_position(const Eigen::Vector2d& z_ne_m);
  /// B9: compass heading [rad], any range (normally [0, 2π)); y is wrapped to (−π, π].
  UpdateReport<1> update_compass(double heading_rad);
  /// B10: RMC velocity [v_N, v_E] [m/s] (rmc_velocity_ne()), R = σ_v² I₂.
  UpdateReport<2> update_gps_velocity(const Eigen::Vector2d& z_ne_mps);

  const P4Vec& x() const { return x_; }  ///< state, ψ continuous (P4Idx)
  const P4Mat& P() const { return P_; }  ///< state covariance
  /// [N, E], NED [m].
  Eigen::Vector2d position_ne() const { return x_.segment<2>(P4Idx::kPos); }
  /// [v_N, v_E], NED [m/s].
  Eigen::Vector2d velocity_ne() const { return x_.segment<2>(P4Idx::kVel); }
  /// ψ wrapped to [0, 2π) [rad].
  double heading() const { return wrap_two_pi(x_(P4Idx::kPsi)); }
  /// b_gz [rad/s].
  double gyro_bias() const { return x_(P4Idx::kBgz); }
  /// 2×2 covariance of [N, E] for $PNVBCOV [m²].
  Eigen::Matrix2d position_covariance_ne() const {
    return P_.block<2, 2>(P4Idx::kPos, P4Idx::kPos);
  }
  /// The UT weights in use (U3 with α = 1, β = 0, κ).
  const UnscentedWeights<kN>& weights() const { return weights_; }
  const P4UkfParams& params() const { return params_; }
  /// Predicts refused for a numerical fault since construction.
  int numerical_faults() const { return numerical_faults_; }
  /// Outcome of the unscented transform of the last predict that reached it (kOk before any).
  UnscentedStatus last_predict_status() const { return last_predict_; }

 private:
  template <int M, class H>
  UpdateReport<M> update(H&& h, const Vec<M>& z, const Mat<M, M>& R, double gate);

  P4UkfParams params_;
  UnscentedWeights<kN> weights_;
  P4Vec x_ = P4Vec::Zero();
  P4Mat P_ = P4Mat::Identity();
  bool initialised_ = false;
  int numerical_faults_ = 0;
  UnscentedStatus last_predict_ = UnscentedStatus::kOk;
};

}  // namespace nav::estimator

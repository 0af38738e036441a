// SPDX-License-Identifier: MIT
// Paper P0's four attitude sources on the Euler-angle state X = (φ, θ, ψ):
//   "no filtering" (eqs 1-4), the EKF (Table 1), the UKF (Table 2) and the PI complementary
//   filter (Table 3), with the parameters of Tables 6, 7 and 8.
//
// Reference: Jeong, Ko, Choi, "Attitude estimation for DVL navigation of a UUV using
// EKF/UKF/CF", J. Korea Robotics Society 9(4), 2014, restated in papers.md P0. Equation and
// table numbers below are the paper's.
//
// Naming: the paper calls the *process* noise R and the *measurement* noise Q, the reverse of
// the usual names. This code uses `process_noise` and `measurement_noise` throughout; the
// comment next to each default says which of the paper's letters it is.
//
// Measurement (eqs 1-4), f_b specific force (level at rest: (0, 0, −g)), m_b field, FRD:
//   (1) φ = atan2(−f_y, −f_z)
//   (2) θ = atan2(f_x, √(f_y² + f_z²))
//   (3) m_l = Ry(θ) Rx(φ) m_b          field levelled by roll and pitch only
//   (4) ψ = atan2(−m_l,y, m_l,x) − ψ0,  ψ0 = −(magnetic declination)  (papers.md: the scan's
//       m_z denominator is read as the levelled x component; ψ0 = 0 in the paper)
// Kinematics used by all three filters (K):
//   φ̇ = p + q sinφ tanθ + r cosφ tanθ;  θ̇ = q cosφ − r sinφ;  ψ̇ = (q sinφ + r cosφ)/cosθ
// Singularity: cos θ is clamped to ±kMinCosPitch (keeping its sign) wherever the kinematics or
// their Jacobian divide by it; a step that needed the clamp returns kSingular. After every step
// the state is normalised to θ ∈ [−π/2, π/2], φ, ψ ∈ (−π, π] (the same rotation:
// (φ, θ, ψ) ≡ (φ + π, π − θ, ψ + π)).
#pragma once

#include <optional>

#include "nav/common/frames.hpp"
#include "nav/estimator/attitude_filter.hpp"
#include "nav/estimator/linear_kf.hpp"

namespace nav::estimator::p0 {

/// Euler state X = (φ, θ, ψ) [rad].
using EulerState = Vec<3>;

/// |cos θ| below this is clamped in the Euler-rate kinematics (θ within ~0.5° of ±90°) [-].
inline constexpr double kMinCosPitch = 8.7e-3;

/// Attitude from accelerometer and magnetometer, eqs (1)-(4). nullopt when an input is not
/// finite or f_b is zero. A field without a horizontal component after levelling gives
/// ψ = declination. declination_rad: east positive (true = magnetic + declination).
std::optional<EulerState> attitude_from_accel_mag(const Vec3& f_b_mps2, const Vec3& m_b,
                                                  double declination_rad);

/// Euler-angle rates Ẋ (K) at X for body rate ω [rad/s]. `clamped` (optional) is set when
/// cos θ had to be clamped.
EulerState euler_rates(const EulerState& x, const Vec3& omega_b_radps,
                       bool* clamped = nullptr);

/// ∂Ẋ/∂X of euler_rates at X, ω (with the same clamp).
Mat<3, 3> euler_rates_jacobian(const EulerState& x, const Vec3& omega_b_radps);

/// ∂δθ/∂X at X: how a small change of the Euler state moves the attitude, as the NED
/// rotation vector δθ of R(X + δX) R(X)ᵀ (attitude_filter.hpp). With R = Rz(ψ) Ry(θ) Rx(φ),
/// dR Rᵀ = [ẑ dψ + Rz(ψ) ŷ dθ + Rz(ψ) Ry(θ) x̂ dφ]×, so the columns (φ, θ, ψ) are
/// (cψ cθ, sψ cθ, −sθ), (−sψ, cψ, 0), (0, 0, 1). The Euler filters state their P on X; the
/// contract's covariance is J P Jᵀ (first order).
Mat3 rotation_vector_jacobian(const EulerState& x);

/// The prediction step X⁻ = X + Ẋ Δt shared by the three filters (Table 1 line 1).
EulerState predict_euler(const EulerState& x, const Vec3& omega_b_radps, double dt_s,
                         bool* clamped = nullptr);

/// A = ∂X⁻/∂X = I + Δt ∂Ẋ/∂X (Table 1).
Mat<3, 3> predict_euler_jacobian(const EulerState& x, const Vec3& omega_b_radps, double dt_s);

/// (φ, θ, ψ) normalised to θ ∈ [−π/2, π/2], φ, ψ ∈ (−π, π] (the same rotation).
EulerState normalise_euler(const EulerState& x);

/// Parameters of the EKF, defaults from Table 6 (X0 = 0).
struct EkfParams {
  /// P0 = diag(0.15, 0.15, 0.15) [rad²].
  Mat<3, 3> initial_covariance = Vec<3>::Constant(0.15).asDiagonal();
  /// The paper's R (process noise): [[0.1, 0.08, 0.08], [0.08, 0.1, 0.08], [0.08, 0.08, 0.1]].
  Mat<3, 3> process_noise = (Mat<3, 3>() << 0.1, 0.08, 0.08, 0.08, 0.1, 0.08, 0.08, 0.08, 0.1)
                                .finished();
  /// The paper's Q (measurement noise). Not legible in the scan; papers.md's positive-definite
  /// matrix of the described form: [[0.15, 0.08, 0.08], [0.08, 0.15, 0.1], [0.08, 0.1, 0.2]].
  Mat<3, 3> measurement_noise =
      (Mat<3, 3>() << 0.15, 0.08, 0.08, 0.08, 0.15, 0.1, 0.08, 0.1, 0.2).finished();
};

/// Parameters of the UKF, defaults from Table 7 (X0 = 0).
struct UkfParams {
  double kappa = 1.7;  ///< κ; w0 = κ/(n+κ), w = 1/(2(n+κ)), n = 3
  /// P0 = diag(0.15, 0.15, 0.15) [rad²].
  Mat<3, 3> initial_covariance = Vec<3>::Constant(0.15).asDiagonal();
  /// The paper's R (process noise): [[0.2, 0.02, 0.02], [0.02, 0.2, 0.02], [0.02, 0.02, 0.15]].
  Mat<3, 3> process_noise =
      (Mat<3, 3>() << 0.2, 0.02, 0.02, 0.02, 0.2, 0.02, 0.02, 0.02, 0.15).finished();
  /// The paper's Q (measurement noise), reconstructed:
  /// [[0.1, 0.07, 0.07], [0.07, 0.1, 0.07], [0.07, 0.07, 0.2]].
  Mat<3, 3> measurement_noise =
      (Mat<3, 3>() << 0.1, 0.07, 0.07, 0.07, 0.1, 0.07, 0.07, 0.07, 0.2).finished();
};

/// Parameters of the PI complementary filter, defaults from Table 8 (b̂0 = Δ0 = 0, X0 = 0).
struct CfParams {
  double kp = 4.35 * 1.4142135623730951;  ///< k_p = 4.35·√2 [1/s]
  double ki = 0.415;                      ///< k_i [1/s²]
};

/// "No filtering": X = the measurement of eqs (1)-(4) at every sample; the gyro is unused.
class RawAttitude final : public AttitudeFilter {
 public:
  explicit RawAttitude(double declination_rad);
  bool initialise(const Vec3& f_b_mps2, const Vec3& m_b_tesla) override;
  AttitudeStatus step(const AttitudeInput& in) override;
  Quat q_nb() const override;
  AttitudeFilterKind kind() const override { return AttitudeFilterKind::kRaw; }
  const EulerState& state() const { return x_; }

 private:
  double declination_rad_;
  EulerState x_ = EulerState::Zero();
};

/// Euler-angle EKF, Table 1:
///   X⁻ = X + Ẋ Δt;  A = I + Δt ∂Ẋ/∂X;  P⁻ = A P Aᵀ + R(process)
///   K = P⁻ Hᵀ (H P⁻ Hᵀ + Q(measurement))⁻¹ (an LDLᵀ solve, never an inverse), H = I₃
///   X = X⁻ + K wrap(z − X⁻);  P in Joseph form (I − KH) P⁻ (I − KH)ᵀ + K Q Kᵀ, which equals
///   the paper's P⁻ − K H P⁻ in exact arithmetic and stays symmetric positive definite.
/// A failed update (innovation covariance not PD, non-finite result) leaves X⁻, P⁻ and
/// returns kNumericalFault.
class EulerEkf final : public AttitudeFilter {
 public:
  EulerEkf(const EkfParams& params, double declination_rad);
  /// X0 = 0, P0 (Table 6): the measurement is not used to initialise, only checked usable.
  bool initialise(const Vec3& f_b_mps2, const Vec3& m_b_tesla) override;
  AttitudeStatus step(const AttitudeInput& in) override;
  Quat q_nb() const override;
  AttitudeFilterKind kind() const override { return AttitudeFilterKind::kEkf; }
  const EulerState& state() const { return x_; }
  const Mat<3, 3>& covariance() const { return P_; }
  /// J P Jᵀ, J = rotation_vector_jacobian(X).
  std::optional<Mat3> attitude_covariance_n() const override;

 private:
  EkfParams params_;
  double declination_rad_;
  EulerState x_ = EulerState::Zero();
  Mat<3, 3> P_;
};

/// Euler-angle UKF, Table 2 (n = 3, κ):
///   U = chol((n+κ) P);  X₀ = X, X_j = X + U_j, X_{n+j} = X − U_j  (U_j the j-th column)
///   propagate each sigma point with predict_euler; X⁻ = Σ w_i X_i (angles averaged as
///   w-weighted wrapped offsets from X₀'s image); P⁻ = Σ w_i (X_i − X⁻)(X_i − X⁻)ᵀ + R(process)
///   hz_i = X_i (identity measurement); ẑ = Σ w_i hz_i; P_z = Σ w_i (hz_i − ẑ)(…)ᵀ + Q(meas.)
///   P_xz = Σ w_i (X_i − X⁻)(hz_i − ẑ)ᵀ;  K = P_xz P_z⁻¹ (LDLᵀ solve)
///   X = X⁻ + K wrap(z − ẑ);  P = P⁻ − K P_z Kᵀ, then symmetrised.
/// Cholesky failure (the paper's warning: (n+κ)P not positive definite) or a non-PD P_z or
/// a P that is not PD after the update: the step returns kNumericalFault and recovers by
/// resetting P to the initial covariance (X kept), then runs the step with it. Never aborts.
class EulerUkf final : public AttitudeFilter {
 public:
  EulerUkf(const UkfParams& params, double declination_rad);
  /// X0 = 0, P0 (Table 7).
  bool initialise(const Vec3& f_b_mps2, const Vec3& m_b_tesla) override;
  AttitudeStatus step(const AttitudeInput& in) override;
  Quat q_nb() const override;
  AttitudeFilterKind kind() const override { return AttitudeFilterKind::kUkf; }
  const EulerState& state() const { return x_; }
  const Mat<3, 3>& covariance() const { return P_; }
  /// J P Jᵀ, J = rotation_vector_jacobian(X).
  std::optional<Mat3> attitude_covariance_n() const override;
  /// Overwrites the covariance (tests use it to provoke a Cholesky failure).
  void set_covariance(const Mat<3, 3>& P) { P_ = P; }

 private:
  UkfParams params_;
  double declination_rad_;
  EulerState x_ = EulerState::Zero();
  Mat<3, 3> P_;
};

/// PI complementary filter in velocity form, Table 3:
///   1. Ẋ from the kinematics at X_{k−1}
///   2. X_k = X_{k−1} + (Ẋ − b̂_{k−1}) Δt
///   3. Δ_k = wrap(X_k − z_k)
///   4. b̂_k = b̂_{k−1} − k_p Δ_{k−1} + (k_p + k_i Δt) Δ_k
class EulerCf final : public AttitudeFilter {
 public:
  EulerCf(const CfParams& params, double declination_rad);
  /// X0 = 0, b̂0 = Δ0 = 0 (Table 8).
  bool initialise(const Vec3& f_b_mps2, const Vec3& m_b_tesla) override;
  AttitudeStatus step(const AttitudeInput& in) override;
  Quat q_nb() const override;
  AttitudeFilterKind kind() const override { return AttitudeFilterKind::kCf; }
  const EulerState& state() const { return x_; }
  const EulerState& correction() const { return b_; }  ///< b̂ [rad/s]
  const EulerState& last_error() const { return delta_; }  ///< Δ_k [rad]

 private:
  CfParams params_;
  double declination_rad_;
  EulerState x_ = EulerState::Zero();
  EulerState b_ = EulerState::Zero();
  EulerState delta_ = EulerState::Zero();
};

/// q_nb of a ZYX Euler state.
Quat quat_from_state(const EulerState& x);

}  // namespace nav::estimator::p0

// SPDX-License-Identifier: MIT
// Navigator "ekf15" of paper P1: nominal strapdown INS + 15-state error-state EKF, closed loop.
//
// Reference: Hwang, Lee, Trans. KIEE 60(12), 2011, §3 (docs/papers.md, P1, "Aided INS
// baseline"); the model (state table, E1..E11) is p1_error_model.hpp, the update algorithm
// linear_kf.hpp (K3..K7: LDLᵀ solve of S, Joseph form). Labels B1..B5 are this file's own.
//
// Processing:
//   B1  on_imu: refuse invalid input (counted, state untouched); predict the nominal and P
//       (P1ErrorModel::predict: E2..E4 + strapdown S1..S4), every sample.
//   B2  then, when the sample carries a field (m̃_b ≠ 0) and mⁿ ≠ 0: the magnetometer update
//       z = δmⁿ = R̂_nb m̃_b − mⁿ, H_m = [0 0 [mⁿ]× 0 0], R = σ_m² I (E6, E7), at the
//       magnetometer's own rate (every sample that carries one; not decimated here: a bench
//       that wants a slower magnetometer sends zeros in between), NIS gate mag_gate_nis.
//   B3  on_gps_position: z = p̃_n − p̂_n, H = [I 0 0 0 0], R = σ_p² I (E5), applied at once
//       (the fix is taken as valid at the last IMU sample), NIS gate gps_gate_nis.
//   B4  after each fused update: δx̂ = K z (δx = 0 before), injected into the nominal and
//       the biases, δx̂ ← 0, P ← G_r P G_rᵀ (E10, E11) — the closed loop keeps δx small so the
//       linearisation holds. P is symmetrised after every prediction and update (Joseph
//       form keeps it PSD for any K).
//   B5  solution: P_position_n = P_δpδp; P_attitude_n = P_ρρ directly, because ρ is already
//       the NED rotation vector of R_true R̂ᵀ that $PNVBCOV wants (p1_error_model.hpp).
// The magnetometer update is the paper's 3-D δmⁿ: it corrects every component of ρ across mⁿ,
// tilt included (unlike quat_eskf.hpp's heading-only field update), so a disturbed field
// tilts the estimate; mag_gate_nis can refuse such samples. Nothing here assumes that aiding
// improves the attitude: in the paper's own table "INS only" has the lower attitude error
// (papers.md, P1 traps).
// A failed factorisation or a non-finite result skips that update (state untouched) and is
// counted in numerical_faults; nothing throws on data. No allocation per step.
#pragma once

#include "nav/estimator/p1_error_model.hpp"
#include "nav/estimator/p1_types.hpp"
#include "nav/estimator/strapdown.hpp"
#include "nav/estimator/update_report.hpp"

namespace nav::estimator {

/// Strapdown + 15-state error EKF (file comment).
class P1Ekf15 final : public P1Navigator {
 public:
  static constexpr int kN = P1ErrorModel::kN;  ///< error-state dimension

  /// params must pass validate() (contract, NAV_ENSURE).
  explicit P1Ekf15(const P1Params& params);

  void on_imu(const ImuSample& sample) override;
  void on_gps_position(const Vec3& p_n_measured_m) override;
  P1Solution solution() const override;
  std::string_view name() const override { return "ekf15"; }

  const NavState& nominal() const { return x_; }              ///< p̂_n, v̂_n, q̂_nb
  const Vec3& accel_bias_b() const { return b_a_; }           ///< b̂_a, body [m/s²]
  const Vec3& gyro_bias_b() const { return b_g_; }            ///< b̂_g, body [rad/s]
  const P1ErrorModel::MatN& covariance() const { return P_; } ///< P of δx
  /// Status of the last GPS update (kRejectedInvalid before the first one).
  UpdateStatus last_gps_status() const { return last_gps_; }
  /// Status of the magnetometer update of the last IMU sample (kRejectedInvalid when it made
  /// none).
  UpdateStatus last_mag_status() const { return last_mag_; }

 private:
  /// Applies a 3-D update (B4): fuses, injects, records the innovation; returns its status.
  UpdateStatus update(const char* source, const Vec3& z, const Mat<3, kN>& H, double std,
                      double gate);

  P1Params params_;
  NavState x_;
  Vec3 b_a_ = Vec3::Zero();
  Vec3 b_g_ = Vec3::Zero();
  P1ErrorModel::MatN P_;
  P1ErrorModel::MatN Q_c_;
  UpdateStatus last_gps_ = UpdateStatus::kRejectedInvalid;
  UpdateStatus last_mag_ = UpdateStatus::kRejectedInvalid;
};

}  // namespace nav::estimator

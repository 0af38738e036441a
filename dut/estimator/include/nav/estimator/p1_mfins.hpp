// SPDX-License-Identifier: MIT
// Navigator "mfins" of paper P1: the multi-filtered INS. Part (a), the 9-state attitude EKF
// [ρ, δb_acc, δb_gyro] at the IMU rate with δmⁿ and δgⁿ (p1_attitude_ekf.hpp, A1..A8), and
// part (b), a 9-state unscented particle filter [δp, δv, δa] of a position/velocity nominal
// (model p1_position_upf.hpp G1..G7, filter upf.hpp P1..P12) updated by GPS fixes.
//
// Reference: Hwang, Lee, Trans. KIEE 60(12), 2011, §4 (docs/papers.md, P1, "MFINS"). Labels
// M1..M8 are this file's own.
//
// Nominal: part (a)'s q̂_nb, b̂_a, b̂_g; part (b)'s p̂_n, v̂_n and acceleration correction ĉ_n
// (NED [m], [m/s], [m/s²]). One IMU sample (dt, ω̃, f̃, m̃), with the biases and q̂ of part (a)
// before the step, ω̂ = ω̃ − b̂_g, f̂ = f̃ − b̂_a:
//   M1  motion acceleration for δgⁿ (the paper never defines it): the position nominal's own
//       acceleration at the end of the step,
//         â_motion = R̂(q̂ ⊗ Exp(ω̂ dt)) f̂ + g_n + φ_a(dt) ĉ_n   (part (a)'s prediction A1 + ĉ)
//       so part (a) sees z = δgⁿ = ĉ_n − δâ_mag (E8; δâ_mag what its magnetometer update of
//       this sample moved â_ins): the acceleration error the GPS-aided position part has
//       learnt, never ≡ 0 by construction as z would be with â_motion = R̂ f̂ + g_n alone.
//       Given once per fused GPS fix, at the first IMU sample after it: ĉ carries new
//       information only when a fix moves it; between fixes it is the same value decayed,
//       and part (a) treats its δgⁿ as white noise, so giving it at every sample counts one
//       fix a hundred times, P_ρρ collapses, part (a) stops listening to its magnetometer and
//       the two parts drift together (measured with σ_grav alone as δgⁿ's noise, seed 7, 50
//       particles, two laps of the unit test's stadium: δgⁿ while the last fix is younger
//       than 1 s or 3 s gives 3.8° worst attitude and 1.6 m rms position; once per fix 0.09°
//       and 0.17 m; never 2.7° and 0.22 m). Before the first fix and in an
//       outage part (a) runs on the gyro and δmⁿ alone. δgⁿ's noise is σ_grav² I plus the
//       covariance of ĉ's error, the δa block of part (b)'s mixture covariance (P11) carried
//       over the step (φ_a²): ĉ is an estimate, and part (a) must not take it as exact.
//   M2  part (a) steps (A1..A8) with the sample and â_motion (or none).
//   M3  transfer: when its δgⁿ update fused, the acceleration correction it made,
//       δâ_grav = â_ins(after) − (â_motion − z_grav), is taken out of ĉ: ĉ ← ĉ − δâ_grav.
//       Without it the same error would be corrected twice (in the attitude and in ĉ) and
//       part (a) would keep pulling on a ĉ that it has already absorbed (wind-up). The
//       position nominal's acceleration is thereby unchanged by the δgⁿ update; the
//       magnetometer's correction passes through to it.
//   M4  position nominal over the step (G6): strapdown S3, S4 of ω̂, f̂ from q̂ at the step's
//       start, plus φ_v ĉ, φ_p ĉ; ĉ ← φ_a ĉ (then M3).
//   M5  error model over the step: Σ_c = J P_att Jᵀ after part (a)'s step (A8 without its
//       white term), Φ_k, Q_k of G2, G3, composed into (Φ_acc, Q_acc) (G4). The particles
//       are moved once with (Φ_acc, Q_acc) right before a GPS update: for this linear model
//       that is exactly the IMU-rate propagation (the UKF is exact for a linear f), at 1/100
//       of the cost. The model is linear, so the UPF keeps one P for all particles
//       (upf_shared.hpp P13..P15): the paper's 19 sigma points per particle give that same
//       P, and the same means, at 19 times the cost.
//   M6  on_gps_position: UPF predict with (Φ_acc, Q_acc) (then reset to (I, 0)), UPF update
//       with z = p̃_n − p̂_n, h = δp, R = σ_p² I (G5): each particle's filter updates, draws
//       from its posterior, is weighted by the GPS likelihood of the draw and keeps the
//       posterior (upf.hpp L5, L6, the paper's weighting); systematic resampling (P9); NIS
//       gate gps_gate_nis.
//   M7  feedback when fused (G7, P12): δx̄ = Σ w_i δx_i; p̂ += δp̄, v̂ += δv̄, ĉ += δā;
//       every particle shifted by −δx̄ (the linear model keeps the mean at 0 until the next
//       update).
//   M8  solution: q̂_nb and P_attitude_n = P_ρρ from part (a) (ρ is the NED rotation vector
//       of R_true R̂ᵀ); p̂_n, v̂_n; P_position_n = (Φ_acc P̄ Φ_accᵀ + Q_acc)_δpδp, P̄ the
//       particles' mixture covariance (P11) carried to the last IMU sample.
// What crosses between the parts each IMU step (the paper's "δa kept as an independent
// variable so the two parts decouple"):
//   | from → to | what                                        | used for             |
//   |-----------|---------------------------------------------|----------------------|
//   | (a) → (b) | q̂_nb, b̂_a, b̂_g before the step (â_ins)       | nominal, M4          |
//   | (a) → (b) | Σ_c = J P_att Jᵀ after the step             | δa's noise, M5 (G1)  |
//   | (a) → (b) | δâ_grav of its δgⁿ update (when fused)      | ĉ ← ĉ − δâ_grav, M3  |
//   | (b) → (a) | â_motion = â_ins,pred + ĉ (when fresh)      | δgⁿ, M1              |
//   | never     | any cross-covariance ρ/δb–δp/δv/δa          | assumed independent  |
// Each part treats what it receives as an independent input: part (b) carries δa as its own
// state and never sees ρ or δb; part (a) treats ĉ's error as white measurement noise of
// σ_grav (gravity_std_mps2) at the IMU rate. It is not: ĉ changes at the GPS rate, so
// P_ρρ is optimistic when σ_grav is set to ĉ's own uncertainty; σ_grav is the knob.
// The attitude depends on the particles only through ĉ (M1, M3), i.e. through the weighted
// mean δā of the UPF, whose Monte Carlo error is ~σ_δa/√ESS: the attitude is nearly, not
// exactly, independent of the particle count (tests/unit/estimator/p1_mfins_test.cpp).
// Randomness: only the UPF's generator, seeded with params.seed: same seed, same inputs →
// bit-identical solutions. Invalid input (NaN/Inf, dt ∉ (0, max_dt_s]) is refused and
// counted, state untouched; a step whose result is not finite or a UPF call that fails is
// skipped and counted in numerical_faults. No allocation per step (storage sized at
// construction).
#pragma once


#include "nav/common/result.hpp"
#include "nav/estimator/p1_attitude_ekf.hpp"
#include "nav/estimator/p1_position_upf.hpp"
#include "nav/estimator/p1_types.hpp"
#include "nav/estimator/upf.hpp"

namespace nav::estimator {

/// MFINS tuning values the paper does not give (not in P1Params).
struct P1MfinsTuning {
  /// τ of the Gauss–Markov acceleration error δa (G1), > 0 [s].
  double accel_error_time_constant_s = 10.0;
};

/// Checks P1MfinsTuning; the error names the first bad field.
Result<void> validate(const P1MfinsTuning& t);

/// Navigator "mfins" (file comment).
class P1Mfins final : public P1Navigator {
 public:
  using PM = P1PositionModel;
  static constexpr int kN = PM::kN;  ///< position error-state dimension

  /// params and tuning must pass validate() (contract, NAV_ENSURE).
  explicit P1Mfins(const P1Params& params, const P1MfinsTuning& tuning = {});

  void on_imu(const ImuSample& sample) override;
  void on_gps_position(const Vec3& p_n_measured_m) override;
  P1Solution solution() const override;
  std::string_view name() const override { return "mfins"; }

  /// Part (a).
  const P1AttitudeEkf& attitude() const { return att_; }
  /// Part (b)'s particles.
  const UnscentedParticleFilter<kN>& position_filter() const { return upf_; }
  const Vec3& position_n() const { return p_n_; }        ///< p̂_n, NED [m]
  const Vec3& velocity_n() const { return v_n_; }        ///< v̂_n, NED [m/s]
  const Vec3& accel_correction_n() const { return c_n_; }  ///< ĉ_n, NED [m/s²]
  /// The composed (Φ_acc, Q_acc) not yet applied to the particles (M5).
  const PM::Step& pending_step() const { return pending_; }
  /// Status of the last GPS update (kRejectedInvalid before the first one).
  UpdateStatus last_gps_status() const { return last_gps_; }

 private:
  void count_attitude_stats();

  P1Params params_;
  P1MfinsTuning tuning_;
  P1AttitudeEkf att_;
  UnscentedParticleFilter<kN> upf_;
  Vec3 p_n_ = Vec3::Zero();
  Vec3 v_n_ = Vec3::Zero();
  Vec3 c_n_ = Vec3::Zero();
  PM::Step pending_;
  double pending_dt_s_ = 0.0;
  bool gravity_due_ = false;  ///< a fix was fused since part (a)'s last δgⁿ (M1)
  std::uint64_t own_faults_ = 0;
  UpdateStatus last_gps_ = UpdateStatus::kRejectedInvalid;
};

}  // namespace nav::estimator

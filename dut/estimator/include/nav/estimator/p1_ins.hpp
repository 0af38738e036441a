// SPDX-License-Identifier: MIT
// Navigator "ins" of paper P1: strapdown only, no aiding — the paper's "INS only" baseline.
//
// Reference: Hwang, Lee, Trans. KIEE 60(12), 2011, §2 (docs/papers.md, P1). The nominal state
// starts at the configured p_n, v_n, q_nb with zero bias estimates and is propagated by
// strapdown_step (strapdown.hpp S1..S4) with the raw ω̃, f̃ (no bias is ever estimated).
// GPS fixes and the magnetometer are ignored (no counter moves for a fix; innovations stay
// empty).
//
// Covariance: the 15-state error covariance of p1_error_model.hpp is propagated (E2..E4, no
// update), so the solution has has_covariance = true. It is meaningful: it is exactly the
// prediction ekf15 makes between fixes, started from the configured initial standard
// deviations, so it states how fast the unaided INS is expected to drift (the initial bias
// uncertainty dominates). The bench's NEES reports then test the drift model too. Cost: one
// 15×15 Φ P Φᵀ per sample.
//
// Invalid input (NaN/Inf, dt ∉ (0, max_dt_s]): refused, counted, state untouched.
#pragma once

#include "nav/estimator/p1_error_model.hpp"
#include "nav/estimator/p1_types.hpp"
#include "nav/estimator/strapdown.hpp"

namespace nav::estimator {

/// Strapdown-only P1 navigator (file comment).
class P1Ins final : public P1Navigator {
 public:
  /// params must pass validate() (contract, NAV_ENSURE).
  explicit P1Ins(const P1Params& params);

  void on_imu(const ImuSample& sample) override;
  /// Ignored: the INS has no aiding.
  void on_gps_position(const Vec3& p_n_measured_m) override;
  P1Solution solution() const override;
  std::string_view name() const override { return "ins"; }

  const NavState& nominal() const { return x_; }  ///< p̂_n, v̂_n, q̂_nb
  /// P of the 15-state error (p1_error_model.hpp slices).
  const P1ErrorModel::MatN& covariance() const { return P_; }

 private:
  P1Params params_;
  NavState x_;
  P1ErrorModel::MatN P_;
  P1ErrorModel::MatN Q_c_;
};

}  // namespace nav::estimator

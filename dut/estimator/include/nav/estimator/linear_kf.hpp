// SPDX-License-Identifier: MIT
// Linear Kalman filter algorithm, independent of any model (the model supplies F, Q, H, R).
//
// Reference: Y. Bar-Shalom, X. R. Li, T. Kirubarajan, "Estimation with Applications to
// Tracking and Navigation", Wiley 2001, ch. 5 (the Kalman filter). Equation labels K1..K7
// are this file's own.
//
//   K1  x⁻ = f(x, u)                    (the model propagates the mean; linear here)
//   K2  P⁻ = F P Fᵀ + Q
//   K3  y  = z − H x⁻                   innovation
//   K4  S  = H P⁻ Hᵀ + R                innovation covariance
//   K5  K  = P⁻ Hᵀ S⁻¹                  gain, computed as (S⁻¹ H P⁻)ᵀ with an LDLᵀ solve
//   K6  x  = x⁻ + K y
//   K7  P  = (I − K H) P⁻ (I − K H)ᵀ + K R Kᵀ      Joseph form: symmetric and PSD for any K
//   NIS = yᵀ S⁻¹ y
//
// Numerical health: S is factorised with LDLᵀ; a failed or non-positive factorisation, or a
// non-finite result, returns kNumericalFault and leaves x and P untouched. Non-finite inputs
// return kRejectedInvalid. Nothing here throws or aborts on data.
#pragma once

#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "nav/estimator/update_report.hpp"

namespace nav::estimator {

template <int R, int C>
using Mat = Eigen::Matrix<double, R, C>;
template <int R>
using Vec = Eigen::Matrix<double, R, 1>;

/// Makes P exactly symmetric (removes round-off asymmetry).
template <int N>
void symmetrize(Mat<N, N>& P) {
  P = 0.5 * (P + P.transpose()).eval();
}

/// Covariance prediction (K2). The caller has already propagated the mean (K1).
template <int N>
void predict_covariance(Mat<N, N>& P, const Mat<N, N>& F, const Mat<N, N>& Q) {
  P = F * P * F.transpose() + Q;  // (K2)
  symmetrize(P);
}

/// Linear measurement update (K3..K7) of x, P with z = H x + v, v ~ N(0, R).
/// `gate` > 0 rejects the update when NIS exceeds it.
template <int N, int M>
UpdateReport<M> linear_update(Vec<N>& x, Mat<N, N>& P, const Vec<M>& z, const Mat<M, N>& H,
                              const Mat<M, M>& R, double gate = 0.0) {
  UpdateReport<M> report;
  report.gate = gate;
  if (!z.allFinite() || !R.allFinite() || !H.allFinite()) {
    report.status = UpdateStatus::kRejectedInvalid;
    return report;
  }
  const Vec<M> y = z - H * x;                          // innovation (K3)
  const Mat<M, M> S = H * P * H.transpose() + R;       // innovation covariance (K4)
  report.y = y;
  report.S = S;
  const Eigen::LDLT<Mat<M, M>> S_ldlt(S);
  if (S_ldlt.info() != Eigen::Success || !S_ldlt.isPositive() ||
      !(S_ldlt.vectorD().array() > 0.0).all()) {
    report.status = UpdateStatus::kNumericalFault;
    return report;
  }
  const double nis = y.dot(S_ldlt.solve(y));           // NIS = yᵀ S⁻¹ y
  report.nis = nis;
  if (!std::isfinite(nis)) {
    report.status = UpdateStatus::kNumericalFault;
    return report;
  }
  if (gate > 0.0 && nis > gate) {
    report.status = UpdateStatus::kRejectedGate;
    return report;
  }
  // H P⁻ evaluated first: solving against the unevaluated product trips a GCC 12
  // -Warray-bounds false positive in Eigen's LDLT for M = 1.
  const Mat<M, N> HP = H * P;
  const Mat<N, M> K = S_ldlt.solve(HP).transpose();     // K = P Hᵀ S⁻¹, S and P symmetric (K5)
  const Vec<N> x_new = x + K * y;                        // (K6)
  const Mat<N, N> I_KH = Mat<N, N>::Identity() - K * H;
  Mat<N, N> P_new = I_KH * P * I_KH.transpose() + K * R * K.transpose();  // Joseph form (K7)
  symmetrize(P_new);
  if (!x_new.allFinite() || !P_new.allFinite()) {
    report.status = UpdateStatus::kNumericalFault;
    return report;
  }
  x = x_new;
  P = P_new;
  report.status = UpdateStatus::kFused;
  return report;
}

}  // namespace nav::estimator

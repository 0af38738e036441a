// SPDX-License-Identifier: MIT
// Scaled unscented transform and the additive-noise unscented Kalman filter, independent of any
// model: the caller supplies f and Q, h and R (style.md "Models separate from algorithms").
//
// References:
//   [J02] S. J. Julier, "The scaled unscented transformation", Proc. American Control
//         Conference 2002 (sigma points and weights, U1..U4).
//   [WM00] E. A. Wan, R. van der Merwe, "The unscented Kalman filter for nonlinear
//         estimation", Proc. IEEE AS-SPCC 2000, the UKF in its additive-noise form
//         (predict U7..U8, update U9..U13).
// Equation labels U1..U13 are this file's own.
//
// Sigma points and weights of an N-dimensional Gaussian N(x, P), 2N + 1 points:
//   U1  λ = α² (N + κ) − N,   γ = √(N + λ)
//   U2  P = L Lᵀ (LLT, L lower);  χ₀ = x,  χ_j = x + γ L_j,  χ_{N+j} = x − γ L_j  (j = 1..N)
//   U3  W₀⁽ᵐ⁾ = λ/(N + λ),  W₀⁽ᶜ⁾ = W₀⁽ᵐ⁾ + 1 − α² + β,  W_j⁽ᵐ⁾ = W_j⁽ᶜ⁾ = 1/(2(N + λ))
//   U4  Σ W⁽ᵐ⁾ = 1 for every α, β, κ (the mean weights sum to one)
// Unscented transform of y = g(x):
//   U5  Y_j = g(χ_j);  ŷ = Σ W_j⁽ᵐ⁾ Y_j
//   U6  P_yy = Σ W_j⁽ᶜ⁾ (Y_j − ŷ)(Y_j − ŷ)ᵀ;  P_xy = Σ W_j⁽ᶜ⁾ (χ_j − x)(Y_j − ŷ)ᵀ
// UKF predict, x_k = f(x_{k−1}) + w, w ~ N(0, Q):
//   U7  x⁻ = Σ W⁽ᵐ⁾ f(χ_j)
//   U8  P⁻ = Σ W⁽ᶜ⁾ (f(χ_j) − x⁻)(f(χ_j) − x⁻)ᵀ + Q
// UKF update, z = h(x) + v, v ~ N(0, R); the sigma points are redrawn from (x⁻, P⁻):
//   U9  ẑ = Σ W⁽ᵐ⁾ h(χ_j)
//   U10 S = Σ W⁽ᶜ⁾ (h(χ_j) − ẑ)(h(χ_j) − ẑ)ᵀ + R;  P_xz = Σ W⁽ᶜ⁾ (χ_j − x⁻)(h(χ_j) − ẑ)ᵀ
//   U11 K = P_xz S⁻¹, computed as (S⁻¹ P_xzᵀ)ᵀ with an LDLᵀ solve
//   U12 y = z − ẑ;  x = x⁻ + K y;  NIS = yᵀ S⁻¹ y
//   U13 P = P⁻ − K S Kᵀ, symmetrised, then checked positive definite with an LLT
//
// Defaults α = 1, β = 2, κ = 0: λ = 0, so W₀⁽ᵐ⁾ = 0, W_j = 1/(2N), W₀⁽ᶜ⁾ = 2 and the points
// lie at ±√N standard deviations. Every weight is non-negative, so P⁻ and S are sums of outer
// products plus Q and R. The often-quoted α = 10⁻³ gives W₀⁽ᵐ⁾ ≈ −10⁶ and cancels ~6 digits in
// U5/U6, for 15 error states spanning many orders of magnitude. β = 2 is optimal for a
// Gaussian prior [J02]. With β ≥ 0 and N + λ > 0 (validate()), U6 is positive semi-definite:
// P_yy = (N/(N+λ)) [S_b + (β/α²) (Y₀ − Ȳ)(Y₀ − Ȳ)ᵀ], S_b the spread of the 2N outer images
// about their mean Ȳ; so P⁻ is positive definite whenever Q is.
//
// Numerical health (style.md): a failed LLT of P (or a non-finite factor: Eigen's LLT lets
// NaN through) returns kCholeskyFailed; a non-finite g(χ) or result returns kNonFinite; the
// update returns UpdateReport statuses as linear_update does. x and P are written only on
// success. Nothing here allocates, throws or aborts on data.
#pragma once

#include <cmath>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "nav/common/ensure.hpp"
#include "nav/common/result.hpp"
#include "nav/estimator/linear_kf.hpp"
#include "nav/estimator/update_report.hpp"

namespace nav::estimator {

/// Spread parameters of the scaled unscented transform (U1, U3).
struct UnscentedParams {
  /// α: spread of the sigma points around the mean, (0, 1] [-].
  double alpha = 1.0;
  /// β: prior knowledge of the distribution's kurtosis; 2 is optimal for a Gaussian, >= 0 [-].
  double beta = 2.0;
  /// κ: secondary scaling; N + κ must be > 0 [-].
  double kappa = 0.0;
};

/// Checks α ∈ (0, 1], β >= 0, N + κ > 0, all finite, for state dimension n. The error names the
/// field and the value.
Result<void> validate(const UnscentedParams& p, int n);

/// Outcome of sigma-point generation, an unscented transform or a UKF predict.
enum class UnscentedStatus {
  kOk,               ///< computed; outputs written
  kRejectedInvalid,  ///< NaN/Inf or out-of-domain input: outputs untouched
  kCholeskyFailed,   ///< a covariance is not positive definite (its LLT failed): untouched
  kNonFinite,        ///< the function or the result is not finite: outputs untouched
};

/// Short lower-case name ("ok", "cholesky_failed", ...).
constexpr const char* to_string(UnscentedStatus s) {
  switch (s) {
    case UnscentedStatus::kOk: return "ok";
    case UnscentedStatus::kRejectedInvalid: return "rejected_invalid";
    case UnscentedStatus::kCholeskyFailed: return "cholesky_failed";
    case UnscentedStatus::kNonFinite: return "non_finite";
  }
  return "unknown";
}

/// Weights of the 2N + 1 sigma points of an N-dimensional Gaussian (U1, U3).
template <int N>
struct UnscentedWeights {
  static_assert(N >= 1, "the state has at least one dimension");
  static constexpr int kPoints = 2 * N + 1;  ///< number of sigma points [-]
  Vec<kPoints> mean = Vec<kPoints>::Zero();  ///< W⁽ᵐ⁾, summing to one (U4) [-]
  Vec<kPoints> cov = Vec<kPoints>::Zero();   ///< W⁽ᶜ⁾ [-]
  double gamma = 0.0;  ///< γ = √(N + λ): distance of the points in standard deviations [-]
};

/// The 2N + 1 sigma points of N(x, P) as columns (column 0 the mean).
template <int N>
using SigmaPoints = Mat<N, 2 * N + 1>;

/// Weights for the parameters p (U1, U3). p must pass validate(p, N) (contract).
template <int N>
UnscentedWeights<N> unscented_weights(const UnscentedParams& p) {
  const Result<void> ok = validate(p, N);
  NAV_ENSURE(ok.has_value(), ok.error().detail);
  const double lambda = p.alpha * p.alpha * (N + p.kappa) - N;  // (U1)
  const double n_lambda = N + lambda;
  UnscentedWeights<N> w;
  w.gamma = std::sqrt(n_lambda);                                  // (U1)
  w.mean.setConstant(1.0 / (2.0 * n_lambda));                     // (U3)
  w.cov.setConstant(1.0 / (2.0 * n_lambda));
  w.mean(0) = lambda / n_lambda;
  w.cov(0) = w.mean(0) + 1.0 - p.alpha * p.alpha + p.beta;
  return w;
}

/// Sigma points of N(x, P) with spread γ (U2). `L_out`, when given, receives the lower Cholesky
/// factor of P (P = L Lᵀ) for callers that evaluate densities of N(x, P). x, P non-finite →
/// kRejectedInvalid; P not positive definite → kCholeskyFailed; X untouched in both cases.
template <int N>
UnscentedStatus sigma_points(const Vec<N>& x, const Mat<N, N>& P, double gamma,
                             SigmaPoints<N>& X, Mat<N, N>* L_out = nullptr) {
  if (!x.allFinite() || !P.allFinite() || !std::isfinite(gamma)) {
    return UnscentedStatus::kRejectedInvalid;
  }
  const Eigen::LLT<Mat<N, N>> llt(P);
  if (llt.info() != Eigen::Success) {
    return UnscentedStatus::kCholeskyFailed;
  }
  const Mat<N, N> L = llt.matrixL();  // P = L Lᵀ (U2)
  if (!L.allFinite()) {
    return UnscentedStatus::kCholeskyFailed;
  }
  X.col(0) = x;                                   // χ₀ = x (U2)
  for (int j = 0; j < N; ++j) {
    X.col(1 + j) = x + gamma * L.col(j);          // χ_j = x + γ L_j
    X.col(1 + N + j) = x - gamma * L.col(j);      // χ_{N+j} = x − γ L_j
  }
  if (L_out != nullptr) {
    *L_out = L;
  }
  return UnscentedStatus::kOk;
}

/// Unscented transform of y = g(x), x ~ N(x, P) (U5, U6): the mean y, covariance P_yy and, when
/// `P_xy` is given, the cross-covariance. g: Vec<N> → Vec<M>. Outputs written only on kOk.
template <int N, int M, class G>
UnscentedStatus unscented_transform(const Vec<N>& x, const Mat<N, N>& P,
                                    const UnscentedWeights<N>& w, G&& g, Vec<M>& y,
                                    Mat<M, M>& P_yy, Mat<N, M>* P_xy = nullptr) {
  constexpr int kPoints = UnscentedWeights<N>::kPoints;
  SigmaPoints<N> X = SigmaPoints<N>::Zero();
  const UnscentedStatus sigma = sigma_points<N>(x, P, w.gamma, X);
  if (sigma != UnscentedStatus::kOk) {
    return sigma;
  }
  Mat<M, kPoints> Y;
  for (int j = 0; j < kPoints; ++j) {
    const Vec<N> chi = X.col(j);
    Y.col(j) = g(chi);                                     // Y_j = g(χ_j) (U5)
  }
  if (!Y.allFinite()) {
    return UnscentedStatus::kNonFinite;
  }
  const Vec<M> y_new = Y * w.mean;                         // ŷ = Σ W⁽ᵐ⁾ Y_j (U5)
  const Mat<M, kPoints> dY = Y.colwise() - y_new;
  const Mat<M, kPoints> dY_w = dY * w.cov.asDiagonal();  // W⁽ᶜ⁾-weighted deviations
  Mat<M, M> P_yy_new = dY_w.lazyProduct(dY.transpose());  // (U6)
  symmetrize(P_yy_new);
  if (!y_new.allFinite() || !P_yy_new.allFinite()) {
    return UnscentedStatus::kNonFinite;
  }
  if (P_xy != nullptr) {
    const Mat<N, kPoints> dX = X.colwise() - x;
    *P_xy = dX.lazyProduct(dY_w.transpose());              // P_xy (U6)
  }
  y = y_new;
  P_yy = P_yy_new;
  return UnscentedStatus::kOk;
}

/// UKF predict (U7, U8) of x, P through f: Vec<N> → Vec<N> with additive process noise Q.
/// Non-finite Q → kRejectedInvalid. x, P written only on kOk. The result is not checked for
/// positive definiteness here (it is PD for validated weights and a PD Q; the next sigma-point
/// factorisation reports it otherwise).
template <int N, class F>
UnscentedStatus ukf_predict(Vec<N>& x, Mat<N, N>& P, const UnscentedWeights<N>& w, F&& f,
                            const Mat<N, N>& Q) {
  if (!Q.allFinite()) {
    return UnscentedStatus::kRejectedInvalid;
  }
  Vec<N> x_pred = Vec<N>::Zero();
  Mat<N, N> P_pred = Mat<N, N>::Zero();
  const UnscentedStatus ut = unscented_transform<N, N>(x, P, w, f, x_pred, P_pred);  // (U7)
  if (ut != UnscentedStatus::kOk) {
    return ut;
  }
  P_pred += Q;                                                                        // (U8)
  if (!P_pred.allFinite()) {
    return UnscentedStatus::kNonFinite;
  }
  x = x_pred;
  P = P_pred;
  return UnscentedStatus::kOk;
}

/// Lower Cholesky factors a fused UKF update computed, for callers that sample or evaluate
/// densities of the prior N(x⁻, P⁻) and of the posterior N(x, P) without factorising again.
template <int N>
struct UkfFactors {
  Mat<N, N> L_prior = Mat<N, N>::Zero();  ///< P⁻ = L Lᵀ (the sigma points' factor, U2)
  Mat<N, N> L_post = Mat<N, N>::Zero();   ///< P = L Lᵀ after the update (U13's check)
};

/// UKF measurement update (U9..U13) of x, P with z = h(x) + v, v ~ N(0, R); h: Vec<N> → Vec<M>.
/// `gate` > 0 rejects the update when NIS exceeds it. Statuses as linear_update: NaN/Inf in z
/// or R → kRejectedInvalid; P not PD, S not PD, a non-finite h or result, or an updated P that
/// is not PD → kNumericalFault. x and P (and `factors`) are written only on kFused.
template <int N, int M, class H>
UpdateReport<M> ukf_update(Vec<N>& x, Mat<N, N>& P, const UnscentedWeights<N>& w, H&& h,
                           const Vec<M>& z, const Mat<M, M>& R, double gate = 0.0,
                           UkfFactors<N>* factors = nullptr) {
  constexpr int kPoints = UnscentedWeights<N>::kPoints;
  UpdateReport<M> report;
  report.gate = gate;
  if (!z.allFinite() || !R.allFinite()) {
    report.status = UpdateStatus::kRejectedInvalid;
    return report;
  }
  SigmaPoints<N> X = SigmaPoints<N>::Zero();
  Mat<N, N> L_prior = Mat<N, N>::Zero();
  if (sigma_points<N>(x, P, w.gamma, X, &L_prior) != UnscentedStatus::kOk) {  // (U2)
    report.status = UpdateStatus::kNumericalFault;
    return report;
  }
  Mat<M, kPoints> Z;
  for (int j = 0; j < kPoints; ++j) {
    const Vec<N> chi = X.col(j);
    Z.col(j) = h(chi);
  }
  const Vec<M> z_hat = Z * w.mean;                                      // (U9)
  const Mat<M, kPoints> dZ = Z.colwise() - z_hat;
  const Mat<N, kPoints> dX = X.colwise() - x;
  const Mat<M, kPoints> dZ_w = dZ * w.cov.asDiagonal();                 // weighted deviations
  Mat<M, M> S = dZ_w.lazyProduct(dZ.transpose()) + R;                   // (U10)
  symmetrize(S);
  const Mat<N, M> P_xz = dX.lazyProduct(dZ_w.transpose());              // (U10)
  if (!Z.allFinite() || !S.allFinite() || !P_xz.allFinite()) {
    report.status = UpdateStatus::kNumericalFault;
    return report;
  }
  const Vec<M> y = z - z_hat;                                           // (U12)
  report.y = y;
  report.S = S;
  const Eigen::LDLT<Mat<M, M>> S_ldlt(S);
  if (S_ldlt.info() != Eigen::Success || !S_ldlt.isPositive() ||
      !(S_ldlt.vectorD().array() > 0.0).all()) {
    report.status = UpdateStatus::kNumericalFault;
    return report;
  }
  const double nis = y.dot(S_ldlt.solve(y));                            // NIS = yᵀ S⁻¹ y
  report.nis = nis;
  if (!std::isfinite(nis)) {
    report.status = UpdateStatus::kNumericalFault;
    return report;
  }
  if (gate > 0.0 && nis > gate) {
    report.status = UpdateStatus::kRejectedGate;
    return report;
  }
  // P_xzᵀ evaluated first (GCC 12 -Warray-bounds false positive in Eigen's LDLT for M = 1,
  // see linear_kf.hpp).
  const Mat<M, N> P_zx = P_xz.transpose();
  const Mat<N, M> K = S_ldlt.solve(P_zx).transpose();   // K = P_xz S⁻¹, S symmetric (U11)
  const Vec<N> x_new = x + K * y;                         // (U12)
  Mat<N, N> P_new = P - K * S * K.transpose();            // (U13)
  symmetrize(P_new);
  const Eigen::LLT<Mat<N, N>> P_llt(P_new);               // PD check (U13)
  if (!x_new.allFinite() || !P_new.allFinite() || P_llt.info() != Eigen::Success) {
    report.status = UpdateStatus::kNumericalFault;
    return report;
  }
  const Mat<N, N> L_post = P_llt.matrixL();
  if (!L_post.allFinite()) {
    report.status = UpdateStatus::kNumericalFault;
    return report;
  }
  x = x_new;
  P = P_new;
  if (factors != nullptr) {
    factors->L_prior = L_prior;
    factors->L_post = L_post;
  }
  report.status = UpdateStatus::kFused;
  return report;
}

}  // namespace nav::estimator

// SPDX-License-Identifier: MIT
// The shared-covariance path of the unscented particle filter (upf.hpp, which includes this
// file at its end; do not include it alone). Labels P1..P12 are upf.hpp's.
//
// Shared covariance (opt-in, P13..P16). For a process that is affine in the state with a
// state-independent covariance propagation — f(x, u, Δt) = Φ(u, Δt) x + b(u, Δt), Q(u, Δt)
// independent of x; the model states it with `static constexpr bool kSharedCovariance = true`
// and `Mat<N, N> Phi(u, Δt)` (UpfSharedCovarianceProcess) — every particle's P_i evolves
// identically from a common start (all P_i = P₀ after reset, all 0 after an update), so the
// filter keeps ONE P for all particles while that holds:
//   P13 predict:  x_i = f(x_i, u, Δt) per particle;  P = Q after an update (P1), else
//                 P = Φ P Φᵀ + Q (what U7, U8 give for an affine f: mathematically equal)
//   P14 update, measurement affine too — h(x) = H x + c, declared by `static constexpr bool
//       kLinear = true` and `Mat<M, N> H()` (UpfLinearMeasurement): one S = H P Hᵀ + R, one
//       K = P Hᵀ S⁻¹, one P̂ = P − K S Kᵀ and its factor L̂, shared by all particles (U10..U13
//       for an affine h); per particle only  y_i = z − h(x_i),  x̂_i = x_i + K y_i,  the draw
//       x̃_i = x̂_i + L̂ ξ (P4),  and the weight
//   P15 ln w_i += ln N(y_i; 0, S): for a linear-Gaussian model P5's three densities reduce
//       exactly to the predictive likelihood (the proposal is the optimal one), so the
//       closed form is the same number without two 15-dimensional densities per particle
//   P16 a non-linear measurement with a shared P runs P3..P7 per particle (its sigma points
//       differ) reading the shared P as every prior; both updates end with all points (P = 0).
// A generic (non-affine) predict copies the shared P into every particle first and the filter
// is generic until the next update. Same seed, same calls → the generic and the shared path
// draw the same ξ in the same order; their results differ by round-off only (tested).
//
// Cost per step with N_p particles (N = 15): predict one Φ P Φᵀ (O(N³)) plus N_p f(x_i)
// (O(N²) each for f = Φ x); update one S, K, P̂ and two factorisations (O(N³)) plus per particle
// one h, one K y_i, N normal draws and L̂ ξ (O(N²)) — against 2N + 1 sigma points, a
// factorisation and two N-dimensional densities per particle on the generic path.
#pragma once

#include "nav/estimator/upf.hpp"

namespace nav::estimator {

/// P13: every particle's mean through f, the one P through Φ (Q already checked PD).
template <int N>
template <class Process>
UpfPredictReport UnscentedParticleFilter<N>::predict_shared(const Process& process,
                                                            const typename Process::Input& u,
                                                            double dt_s, const Mat<N, N>& Q) {
  UpfPredictReport report;
  Mat<N, N> P_next = Q;                                                // (P1)
  if (!point_common_) {
    const Mat<N, N> Phi = process.Phi(u, dt_s);
    P_next = Phi * P_common_ * Phi.transpose() + Q;                    // (P13)
    symmetrize(P_next);
  }
  if (!P_next.allFinite()) {
    report.status = UnscentedStatus::kNonFinite;
    return report;
  }
  int survivors = 0;
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    log_w_new_[i] = 0.0;
    if (dead(i)) continue;
    const Vec<N> x_next = process.f(particles_[i].x, u, dt_s);         // (P13)
    if (x_next.allFinite()) {
      x_new_[i] = x_next;
      ++survivors;
    } else {
      log_w_new_[i] = kMinusInf;
      ++report.failed_particles;
    }
  }
  if (survivors == 0) {
    report.status = UnscentedStatus::kNonFinite;
    return report;
  }
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    if (!dead(i) && log_w_new_[i] == 0.0) particles_[i].x = x_new_[i];
  }
  P_common_ = P_next;
  point_common_ = false;
  shared_ = true;
  drop_marked(report.failed_particles);
  report.status = UnscentedStatus::kOk;
  return report;
}

/// P14, P15 (P7 when the particles are points): one S, K, P̂ and L̂ for all particles.
template <int N>
template <class Meas, int M>
void UnscentedParticleFilter<N>::update_shared(const Meas& meas, const Vec<M>& z,
                                               const Mat<M, M>& R, const Mat<M, M>& L_R,
                                               double gate, UpfUpdateReport<M>& report) {
  shared_ = true;  // uniform_: every P_i is P_common_ already
  Mat<M, M> S = R;
  Mat<M, M> L_S = L_R;
  Mat<N, M> K = Mat<N, M>::Zero();
  Mat<N, N> L_post = Mat<N, N>::Zero();
  Mat<N, N> P_post = Mat<N, N>::Zero();
  if (!point_common_ && !shared_gain(meas.H(), R, S, L_S, K, L_post, P_post)) {
    for (std::size_t i = 0; i < particles_.size(); ++i) {
      if (!dead(i)) ++report.failed_particles;  // every proposal fails together
    }
    report.status = UpdateStatus::kNumericalFault;
    return;
  }
  const Rng rng_before = rng_;
  Moments<M> mom;
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    log_w_new_[i] = kMinusInf;
    x_new_[i] = particles_[i].x;
    if (dead(i)) continue;
    const Vec<M> y_i = z - meas.h(particles_[i].x);                    // (P14)
    if (!point_common_) {
      const Vec<N> xi = draw_normal();
      x_new_[i] = particles_[i].x + K * y_i + L_post * xi;             // x̂_i + L̂ ξ (P4, P14)
    }
    const double log_increment =
        params_.weighting == UpfWeighting::kLikelihood
            ? gaussian_log_density<M>(z - meas.h(x_new_[i]), L_R)      // (L5)
            : gaussian_log_density<M>(y_i, L_S);                       // (P15; P7: S = R)
    if (!std::isfinite(log_increment) || !x_new_[i].allFinite() || !y_i.allFinite()) {
      x_new_[i] = particles_[i].x;
      ++report.failed_particles;
      continue;
    }
    log_w_new_[i] = log_w_[i] + log_increment;
    mom.add(w_[i], y_i, S);
  }
  finish_update(mom, gate, rng_before, report, &P_post);  // P_post is L6's (P̂)
}

/// C1 on the shared path: one S, K and P̂; per particle x_i += K (z − h(x_i)); the weights
/// and the generator are untouched.
template <int N>
template <class Meas, int M>
void UnscentedParticleFilter<N>::correct_shared(const Meas& meas, const Vec<M>& z,
                                                const Mat<M, M>& R, double gate,
                                                UpfUpdateReport<M>& report) {
  shared_ = true;  // uniform_: every P_i is P_common_ already
  Mat<M, M> S = R;
  Mat<M, M> L_S = Mat<M, M>::Zero();
  Mat<N, M> K = Mat<N, M>::Zero();
  Mat<N, N> L_post = Mat<N, N>::Zero();
  Mat<N, N> P_post = P_common_;
  if (!point_common_ && !shared_gain(meas.H(), R, S, L_S, K, L_post, P_post)) {
    for (std::size_t i = 0; i < particles_.size(); ++i) {
      if (!dead(i)) ++report.failed_particles;
    }
    report.status = UpdateStatus::kNumericalFault;
    return;
  }
  Moments<M> mom;
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    log_w_new_[i] = kMinusInf;
    x_new_[i] = particles_[i].x;
    if (dead(i)) continue;
    const Vec<M> y_i = z - meas.h(particles_[i].x);
    x_new_[i] = particles_[i].x + K * y_i;                             // (C1, U12)
    if (!x_new_[i].allFinite() || !y_i.allFinite()) {
      x_new_[i] = particles_[i].x;
      ++report.failed_particles;
      continue;
    }
    log_w_new_[i] = log_w_[i];
    mom.add(w_[i], y_i, S);
  }
  if (!judge(mom, gate, report)) return;
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    if (log_w_new_[i] != kMinusInf) particles_[i].x = x_new_[i];
  }
  P_common_ = P_post;                                                  // (C1, U13)
  commit_weights(report);
}

/// S = H P Hᵀ + R, K = P Hᵀ S⁻¹, P̂ = P − K S Kᵀ of the shared P (P14) and the factors of S
/// and P̂; false when S or P̂ is not positive definite or a result is not finite.
template <int N>
template <int M>
bool UnscentedParticleFilter<N>::shared_gain(const Mat<M, N>& H, const Mat<M, M>& R,
                                             Mat<M, M>& S, Mat<M, M>& L_S, Mat<N, M>& K,
                                             Mat<N, N>& L_post, Mat<N, N>& P_post) const {
  const Mat<M, N> HP = H * P_common_;
  S = HP * H.transpose() + R;                                          // (U10)
  symmetrize(S);
  const Eigen::LLT<Mat<M, M>> S_llt(S);
  if (!S.allFinite() || S_llt.info() != Eigen::Success) return false;
  L_S = S_llt.matrixL();
  K = S_llt.solve(HP).transpose();                                     // K = P Hᵀ S⁻¹ (U11)
  P_post = P_common_ - K * S * K.transpose();                          // (U13)
  symmetrize(P_post);
  const Eigen::LLT<Mat<N, N>> P_llt(P_post);
  if (!P_post.allFinite() || P_llt.info() != Eigen::Success) return false;
  L_post = P_llt.matrixL();
  return L_S.allFinite() && K.allFinite() && L_post.allFinite();
}

}  // namespace nav::estimator

// SPDX-License-Identifier: MIT
// Unscented particle filter (UPF) over an N-dimensional state, independent of any model: each
// particle runs a UKF (unscented.hpp) whose update is the particle's proposal. Used by paper
// P1's "UPF" (15 error states [δp, δv, ρ, δb_acc, δb_gyro], GPS-position likelihood, 31 sigma
// points) and by its MFINS position part (9 states [δp, δv, δa], 19 sigma points).
//
// Reference: R. van der Merwe, A. Doucet, N. de Freitas, E. Wan, "The Unscented Particle
// Filter", Cambridge University Engineering Dept. tech. report CUED/F-INFENG/TR 380, 2000 (and
// NIPS 13, 2000), the section "The unscented particle filter". Labels P1..P12 are this file's
// own.
//
// Particles: i = 1..N_p, each a Gaussian component N(x_i, P_i) with normalised weight w_i; the
// filter's density is the mixture Σ w_i N(x_i, P_i). A "point" particle has P_i = 0 (a sample).
// Initialisation: every particle is (x₀, P₀), w_i = 1/N_p (the mixture is exactly N(x₀, P₀)).
// Predict (process x_k = f(x_{k−1}, u, Δt) + q, q ~ N(0, Q(u, Δt)), Q positive definite):
//   P1  point:      x_i = f(x_i, u, Δt),  P_i = Q                   (exact for a point)
//   P2  otherwise:  (x_i, P_i) = UKF predict of (x_i, P_i)          (unscented.hpp U7, U8)
// Update (z = h(x) + v, v ~ N(0, R)); for every live particle, in index order:
//   P3  proposal  q_i = N(x̂_i, P̂_i) = UKF update of the prior (x_i, P_i) with z   (U9..U13)
//   P4  draw      x̃_i = x̂_i + L̂_i ξ,  ξ ~ N(0, I_N),  P̂_i = L̂_i L̂_iᵀ
//   P5  ln w_i += ln N(z; h(x̃_i), R) + ln N(x̃_i; x_i, P_i) − ln N(x̃_i; x̂_i, P̂_i)
//                 likelihood            prior (the particle's     proposal
//                                        UKF-predicted density)
//   P6  the particle becomes the point x̃_i (P_i = 0)
//   A point particle (no predict since the last update: the transition is the identity) is
//   only reweighted: P7  ln w_i += ln N(z; h(x_i), R), x_i kept.
//   P8  normalise in log space (particle_filter.hpp W1, W2);  ESS = 1/Σ w² (W3)
//   P9  resample systematically (W4, W5) when ESS < threshold·N_p or a weight is 0; then
//       w_i = 1/N_p.
// Output (the mixture's moments):
//   P10 x̄ = Σ w_i x_i
//   P11 P̄ = Σ w_i P_i + Σ w_i (x_i − x̄)(x_i − x̄)ᵀ   (mean of the P_i plus the spread of the
//       x_i; right after an update every P_i is 0 and P̄ is the spread alone)
//   P12 error-state feedback: after the host applies x̄ to its nominal state, shift(x̄) moves
//       every particle by −x̄.
// Log-densities: ln N(r; 0, L Lᵀ) with one triangular solve on the LLT factor (W6): P5's prior
// uses the factor of P_i the UKF update drew its sigma points with, the proposal the factor of
// P̂_i from U13's positive-definiteness check (and L̂_i⁻¹(x̃_i − x̂_i) = ξ), the likelihood R's
// factor, computed once per update.
//
// Why P6 resets P_i to 0 instead of keeping P̂_i as the reference's algorithm does: with P̂_i kept,
// P5's prior must be the transition density from the point x̃_i over the whole interval since
// the last update (the reference's p(x_k | x_{k−1}) with one predict per update); a proposal
// built from P̂_i is then far wider than that density whenever Q is small against P̂ (error
// states between GPS fixes), and the weights collapse. With P6 the UKF's (x_i, P_i) at the next
// update is exactly the transition density from x̃_i (P1, P2), the proposal is the unscented
// approximation of the optimal one p(x_k | x̃_i, z_k), P5 is its correct weight, and for a
// linear-Gaussian model the weights equal N(z; ẑ_i, S_i) whatever ξ: the filter converges to
// the Kalman filter (tests/unit/estimator/upf_test.cpp). Q must therefore be positive definite
// (give every state some process noise); predict refuses one that is not.
//
// Paper P1's weighting (UpfParams::weighting = kLikelihood; the paper: "particles are drawn
// from N(δx̂, P) of their UKF, weighted by the GPS likelihood, normalised, resampled"):
//   L5  ln w_i += ln N(z; h(x̃_i), R)                        (P3, P4 as above)
//   L6  the particle becomes (x̃_i, P̂_i): it goes on as a UKF from its draw
// Each particle is then a UKF whose mean is jittered by a draw from its own posterior at every
// weighted update, and the weights pull the cloud towards the fix. This is not the reference
// UPF's importance weight: it counts the fix twice (once in the proposal, once in the weight)
// and the mixture P11 holds P̂ plus the jitter's spread, so it does not converge to the Kalman
// filter; it is kept because it is what the paper ran, and because a particle that keeps P̂_i
// keeps the cloud's uncertainty through resampling, where P6's points lose it between rare
// fixes (docs/estimators.md, "Paper P1").
//   C1  correct(): a measurement the weights do not use (P1's magnetometer, at the IMU rate)
//       is fused into every particle's UKF (U9..U13) with no draw and no weight change.
//
// Shared covariance (opt-in, P13..P16, upf_shared.hpp): for a process affine in the state with
// a state-independent Q (UpfSharedCovarianceProcess) the filter keeps one P for all particles
// while they share it (after reset, after every update), and for an affine measurement
// (UpfLinearMeasurement) computes one gain and one factorisation per update: the per-particle
// cost is a mean update and a draw. Same seed → the same draws as the generic path.
//
// Numerical health: a particle whose factorisation fails (P_i or P̂_i not positive definite) or
// whose result is not finite is dropped (weight 0, state kept) and counted in the report; the
// next update resamples it away. When no particle survives, or the update is refused (NaN/Inf
// input, gate), nothing changes, the random generator included. Storage is sized at
// construction: no heap allocation per step.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numbers>
#include <span>
#include <type_traits>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "nav/common/ensure.hpp"
#include "nav/estimator/linear_kf.hpp"
#include "nav/estimator/particle_filter.hpp"
#include "nav/estimator/unscented.hpp"
#include "nav/estimator/update_report.hpp"
#include "nav/estimator/upf_types.hpp"

namespace nav::estimator {

/// Unscented particle filter over Vec<N> (see the file comment). Models are passed to each
/// call, so one filter can fuse several measurement types and the host can move a model's
/// nominal trajectory between calls.
template <int N>
class UnscentedParticleFilter {
 public:
  static constexpr int kSigmaPoints = UnscentedWeights<N>::kPoints;  ///< 2N + 1 per particle

  /// N_p copies of (x0, P0) with equal weights; draws come from a generator seeded with
  /// `seed`. params must pass validate(); x0 finite, P0 positive definite (contracts).
  UnscentedParticleFilter(const UpfParams& params, std::uint64_t seed, const Vec<N>& x0,
                          const Mat<N, N>& P0)
      : params_(params),
        weights_(unscented_weights<N>(params.unscented)),
        rng_(seed),
        particles_(checked_count(params)),
        log_w_(particles_.size()),
        w_(particles_.size()),
        log_w_new_(particles_.size()),
        x_new_(particles_.size()),
        P_new_(particles_.size()),
        ancestors_(particles_.size()) {
    NAV_ENSURE(reset(x0, P0) == StepStatus::kApplied,
               "UPF initial state must be finite and its covariance positive definite");
  }

  /// Back to N_p copies of (x0, P0) with equal weights; the generator is not reseeded. x0 not
  /// finite or P0 not positive definite → kRejectedInvalid, nothing changed.
  StepStatus reset(const Vec<N>& x0, const Mat<N, N>& P0) {
    const Eigen::LLT<Mat<N, N>> llt(P0);
    if (!x0.allFinite() || !P0.allFinite() || llt.info() != Eigen::Success) {
      return StepStatus::kRejectedInvalid;
    }
    for (Particle& p : particles_) {
      p = Particle{x0, P0, false};
    }
    set_uniform_weights();
    shared_ = false;
    uniform_ = true;
    P_common_ = P0;
    point_common_ = false;
    return StepStatus::kApplied;
  }

  /// Propagates every live particle by Δt = dt_s [s] with input u (P1, P2; P13 for a
  /// UpfSharedCovarianceProcess while every P_i is equal).
  template <class Process>
    requires UpfProcessModel<Process, N>
  UpfPredictReport predict(const Process& process, const typename Process::Input& u,
                           double dt_s) {
    UpfPredictReport report;
    if (!std::isfinite(dt_s) || dt_s <= 0.0 || !input_valid(process, u)) {
      return report;  // kRejectedInvalid
    }
    const Mat<N, N> Q = process.Q(u, dt_s);
    if (!Q.allFinite()) {
      return report;
    }
    const Eigen::LLT<Mat<N, N>> Q_llt(Q);
    if (Q_llt.info() != Eigen::Success) {  // a particle filter cannot move a noise-free state
      report.status = UnscentedStatus::kCholeskyFailed;
      return report;
    }
    if constexpr (UpfSharedCovarianceProcess<Process, N>) {
      if (uniform_) return predict_shared(process, u, dt_s, Q);
    }
    materialise();
    const auto f = [&process, &u, dt_s](const Vec<N>& x) -> Vec<N> {
      return process.f(x, u, dt_s);
    };
    int survivors = 0;
    UnscentedStatus first_failure = UnscentedStatus::kOk;
    for (std::size_t i = 0; i < particles_.size(); ++i) {
      log_w_new_[i] = 0.0;  // drop mark: −Inf when this particle fails below
      if (dead(i)) continue;
      Particle& p = particles_[i];
      UnscentedStatus s = UnscentedStatus::kOk;
      if (p.point) {
        const Vec<N> x_next = f(p.x);                                    // (P1)
        if (x_next.allFinite()) {
          p = Particle{x_next, Q, false};
        } else {
          s = UnscentedStatus::kNonFinite;
        }
      } else {
        s = ukf_predict<N>(p.x, p.P, weights_, f, Q);                    // (P2)
      }
      if (s == UnscentedStatus::kOk) {
        ++survivors;
      } else {
        if (first_failure == UnscentedStatus::kOk) first_failure = s;
        log_w_new_[i] = kMinusInf;  // marked; applied below once a survivor is known
        ++report.failed_particles;
      }
    }
    if (survivors == 0) {  // no particle was changed
      report.status = first_failure;
      return report;
    }
    uniform_ = false;  // the UKF predicts of different points give different P_i
    drop_marked(report.failed_particles);
    report.status = UnscentedStatus::kOk;
    return report;
  }

  /// Fuses z (P3..P9; P14, P15 for a UpfLinearMeasurement while every P_i is equal). `gate`
  /// > 0 refuses the update when the filter's NIS exceeds it.
  template <class Meas>
    requires UpfMeasurementModel<Meas, N>
  UpfUpdateReport<Meas::kMeasDim> update(const Meas& meas, const Vec<Meas::kMeasDim>& z,
                                         double gate = 0.0) {
    constexpr int M = Meas::kMeasDim;
    UpfUpdateReport<M> report;
    report.gate = gate;
    const Mat<M, M> R = meas.R();
    if (!z.allFinite() || !R.allFinite()) {
      report.status = UpdateStatus::kRejectedInvalid;
      return report;
    }
    const Eigen::LLT<Mat<M, M>> R_llt(R);
    const Mat<M, M> L_R = R_llt.matrixL();
    if (R_llt.info() != Eigen::Success || !L_R.allFinite()) {
      report.status = UpdateStatus::kNumericalFault;
      return report;
    }
    if constexpr (UpfLinearMeasurement<Meas, N>) {
      if (uniform_) {
        update_shared(meas, z, R, L_R, gate, report);
        return report;
      }
    }
    if (params_.weighting == UpfWeighting::kLikelihood) materialise();  // each keeps its P̂_i
    const auto h = [&meas](const Vec<N>& x) -> Vec<M> { return meas.h(x); };
    const Rng rng_before = rng_;
    Moments<M> mom;
    for (std::size_t i = 0; i < particles_.size(); ++i) {
      log_w_new_[i] = kMinusInf;
      x_new_[i] = particles_[i].x;
      if (dead(i)) continue;
      const Particle& p = particles_[i];
      Vec<M> y_i = Vec<M>::Zero();
      Mat<M, M> S_i = Mat<M, M>::Zero();
      double log_increment = 0.0;
      if (point_of(i)) {  // identity transition: reweight only (P7)
        y_i = z - h(p.x);
        S_i = R;
        log_increment = gaussian_log_density<M>(y_i, L_R);
      } else {
        Vec<N> x_hat = p.x;
        Mat<N, N> P_hat = prior_of(i);  // the shared P for every particle (P16)
        UkfFactors<N> fac;
        const UpdateReport<M> ukf = ukf_update<N, M>(x_hat, P_hat, weights_, h, z, R, 0.0, &fac);
        if (ukf.status != UpdateStatus::kFused) {  // proposal (P3)
          ++report.failed_particles;
          continue;
        }
        const Vec<N> xi = draw_normal();
        const Vec<N> x_tilde = x_hat + fac.L_post * xi;                    // (P4)
        const double log_lik = gaussian_log_density<M>(z - h(x_tilde), L_R);
        if (params_.weighting == UpfWeighting::kLikelihood) {
          log_increment = log_lik;                                        // (L5)
          P_new_[i] = P_hat;                                              // (L6)
        } else {
          const double log_q = -0.5 * xi.squaredNorm() -
                               fac.L_post.diagonal().array().log().sum() -
                               0.5 * N * std::log(2.0 * std::numbers::pi);  // ln q (W6)
          const double log_prior = gaussian_log_density<N>(x_tilde - p.x, fac.L_prior);
          log_increment = log_lik + log_prior - log_q;                    // (P5)
        }
        x_new_[i] = x_tilde;
        y_i = ukf.y;
        S_i = ukf.S;
      }
      if (!std::isfinite(log_increment) || !x_new_[i].allFinite() || !y_i.allFinite()) {
        x_new_[i] = p.x;
        ++report.failed_particles;
        continue;
      }
      log_w_new_[i] = log_w_[i] + log_increment;
      mom.add(w_[i], y_i, S_i);
    }
    finish_update(mom, gate, rng_before, report);
    return report;
  }

  /// Fuses z into every particle's UKF without a draw and without touching the weights (C1):
  /// for a measurement the weights do not use (paper P1's magnetometer). The gate and the
  /// refusals are update()'s; a point particle's UKF has nothing to correct.
  template <class Meas>
    requires UpfMeasurementModel<Meas, N>
  UpfUpdateReport<Meas::kMeasDim> correct(const Meas& meas, const Vec<Meas::kMeasDim>& z,
                                          double gate = 0.0);

  /// Moves every particle by −delta (P12). Non-finite delta → kRejectedInvalid, unchanged.
  StepStatus shift(const Vec<N>& delta) {
    if (!delta.allFinite()) {
      return StepStatus::kRejectedInvalid;
    }
    for (Particle& p : particles_) p.x -= delta;
    return StepStatus::kApplied;
  }

  /// Weighted mean x̄ = Σ w_i x_i (P10), in the state's units.
  Vec<N> mean() const {
    Vec<N> x_bar = Vec<N>::Zero();
    for (std::size_t i = 0; i < particles_.size(); ++i) {
      if (w_[i] > 0.0) x_bar += w_[i] * particles_[i].x;
    }
    return x_bar;
  }

  /// Mixture covariance Σ w_i P_i + Σ w_i (x_i − x̄)(x_i − x̄)ᵀ (P11), in the state's units².
  Mat<N, N> covariance() const {
    const Vec<N> x_bar = mean();
    Mat<N, N> P_bar = Mat<N, N>::Zero();
    double w_live = 0.0;
    for (std::size_t i = 0; i < particles_.size(); ++i) {
      if (!(w_[i] > 0.0)) continue;
      const Vec<N> d = particles_[i].x - x_bar;
      P_bar += w_[i] * d * d.transpose();
      w_live += w_[i];
      if (!shared_ && !particles_[i].point) P_bar += w_[i] * particles_[i].P;
    }
    if (shared_ && !point_common_) P_bar += w_live * P_common_;  // Σ w_i P for one P (P13)
    symmetrize(P_bar);
    return P_bar;
  }

  /// Effective sample size 1/Σ w² of the current weights [-].
  double ess() const { return effective_sample_size(w_); }
  /// N_p [-].
  int particle_count() const { return static_cast<int>(particles_.size()); }
  /// Normalised weights w_i (Σ = 1; 0 for a dropped particle) [-].
  std::span<const double> weights() const { return w_; }
  /// Normalised log-weights ln w_i (−Inf for a dropped particle) [-].
  std::span<const double> log_weights() const { return log_w_; }
  /// x_i of particle i, 0 <= i < N_p (contract).
  const Vec<N>& particle_state(int i) const { return particle(i).x; }
  /// P_i of particle i (zero for a point particle), 0 <= i < N_p (contract).
  const Mat<N, N>& particle_covariance(int i) const {
    const Particle& p = particle(i);
    return shared_ ? P_common_ : p.P;
  }
  /// True while the particles share one covariance (P13..P16), false on the generic path.
  bool shares_covariance() const { return shared_; }
  /// The sigma-point weights of every particle's UKF.
  const UnscentedWeights<N>& sigma_weights() const { return weights_; }
  /// The parameters given at construction.
  const UpfParams& params() const { return params_; }

 private:
  struct Particle {
    Vec<N> x;      ///< x_i, the state's units
    Mat<N, N> P;   ///< P_i, the state's units² (0 for a point); stale while shared_
    bool point;    ///< P_i = 0: a sample, not yet propagated; stale while shared_
  };

  /// Prior-weighted sums of the survivors' innovations, for the filter's y and S.
  template <int M>
  struct Moments {
    double w_sum = 0.0;  ///< prior weight of the particles that survive
    Vec<M> y_sum = Vec<M>::Zero();
    Mat<M, M> yy_sum = Mat<M, M>::Zero();
    Mat<M, M> S_sum = Mat<M, M>::Zero();
    void add(double w, const Vec<M>& y, const Mat<M, M>& S) {
      w_sum += w;
      y_sum += w * y;
      yy_sum += w * y * y.transpose();
      S_sum += w * S;
    }
  };

  static constexpr double kMinusInf = -std::numeric_limits<double>::infinity();

  static std::size_t checked_count(const UpfParams& params) {
    const Result<void> ok = validate(params, N);
    NAV_ENSURE(ok.has_value(), ok.error().detail);
    return static_cast<std::size_t>(params.particle_count);
  }

  template <class Process>
  static bool input_valid(const Process& process, const typename Process::Input& u) {
    if constexpr (requires { { process.input_valid(u) } -> std::convertible_to<bool>; }) {
      return process.input_valid(u);
    } else if constexpr (requires { { u.allFinite() } -> std::convertible_to<bool>; }) {
      return u.allFinite();
    } else if constexpr (std::is_arithmetic_v<typename Process::Input>) {
      return std::isfinite(static_cast<double>(u));
    } else {
      return true;
    }
  }

  const Particle& particle(int i) const {
    NAV_ENSURE(i >= 0 && i < particle_count(), "UPF particle index out of range");
    return particles_[static_cast<std::size_t>(i)];
  }

  bool dead(std::size_t i) const { return log_w_[i] == kMinusInf; }
  bool point_of(std::size_t i) const { return shared_ ? point_common_ : particles_[i].point; }
  const Mat<N, N>& prior_of(std::size_t i) const { return shared_ ? P_common_ : particles_[i].P; }

  Vec<N> draw_normal() {
    Vec<N> xi;
    for (int k = 0; k < N; ++k) xi(k) = rng_.normal();
    return xi;
  }

  /// Leaves the shared representation: every particle gets the common P (no value changes).
  void materialise() {
    if (!shared_) return;
    for (Particle& p : particles_) {
      p.P = P_common_;
      p.point = point_common_;
    }
    shared_ = false;
  }

  /// Applies the drop marks a predict left in log_w_new_ (a survivor exists: cannot fail).
  void drop_marked(int failed) {
    if (failed == 0) return;
    for (std::size_t i = 0; i < particles_.size(); ++i) {
      if (!dead(i) && log_w_new_[i] == kMinusInf) log_w_[i] = kMinusInf;
    }
    normalize_log_weights(log_w_, w_);
  }

  // The shared path (P13..P16), defined in upf_shared.hpp.
  template <class Process>
  UpfPredictReport predict_shared(const Process& process, const typename Process::Input& u,
                                  double dt_s, const Mat<N, N>& Q);
  template <class Meas, int M>
  void update_shared(const Meas& meas, const Vec<M>& z, const Mat<M, M>& R,
                     const Mat<M, M>& L_R, double gate, UpfUpdateReport<M>& report);
  template <class Meas, int M>
  void correct_shared(const Meas& meas, const Vec<M>& z, const Mat<M, M>& R, double gate,
                      UpfUpdateReport<M>& report);
  template <int M>
  bool shared_gain(const Mat<M, N>& H, const Mat<M, M>& R, Mat<M, M>& S, Mat<M, M>& L_S,
                   Mat<N, M>& K, Mat<N, N>& L_post, Mat<N, N>& P_post) const;

  /// The filter's y and S, NIS and gate from the survivors' moments; false (report says why)
  /// when the update is refused (upf_update.hpp).
  template <int M>
  static bool judge(const Moments<M>& mom, double gate, UpfUpdateReport<M>& report);
  /// Takes the update's log-weights, normalises them (P8), fills the ESS; fused.
  template <int M>
  void commit_weights(UpfUpdateReport<M>& report);
  /// The end of every update: judge, commit (P6 or L6), P8, P9; refused → rng_ restored and
  /// nothing changed. P_shared_post: the shared path's P̂ (L6), null otherwise.
  template <int M>
  void finish_update(const Moments<M>& mom, double gate, const Rng& rng_before,
                     UpfUpdateReport<M>& report, const Mat<N, N>* P_shared_post = nullptr);
  /// Systematic resampling (P9) after a commit.
  void resample();

  /// After a fused update every live particle is a point (a dropped one forces P9).
  void set_common_point() {
    uniform_ = true;
    P_common_.setZero();
    point_common_ = true;
  }

  void set_uniform_weights() {
    const double n = static_cast<double>(particles_.size());
    for (std::size_t i = 0; i < particles_.size(); ++i) {
      log_w_[i] = -std::log(n);
      w_[i] = 1.0 / n;
    }
  }

  UpfParams params_;
  UnscentedWeights<N> weights_;
  Rng rng_;
  std::vector<Particle> particles_;
  std::vector<double> log_w_;      ///< normalised ln w_i
  std::vector<double> w_;          ///< normalised w_i
  std::vector<double> log_w_new_;  ///< scratch: the update's ln w_i, the predict's drop marks
  std::vector<Vec<N>> x_new_;      ///< scratch: samples x̃_i, propagated and resampled states
  std::vector<Mat<N, N>> P_new_;   ///< scratch: posteriors P̂_i (L6, C1), resampled P_i
  std::vector<std::size_t> ancestors_;  ///< scratch: systematic resampling's a_j
  /// Every live particle has covariance P_common_ and point flag point_common_ (after reset
  /// and after every fused update; a generic predict ends it).
  bool uniform_ = true;
  /// The per-particle P and point are stale; P_common_, point_common_ hold them (P13..P16).
  bool shared_ = false;
  Mat<N, N> P_common_ = Mat<N, N>::Zero();
  bool point_common_ = false;
};

}  // namespace nav::estimator

#include "nav/estimator/upf_shared.hpp"  // IWYU pragma: export
#include "nav/estimator/upf_update.hpp"  // IWYU pragma: export

// SPDX-License-Identifier: MIT
// The unscented particle filter's parameters, model concepts and reports (the filter is
// upf.hpp, whose labels P1..P16 and L5, L6 these comments use).
#pragma once

#include <concepts>

#include "nav/common/result.hpp"
#include "nav/estimator/linear_kf.hpp"
#include "nav/estimator/unscented.hpp"
#include "nav/estimator/update_report.hpp"

namespace nav::estimator {

/// How an update weighs a particle and what the particle keeps (upf.hpp P5, P6 / L5, L6).
enum class UpfWeighting {
  /// The reference UPF's importance weight, likelihood × prior / proposal; the particle
  /// becomes the point it drew (P5, P6). Converges to the Kalman filter on a linear-Gaussian
  /// model; needs the proposal to span the transition since the last update.
  kOptimalProposal,
  /// Paper P1's: the GPS likelihood of the drawn state alone; the particle keeps its UKF's
  /// posterior covariance and goes on as a UKF (L5, L6).
  kLikelihood,
};

/// Parameters of an UnscentedParticleFilter.
struct UpfParams {
  /// N_p, fixed at construction, >= 1 [-].
  int particle_count = 250;
  /// Resample when ESS < this × N_p, in (0, 1]; 1 resamples at almost every update [-].
  double resample_threshold = 0.5;
  /// Sigma points of every particle's UKF (defaults α = 1, β = 2, κ = 0; unscented.hpp).
  UnscentedParams unscented{};
  /// What an update weighs and keeps (UpfWeighting).
  UpfWeighting weighting = UpfWeighting::kOptimalProposal;
};

/// Checks the particle count, the threshold and the unscented parameters for state dimension n.
Result<void> validate(const UpfParams& p, int n);

/// A process model for the UPF: x_k = f(x_{k−1}, u, Δt) + q, q ~ N(0, Q(u, Δt)), Q positive
/// definite. Input is the model's control/nominal-trajectory type. Optional: a member
/// `bool input_valid(const Input&) const`; otherwise an Eigen input is checked with allFinite()
/// and an arithmetic one with std::isfinite.
template <class P, int N>
concept UpfProcessModel = requires(const P& p, const Vec<N>& x, const typename P::Input& u,
                                   double dt_s) {
  { p.f(x, u, dt_s) } -> std::convertible_to<Vec<N>>;
  { p.Q(u, dt_s) } -> std::convertible_to<Mat<N, N>>;
};

/// A measurement model for the UPF: z = h(x) + v, v ~ N(0, R), z of dimension kMeasDim.
template <class H, int N>
concept UpfMeasurementModel = requires(const H& m, const Vec<N>& x) {
  { H::kMeasDim } -> std::convertible_to<int>;
  { m.h(x) } -> std::convertible_to<Vec<H::kMeasDim>>;
  { m.R() } -> std::convertible_to<Mat<H::kMeasDim, H::kMeasDim>>;
};

/// A process the UPF may propagate with one shared covariance (P13): f(x, u, Δt) =
/// Φ(u, Δt) x + b(u, Δt) exactly, Q independent of x. The model declares it; the filter
/// cannot check it.
template <class P, int N>
concept UpfSharedCovarianceProcess =
    UpfProcessModel<P, N> && P::kSharedCovariance &&
    requires(const P& p, const typename P::Input& u, double dt_s) {
      { p.Phi(u, dt_s) } -> std::convertible_to<Mat<N, N>>;
    };

/// A measurement the UPF may update with one shared gain (P14): h(x) = H x + c exactly.
template <class H, int N>
concept UpfLinearMeasurement = UpfMeasurementModel<H, N> && H::kLinear && requires(const H& m) {
  { m.H() } -> std::convertible_to<Mat<H::kMeasDim, N>>;
};

/// What a UPF predict did.
struct UpfPredictReport {
  /// kOk when at least one particle was propagated; otherwise why nothing changed.
  UnscentedStatus status = UnscentedStatus::kRejectedInvalid;
  int failed_particles = 0;  ///< particles dropped in this step (weight set to 0) [-]
};

/// What a UPF update did. y, S are the filter's innovation z − Σ w_i ẑ_i and its mixture
/// covariance Σ w_i (S_i + (y_i − y)(y_i − y)ᵀ) (prior weights); nis = yᵀ S⁻¹ y is what the
/// gate tests.
template <int M>
struct UpfUpdateReport : UpdateReport<M> {
  double ess = 0.0;          ///< effective sample size after weighting, before resampling [-]
  bool resampled = false;    ///< the particles were resampled (then ESS = N_p again)
  int failed_particles = 0;  ///< particles dropped in this update (weight set to 0) [-]
};

}  // namespace nav::estimator

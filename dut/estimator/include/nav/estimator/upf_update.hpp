// SPDX-License-Identifier: MIT
// The update's common end and the correction of the unscented particle filter (upf.hpp, which
// includes this file at its end; do not include it alone): the filter's innovation and gate,
// the commit of P6 or L6, the weights (P8), systematic resampling (P9), and C1. Labels are
// upf.hpp's.
#pragma once

#include "nav/estimator/upf.hpp"

namespace nav::estimator {

/// Fuses z into every particle's UKF without a draw and without touching the weights (C1):
/// for a measurement the weights do not use (paper P1's magnetometer). The gate and the
/// refusals are update()'s; a point particle's UKF has nothing to correct.
template <int N>
template <class Meas>
  requires UpfMeasurementModel<Meas, N>
UpfUpdateReport<Meas::kMeasDim> UnscentedParticleFilter<N>::correct(
    const Meas& meas, const Vec<Meas::kMeasDim>& z, double gate) {
  constexpr int M = Meas::kMeasDim;
  UpfUpdateReport<M> report;
  report.gate = gate;
  const Mat<M, M> R = meas.R();
  if (!z.allFinite() || !R.allFinite() || Eigen::LLT<Mat<M, M>>(R).info() != Eigen::Success) {
    report.status = z.allFinite() && R.allFinite() ? UpdateStatus::kNumericalFault
                                                   : UpdateStatus::kRejectedInvalid;
    return report;
  }
  if constexpr (UpfLinearMeasurement<Meas, N>) {
    if (uniform_) {
      correct_shared(meas, z, R, gate, report);
      return report;
    }
  }
  materialise();
  const auto h = [&meas](const Vec<N>& x) -> Vec<M> { return meas.h(x); };
  Moments<M> mom;
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    log_w_new_[i] = kMinusInf;
    x_new_[i] = particles_[i].x;
    P_new_[i] = particles_[i].P;
    if (dead(i)) continue;
    if (particles_[i].point) {
      const Vec<M> y_i = z - h(particles_[i].x);
      if (!y_i.allFinite()) {
        ++report.failed_particles;
        continue;
      }
      log_w_new_[i] = log_w_[i];
      mom.add(w_[i], y_i, R);
      continue;
    }
    const UpdateReport<M> ukf = ukf_update<N, M>(x_new_[i], P_new_[i], weights_, h, z, R);
    if (ukf.status != UpdateStatus::kFused || !x_new_[i].allFinite()) {     // (C1)
      ++report.failed_particles;
      continue;
    }
    log_w_new_[i] = log_w_[i];
    mom.add(w_[i], ukf.y, ukf.S);
  }
  if (!judge(mom, gate, report)) return report;
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    if (log_w_new_[i] == kMinusInf) continue;
    particles_[i].x = x_new_[i];
    particles_[i].P = P_new_[i];
  }
  uniform_ = false;
  commit_weights(report);
  return report;
}

/// The filter's y and S, NIS and gate from the survivors' moments; false (report says why)
/// when the update is refused.
template <int N>
template <int M>
bool UnscentedParticleFilter<N>::judge(const Moments<M>& mom, double gate,
                                       UpfUpdateReport<M>& report) {
  if (!(mom.w_sum > 0.0)) {  // no survivor (or only survivors of underflowed weight)
    report.status = UpdateStatus::kNumericalFault;
    return false;
  }
  const Vec<M> y = mom.y_sum / mom.w_sum;
  Mat<M, M> S = mom.S_sum / mom.w_sum + mom.yy_sum / mom.w_sum - y * y.transpose();
  symmetrize(S);
  report.y = y;
  report.S = S;
  const Eigen::LDLT<Mat<M, M>> S_ldlt(S);
  report.nis = y.dot(S_ldlt.solve(y));
  if (S_ldlt.info() != Eigen::Success || !S_ldlt.isPositive() ||
      !(S_ldlt.vectorD().array() > 0.0).all() || !std::isfinite(report.nis)) {
    report.status = UpdateStatus::kNumericalFault;
    return false;
  }
  if (gate > 0.0 && report.nis > gate) {
    report.status = UpdateStatus::kRejectedGate;
    return false;
  }
  return true;
}

/// Takes the update's log-weights (the dropped at −Inf), normalises them (P8) and fills the
/// report's ESS; the update is fused.
template <int N>
template <int M>
void UnscentedParticleFilter<N>::commit_weights(UpfUpdateReport<M>& report) {
  log_w_.swap(log_w_new_);
  normalize_log_weights(log_w_, w_);                                    // (P8)
  report.ess = effective_sample_size(w_);                               // (P8)
  report.status = UpdateStatus::kFused;
}

/// The end of every update: judge; then commit (P6 or L6), normalise (P8) and resample
/// (P9). Refused → rng_ restored and nothing changed. P_shared_post: the shared path's P̂
/// (L6), null otherwise.
template <int N>
template <int M>
void UnscentedParticleFilter<N>::finish_update(const Moments<M>& mom, double gate,
                                               const Rng& rng_before,
                                               UpfUpdateReport<M>& report,
                                               const Mat<N, N>* P_shared_post) {
  if (!judge(mom, gate, report)) {
    rng_ = rng_before;
    return;
  }
  const bool keep = params_.weighting == UpfWeighting::kLikelihood;
  // Commit: survivors become points (P6) or keep their UKF's posterior (L6); the dropped
  // keep their state with weight 0.
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    if (log_w_new_[i] == kMinusInf) continue;
    particles_[i].x = x_new_[i];
    if (!shared_) {
      particles_[i].P = keep ? P_new_[i] : Mat<N, N>::Zero();
      particles_[i].point = !keep;
    }
  }
  if (!keep) {
    set_common_point();
  } else if (shared_ && P_shared_post != nullptr) {
    P_common_ = *P_shared_post;
    point_common_ = false;
  } else {
    uniform_ = false;
  }
  commit_weights(report);
  bool any_zero = false;
  for (const double wi : w_) any_zero = any_zero || wi == 0.0;
  if (any_zero || report.ess < params_.resample_threshold * static_cast<double>(w_.size())) {
    resample();                                                         // (P9)
    report.resampled = true;
  }
}

/// Systematic resampling (P9), after a commit: each particle j becomes a copy of its
/// ancestor a_j (state, covariance and point flag).
template <int N>
void UnscentedParticleFilter<N>::resample() {
  systematic_resample(w_, rng_, ancestors_);  // w_ normalised and valid: cannot fail
  for (std::size_t j = 0; j < particles_.size(); ++j) {
    x_new_[j] = particles_[ancestors_[j]].x;
    if (!shared_) P_new_[j] = particles_[ancestors_[j]].P;
  }
  for (std::size_t j = 0; j < particles_.size(); ++j) {
    particles_[j].x = x_new_[j];
    if (!shared_) {
      particles_[j].P = P_new_[j];
      particles_[j].point = params_.weighting == UpfWeighting::kOptimalProposal;  // as committed
    }
  }
  set_uniform_weights();
}

}  // namespace nav::estimator

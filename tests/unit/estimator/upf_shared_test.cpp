// SPDX-License-Identifier: MIT
// The unscented particle filter's shared-covariance path (upf_shared.hpp) against the generic
// one, paper P1's weighting (upf.hpp L5, L6: weights from the likelihood of each draw alone,
// each particle keeping its posterior, through resampling too) on both paths, the correction
// without a draw (C1), and P1's dimensions (15 and 9 states, 250 particles). Every seed is
// fixed.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "nav/estimator/upf.hpp"
#include "upf_test_support.hpp"

namespace nav::estimator {
namespace {

using namespace upf_testing;  // NOLINT(google-build-using-namespace): the tests' own helpers

/// CvProcess declaring what it is: affine in x with a state-independent Q (upf.hpp P13).
struct SharedCvProcess : CvProcess {
  static constexpr bool kSharedCovariance = true;
  Mat<2, 2> Phi(const double& /*a*/, double dt) const { return F(dt); }
};

/// PositionMeas declaring h = H x (upf.hpp P14).
struct LinearPositionMeas : PositionMeas {
  static constexpr bool kLinear = true;
  Mat<1, 2> H() const { return Mat<1, 2>(1.0, 0.0); }
};

static_assert(UpfSharedCovarianceProcess<SharedCvProcess, 2>);
static_assert(!UpfSharedCovarianceProcess<CvProcess, 2>);
static_assert(UpfLinearMeasurement<LinearPositionMeas, 2>);
static_assert(!UpfLinearMeasurement<PositionMeas, 2>);

/// Largest difference between two filters' particle states, and between their log-weights.
template <int N>
std::pair<double, double> max_difference(const UnscentedParticleFilter<N>& a,
                                         const UnscentedParticleFilter<N>& b) {
  double dx = 0.0, dl = 0.0;
  for (int i = 0; i < a.particle_count(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    dx = std::max(dx, (a.particle_state(i) - b.particle_state(i)).cwiseAbs().maxCoeff());
    dl = std::max(dl, std::abs(a.log_weights()[k] - b.log_weights()[k]));
  }
  return {dx, dl};
}

/// Paper P1's weighting (upf.hpp L5, L6) with a threshold that never resamples.
UpfParams likelihood_params(int particles) {
  UpfParams p = params_with(particles, 1e-9);
  p.weighting = UpfWeighting::kLikelihood;
  return p;
}

/// The Kalman filter's posterior covariance from a prior P for PositionMeas [m², m/s ...].
Mat<2, 2> kf_posterior(const Mat<2, 2>& P, double r) {
  const Mat<1, 2> H(1.0, 0.0);
  const double S = (H * P * H.transpose())(0, 0) + r;
  const Vec<2> K = P * H.transpose() / S;
  return P - K * S * K.transpose();
}

/// After L5/L6: each particle keeps the (UKF = KF) posterior covariance, and the weights
/// differ by the GPS likelihood of each particle's draw alone: ln w_i − ln w_j =
/// ln N(z; x̃_i, r) − ln N(z; x̃_j, r) from uniform prior weights.
template <class Process, class Meas>
void check_likelihood_update(const Process& process, const Meas& meas, bool expect_shared) {
  UnscentedParticleFilter<2> upf(likelihood_params(30), 17, kX0, kP0);
  for (int j = 0; j < 5; ++j) {
    ASSERT_EQ(upf.predict(process, 0.1, CvRun::kDt).status, UnscentedStatus::kOk);
  }
  const Mat<2, 2> prior = upf.particle_covariance(0);
  const Vec<1> z(1.5);
  const UpfUpdateReport<1> r = upf.update(meas, z);
  ASSERT_EQ(r.status, UpdateStatus::kFused);
  EXPECT_FALSE(r.resampled);
  EXPECT_EQ(upf.shares_covariance(), expect_shared);
  const Mat<2, 2> post = kf_posterior(prior, meas.r);
  const auto lik = [&](int i) {
    const double y = z(0) - upf.particle_state(i)(0);
    return -0.5 * y * y / meas.r;  // ln N(z; x̃_i, r) up to a constant
  };
  for (int i = 0; i < upf.particle_count(); ++i) {
    EXPECT_LT((upf.particle_covariance(i) - post).cwiseAbs().maxCoeff(), 1e-9) << i;  // (L6)
    const auto k = static_cast<std::size_t>(i);
    EXPECT_NEAR(upf.log_weights()[k] - upf.log_weights()[0], lik(i) - lik(0), 1e-9) << i;
  }
  // The mixture: the kept posterior plus the spread of the draws (P11).
  EXPECT_GT(upf.covariance()(0, 0), post(0, 0));
}

TEST(Upf, LikelihoodWeightingWeighsByTheFixAndKeepsEachPosterior) {
  check_likelihood_update(CvProcess{}, PositionMeas{}, /*expect_shared=*/false);
  check_likelihood_update(SharedCvProcess{}, LinearPositionMeas{}, /*expect_shared=*/true);
}

TEST(Upf, LikelihoodWeightingGivesTheSameNumbersOnBothPaths) {
  UnscentedParticleFilter<2> generic(likelihood_params(40), 5, kX0, kP0);
  UnscentedParticleFilter<2> shared(likelihood_params(40), 5, kX0, kP0);
  const CvRun run(30, 8, CvProcess{}, PositionMeas{});
  std::size_t predict = 0;
  for (std::size_t k = 0; k < run.z.size(); ++k) {
    for (int j = 0; j < CvRun::kPredictsPerUpdate; ++j, ++predict) {
      ASSERT_EQ(generic.predict(CvProcess{}, run.a[predict], CvRun::kDt).status,
                UnscentedStatus::kOk);
      ASSERT_EQ(shared.predict(SharedCvProcess{}, run.a[predict], CvRun::kDt).status,
                UnscentedStatus::kOk);
    }
    ASSERT_EQ(generic.update(PositionMeas{}, run.z[k]).status, UpdateStatus::kFused);
    ASSERT_EQ(shared.update(LinearPositionMeas{}, run.z[k]).status, UpdateStatus::kFused);
    const auto [dx, dl] = max_difference(generic, shared);
    ASSERT_LT(dx, 1e-9) << k;
    ASSERT_LT(dl, 1e-9) << k;
  }
  EXPECT_TRUE(shared.shares_covariance());
}

/// C1: correct() moves every particle by the Kalman gain and leaves the weights exactly.
template <class Process, class Meas>
void check_correct(const Process& process, const Meas& meas) {
  UnscentedParticleFilter<2> upf(likelihood_params(20), 3, kX0, kP0);
  ASSERT_EQ(upf.predict(process, 0.0, CvRun::kDt).status, UnscentedStatus::kOk);
  ASSERT_EQ(upf.update(meas, Vec<1>(0.7)).status, UpdateStatus::kFused);  // uneven weights
  ASSERT_EQ(upf.predict(process, 0.0, CvRun::kDt).status, UnscentedStatus::kOk);
  const Snapshot<2> before(upf);
  const Mat<2, 2> prior = upf.particle_covariance(0);
  const Vec<1> z(-0.4);
  const UpfUpdateReport<1> r = upf.correct(meas, z);
  ASSERT_EQ(r.status, UpdateStatus::kFused);
  const Mat<2, 2> post = kf_posterior(prior, meas.r);
  const Vec<2> K = prior.col(0) / (prior(0, 0) + meas.r);
  for (int i = 0; i < upf.particle_count(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    const Vec<2> expected = before.x[k] + K * (z(0) - before.x[k](0));
    EXPECT_LT((upf.particle_state(i) - expected).cwiseAbs().maxCoeff(), 1e-9) << i;
    EXPECT_LT((upf.particle_covariance(i) - post).cwiseAbs().maxCoeff(), 1e-9) << i;
    EXPECT_EQ(upf.log_weights()[k], before.log_w[k]) << i;
  }
  // Refused: nothing changes.
  const Snapshot<2> after(upf);
  EXPECT_EQ(upf.correct(meas, Vec<1>(kNaN)).status, UpdateStatus::kRejectedInvalid);
  EXPECT_EQ(upf.correct(meas, Vec<1>(1e6), 9.0).status, UpdateStatus::kRejectedGate);
  EXPECT_TRUE(Snapshot<2>(upf) == after);
}

TEST(Upf, CorrectFusesEveryParticleWithoutADrawOrAWeightChange) {
  check_correct(CvProcess{}, PositionMeas{});
  check_correct(SharedCvProcess{}, LinearPositionMeas{});
}

TEST(Upf, ResamplingKeepsEachParticlesCovarianceUnderLikelihoodWeighting) {
  UpfParams p = params_with(25, 1.0);  // resample at every update
  p.weighting = UpfWeighting::kLikelihood;
  UnscentedParticleFilter<2> upf(p, 9, kX0, kP0);
  ASSERT_EQ(upf.predict(CvProcess{}, 0.0, CvRun::kDt).status, UnscentedStatus::kOk);
  const UpfUpdateReport<1> r = upf.update(PositionMeas{}, Vec<1>(2.0));
  ASSERT_EQ(r.status, UpdateStatus::kFused);
  ASSERT_TRUE(r.resampled);
  for (int i = 0; i < upf.particle_count(); ++i) {
    EXPECT_GT(upf.particle_covariance(i)(0, 0), 0.1) << i;  // a UKF still, not a point
    EXPECT_DOUBLE_EQ(upf.weights()[static_cast<std::size_t>(i)], 1.0 / 25.0);
  }
}

TEST(Upf, SharedCovariancePathMatchesTheGenericPathForOneSeed) {
  // The CV model is linear-Gaussian, so the shared path (P13..P15) is mathematically the
  // generic one (P1..P9): same seed, same draws in the same order; only round-off differs
  // (UKF sigma points against H P Hᵀ, three densities against the closed form of P15). Tight
  // bounds: particle states within 1e-9 m (≈ 1e-10 of the spread), log-weights within 1e-9,
  // through 40 updates with resampling. A third filter runs the shared predict with the
  // non-linear update (P16) and matches too.
  const CvProcess generic;
  const SharedCvProcess shared;
  const PositionMeas meas;
  const LinearPositionMeas linear;
  const CvRun run(40, 3, generic, meas);
  UnscentedParticleFilter<2> a(params_with(300), 17, kX0, kP0);
  UnscentedParticleFilter<2> b(params_with(300), 17, kX0, kP0);
  UnscentedParticleFilter<2> c(params_with(300), 17, kX0, kP0);
  std::size_t predict = 0;
  int resampled = 0;
  double worst_x = 0.0, worst_l = 0.0;
  for (std::size_t k = 0; k < run.z.size(); ++k) {
    for (int j = 0; j < CvRun::kPredictsPerUpdate; ++j, ++predict) {
      ASSERT_EQ(a.predict(generic, run.a[predict], CvRun::kDt).status, UnscentedStatus::kOk);
      ASSERT_EQ(b.predict(shared, run.a[predict], CvRun::kDt).status, UnscentedStatus::kOk);
      ASSERT_EQ(c.predict(shared, run.a[predict], CvRun::kDt).status, UnscentedStatus::kOk);
      EXPECT_FALSE(a.shares_covariance());
      EXPECT_TRUE(b.shares_covariance());
      EXPECT_LT((a.particle_covariance(0) - b.particle_covariance(0)).cwiseAbs().maxCoeff(),
                1e-12);
    }
    const UpfUpdateReport<1> ra = a.update(meas, run.z[k]);
    const UpfUpdateReport<1> rb = b.update(linear, run.z[k]);
    const UpfUpdateReport<1> rc = c.update(meas, run.z[k]);
    ASSERT_EQ(ra.status, UpdateStatus::kFused);
    ASSERT_EQ(rb.status, UpdateStatus::kFused);
    ASSERT_EQ(rc.status, UpdateStatus::kFused);
    ASSERT_EQ(ra.resampled, rb.resampled) << k;
    ASSERT_EQ(ra.resampled, rc.resampled) << k;
    resampled += ra.resampled ? 1 : 0;
    EXPECT_NEAR(ra.y(0), rb.y(0), 1e-9);
    EXPECT_NEAR(ra.S(0, 0), rb.S(0, 0), 1e-9 * ra.S(0, 0));
    EXPECT_NEAR(ra.ess, rb.ess, 1e-6);
    for (const UnscentedParticleFilter<2>* f : {&b, &c}) {
      const auto [dx, dl] = max_difference(a, *f);
      worst_x = std::max(worst_x, dx);
      worst_l = std::max(worst_l, dl);
    }
  }
  EXPECT_LT(worst_x, 1e-9);
  EXPECT_LT(worst_l, 1e-9);
  EXPECT_GT(resampled, 5);  // the comparison went through resampling
  EXPECT_LT((a.mean() - b.mean()).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((a.covariance() - b.covariance()).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(Upf, SharedPathIsLeftForAGenericPredictAndRefusesLikeTheGenericOne) {
  const CvProcess generic;
  const SharedCvProcess shared;
  const LinearPositionMeas linear;
  UnscentedParticleFilter<2> upf(params_with(100), 18, kX0, kP0);
  UnscentedParticleFilter<2> twin(params_with(100), 18, kX0, kP0);
  ASSERT_EQ(upf.predict(shared, 0.1, 0.1).status, UnscentedStatus::kOk);
  ASSERT_EQ(twin.predict(generic, 0.1, 0.1).status, UnscentedStatus::kOk);
  EXPECT_TRUE(upf.shares_covariance());
  // Refusals leave everything, the generator included, untouched.
  const Snapshot<2> before(upf);
  EXPECT_EQ(upf.update(linear, Vec<1>(kNaN)).status, UpdateStatus::kRejectedInvalid);
  LinearPositionMeas zero_r;
  zero_r.r = 0.0;
  EXPECT_EQ(upf.update(zero_r, Vec<1>(1.0)).status, UpdateStatus::kNumericalFault);
  EXPECT_EQ(upf.update(linear, Vec<1>(1e4), 11.0).status, UpdateStatus::kRejectedGate);
  SharedCvProcess no_noise;
  no_noise.q = 0.0;
  EXPECT_EQ(upf.predict(no_noise, 0.0, 0.1).status, UnscentedStatus::kCholeskyFailed);
  EXPECT_TRUE(Snapshot<2>(upf) == before);
  // A generic predict after a shared one copies the shared P into every particle (same values).
  ASSERT_EQ(upf.predict(generic, 0.0, 0.1).status, UnscentedStatus::kOk);
  ASSERT_EQ(twin.predict(generic, 0.0, 0.1).status, UnscentedStatus::kOk);
  EXPECT_FALSE(upf.shares_covariance());
  // A shared predict while the P_i differ stays generic; the update returns to shared.
  ASSERT_EQ(upf.predict(shared, 0.0, 0.1).status, UnscentedStatus::kOk);
  ASSERT_EQ(twin.predict(generic, 0.0, 0.1).status, UnscentedStatus::kOk);
  EXPECT_FALSE(upf.shares_covariance());
  ASSERT_EQ(upf.update(linear, Vec<1>(0.5)).status, UpdateStatus::kFused);
  ASSERT_EQ(twin.update(PositionMeas{}, Vec<1>(0.5)).status, UpdateStatus::kFused);
  ASSERT_EQ(upf.predict(shared, 0.0, 0.1).status, UnscentedStatus::kOk);
  ASSERT_EQ(twin.predict(generic, 0.0, 0.1).status, UnscentedStatus::kOk);
  EXPECT_TRUE(upf.shares_covariance());
  const auto [dx, dl] = max_difference(upf, twin);
  EXPECT_LT(dx, 1e-9);
  EXPECT_LT(dl, 1e-9);
}

/// A linear error-state model of K states driven by F = I + Δt A, Q = Δt diag(q), measured by
/// its first three states (P1's GPS position): A couples δp ← δv and, for 15 states,
/// δv ← ρ (−[g×]) and δb_acc, ρ ← δb_gyro; for 9 states δv ← δa.
template <int K>
struct ErrorModel {
  using Input = double;  ///< unused
  Mat<K, K> A = Mat<K, K>::Zero();
  Vec<K> q = Vec<K>::Zero();  ///< noise densities, the state's units²/s
  ErrorModel() {
    A.template block<3, 3>(0, 3).setIdentity();  // δṗ = δv
    if constexpr (K == 15) {
      const double g = 9.81;  // [m/s²]
      A(3, 7) = -g;           // δv̇ = −[g×] ρ − δb_acc, g = (0, 0, g) NED
      A(4, 6) = g;
      A.template block<3, 3>(3, 9) = -Mat<3, 3>::Identity();
      A.template block<3, 3>(6, 12) = -Mat<3, 3>::Identity();  // ρ̇ = −δb_gyro
      q << Vec<3>::Constant(1e-6), Vec<3>::Constant(1e-3), Vec<3>::Constant(1e-7),
          Vec<3>::Constant(1e-8), Vec<3>::Constant(1e-12);
    } else {
      A.template block<3, 3>(3, 6).setIdentity();  // δv̇ = δa
      q << Vec<3>::Constant(1e-6), Vec<3>::Constant(1e-3), Vec<3>::Constant(1e-4);
    }
  }
  Mat<K, K> F(double dt) const { return Mat<K, K>::Identity() + dt * A; }
  Vec<K> f(const Vec<K>& x, const double&, double dt) const { return F(dt) * x; }
  Mat<K, K> Q(const double&, double dt) const { return (dt * q).asDiagonal(); }
};

template <int K>
struct GpsPosition {
  static constexpr int kMeasDim = 3;
  Vec<3> h(const Vec<K>& x) const { return x.template head<3>(); }
  Mat<3, 3> R() const { return Mat<3, 3>::Identity(); }  // 1 m per axis
};

template <int K>
void run_p1_sized(std::uint64_t seed) {
  const ErrorModel<K> model;
  const GpsPosition<K> gps;
  Vec<K> sigma0 = Vec<K>::Constant(0.01);
  sigma0.template head<6>() << 3.0, 3.0, 3.0, 0.5, 0.5, 0.5;
  const Mat<K, K> P0 = sigma0.cwiseProduct(sigma0).asDiagonal();
  UnscentedParticleFilter<K> upf(params_with(250), seed, Vec<K>::Zero(), P0);
  EXPECT_EQ(upf.sigma_weights().mean.size(), 2 * K + 1);
  Vec<K> x_kf = Vec<K>::Zero();
  Mat<K, K> P_kf = P0;
  Mat<3, K> H = Mat<3, K>::Zero();
  H.template leftCols<3>().setIdentity();
  Rng rng(seed + 1);
  for (int k = 0; k < 3; ++k) {
    for (int j = 0; j < 10; ++j) {  // 10 IMU-rate predicts per GPS fix
      ASSERT_EQ(upf.predict(model, 0.0, 0.01).status, UnscentedStatus::kOk);
      x_kf = model.F(0.01) * x_kf;
      predict_covariance<K>(P_kf, model.F(0.01), model.Q(0.0, 0.01));
    }
    const Vec<3> z(1.0 + rng.normal(), -2.0 + rng.normal(), 0.5 + rng.normal());
    const UpfUpdateReport<3> r = upf.update(gps, z);
    ASSERT_EQ(r.status, UpdateStatus::kFused);
    const UpdateReport<3> r_kf = linear_update<K, 3>(x_kf, P_kf, z, H, gps.R());
    ASSERT_EQ(r_kf.status, UpdateStatus::kFused);
    const Vec<K> x = upf.mean();
    const Mat<K, K> P = upf.covariance();
    ASSERT_TRUE(x.allFinite());
    ASSERT_TRUE(P.allFinite());
    // Position and velocity (observed, large prior) within 0.35 σ_KF with 250 particles
    // (~5 standard errors); position variance within 35 %.
    for (int s = 0; s < 6; ++s) {
      EXPECT_LT(std::abs(x(s) - x_kf(s)), 0.35 * std::sqrt(P_kf(s, s))) << "state " << s;
    }
    for (int s = 0; s < 3; ++s) EXPECT_NEAR(P(s, s) / P_kf(s, s), 1.0, 0.35) << "state " << s;
  }
}

TEST(Upf, RunsP1DimensionsFifteenAndNineStates) {
  run_p1_sized<15>(21);
  run_p1_sized<9>(22);
}

}  // namespace
}  // namespace nav::estimator

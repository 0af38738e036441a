// SPDX-License-Identifier: MIT
// The scaled unscented transform and the additive-noise UKF (unscented.hpp): weights against
// U1/U3 (the mean weights sum to one), sigma points reproducing N(x, P), the transform of a
// linear function (exact mean, covariance, cross-covariance) and of x² (exact mean), the UKF
// against the linear KF (linear_kf.hpp) over many steps of a linear-Gaussian model, and every
// refusal: NaN/Inf input, a covariance that is not positive definite, a non-finite function,
// the gate. Every random engine has a fixed seed.
#include "nav/estimator/unscented.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "nav/estimator/linear_kf.hpp"
#include "nav/estimator/particle_filter.hpp"
#include "test_support.hpp"

namespace nav::estimator {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// P1's particle UKFs: 31 sigma points for 15 states, 19 for 9 (papers.md P1).
static_assert(UnscentedWeights<15>::kPoints == 31);
static_assert(UnscentedWeights<9>::kPoints == 19);

/// A random symmetric positive definite K×K matrix A Aᵀ + 0.1 I.
template <int K>
Mat<K, K> random_spd(Rng& rng) {
  Mat<K, K> A;
  for (int r = 0; r < K; ++r) {
    for (int c = 0; c < K; ++c) A(r, c) = rng.normal();
  }
  return A * A.transpose() + 0.1 * Mat<K, K>::Identity();
}

template <int R, int C>
Mat<R, C> random_matrix(Rng& rng) {
  Mat<R, C> A;
  for (int r = 0; r < R; ++r) {
    for (int c = 0; c < C; ++c) A(r, c) = rng.normal();
  }
  return A;
}

/// Checks U1/U3/U4 for one dimension and parameter set.
template <int N>
void expect_weights(const UnscentedParams& p) {
  SCOPED_TRACE("N=" + std::to_string(N) + " alpha=" + std::to_string(p.alpha) +
               " beta=" + std::to_string(p.beta) + " kappa=" + std::to_string(p.kappa));
  const UnscentedWeights<N> w = unscented_weights<N>(p);
  const double lambda = p.alpha * p.alpha * (N + p.kappa) - N;
  const double n_lambda = N + lambda;
  // The mean weights sum to one (U4); W₀ may be ~−10⁶ for small α, so the bound is relative.
  const double scale = std::abs(w.mean(0)) + 1.0;
  EXPECT_NEAR(w.mean.sum(), 1.0, 1e-14 * scale);
  EXPECT_NEAR(w.mean(0), lambda / n_lambda, 1e-12 * scale);
  EXPECT_NEAR(w.cov(0), w.mean(0) + 1.0 - p.alpha * p.alpha + p.beta, 1e-12 * scale);
  for (int j = 1; j < UnscentedWeights<N>::kPoints; ++j) {
    EXPECT_DOUBLE_EQ(w.mean(j), 1.0 / (2.0 * n_lambda));
    EXPECT_DOUBLE_EQ(w.cov(j), w.mean(j));
  }
  EXPECT_DOUBLE_EQ(w.gamma, std::sqrt(n_lambda));
}

TEST(UnscentedWeights, MeanWeightsSumToOneForEveryParameterSet) {
  const UnscentedParams sets[] = {
      {},                 // defaults
      {1e-3, 2.0, 0.0},   // the often-quoted small α
      {0.5, 0.0, 1.0},
      {1.0, 0.0, 2.0},
      {0.3, 2.0, -0.5},
  };
  for (const UnscentedParams& p : sets) {
    expect_weights<1>(p);
    expect_weights<2>(p);
    expect_weights<9>(p);
    expect_weights<15>(p);
  }
}

TEST(UnscentedWeights, DefaultsAreNonNegativeWithPointsAtSqrtN) {
  const UnscentedParams p;
  EXPECT_EQ(p.alpha, 1.0);
  EXPECT_EQ(p.beta, 2.0);
  EXPECT_EQ(p.kappa, 0.0);
  const UnscentedWeights<15> w = unscented_weights<15>(p);
  EXPECT_EQ(w.mean(0), 0.0);  // λ = 0
  EXPECT_EQ(w.cov(0), 2.0);   // 0 + 1 − 1 + 2
  EXPECT_DOUBLE_EQ(w.mean(1), 1.0 / 30.0);
  EXPECT_DOUBLE_EQ(w.gamma, std::sqrt(15.0));
  EXPECT_GE(w.mean.minCoeff(), 0.0);
  EXPECT_GE(w.cov.minCoeff(), 0.0);
}

TEST(UnscentedWeights, ValidateNamesTheBadParameter) {
  EXPECT_TRUE(validate(UnscentedParams{}, 15).has_value());
  const auto error_of = [](const UnscentedParams& p, int n) {
    const Result<void> r = validate(p, n);
    return r.has_value() ? std::string() : r.error().detail;
  };
  EXPECT_NE(error_of({0.0, 2.0, 0.0}, 3).find("alpha"), std::string::npos);
  EXPECT_NE(error_of({1.5, 2.0, 0.0}, 3).find("alpha"), std::string::npos);
  EXPECT_NE(error_of({kNaN, 2.0, 0.0}, 3).find("finite"), std::string::npos);
  EXPECT_NE(error_of({1.0, -0.1, 0.0}, 3).find("beta"), std::string::npos);
  EXPECT_NE(error_of({1.0, 2.0, -3.0}, 3).find("kappa"), std::string::npos);
  EXPECT_NE(error_of({1.0, 2.0, 0.0}, 0).find("dimension"), std::string::npos);
  // A bad parameter set is a contract violation where weights are built.
  EXPECT_THROW(unscented_weights<3>(UnscentedParams{1.0, 2.0, -3.0}), std::logic_error);
}

TEST(SigmaPoints, ReproduceMeanAndCovariance) {
  Rng rng(11);
  const Vec<5> x = random_matrix<5, 1>(rng);
  const Mat<5, 5> P = random_spd<5>(rng);
  for (const UnscentedParams& p : {UnscentedParams{}, UnscentedParams{0.5, 2.0, 1.0}}) {
    const UnscentedWeights<5> w = unscented_weights<5>(p);
    SigmaPoints<5> X = SigmaPoints<5>::Zero();
    Mat<5, 5> L = Mat<5, 5>::Zero();
    ASSERT_EQ(sigma_points<5>(x, P, w.gamma, X, &L), UnscentedStatus::kOk);
    EXPECT_LT((L * L.transpose() - P).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((X * w.mean - x).cwiseAbs().maxCoeff(), 1e-12);
    const Mat<5, 11> dX = X.colwise() - x;
    const Mat<5, 5> P_back = dX * w.cov.asDiagonal() * dX.transpose();
    EXPECT_LT((P_back - P).cwiseAbs().maxCoeff(), 1e-12 * P.cwiseAbs().maxCoeff());
  }
}

TEST(UnscentedTransform, LinearFunctionGivesExactMeanAndCovariance) {
  Rng rng(12);
  const Vec<4> x = random_matrix<4, 1>(rng);
  const Mat<4, 4> P = random_spd<4>(rng);
  const Mat<3, 4> A = random_matrix<3, 4>(rng);
  const Vec<3> b = random_matrix<3, 1>(rng);
  const auto g = [&](const Vec<4>& v) -> Vec<3> { return A * v + b; };
  for (const UnscentedParams& p :
       {UnscentedParams{}, UnscentedParams{1e-3, 2.0, 0.0}, UnscentedParams{0.7, 0.0, 3.0}}) {
    const UnscentedWeights<4> w = unscented_weights<4>(p);
    Vec<3> y = Vec<3>::Zero();
    Mat<3, 3> P_yy = Mat<3, 3>::Zero();
    Mat<4, 3> P_xy = Mat<4, 3>::Zero();
    ASSERT_EQ((unscented_transform<4, 3>(x, P, w, g, y, P_yy, &P_xy)), UnscentedStatus::kOk);
    // Small α cancels ~6 digits in W₀ (unscented.hpp): the bounds cover it.
    const double tol = p.alpha < 0.01 ? 1e-8 : 1e-12;
    const Vec<3> y_exact = A * x + b;
    const Mat<3, 3> P_yy_exact = A * P * A.transpose();
    const Mat<4, 3> P_xy_exact = P * A.transpose();
    EXPECT_LT((y - y_exact).cwiseAbs().maxCoeff(), tol * (1.0 + y_exact.cwiseAbs().maxCoeff()));
    EXPECT_LT((P_yy - P_yy_exact).cwiseAbs().maxCoeff(), tol * P_yy_exact.cwiseAbs().maxCoeff());
    EXPECT_LT((P_xy - P_xy_exact).cwiseAbs().maxCoeff(), tol * P_xy_exact.cwiseAbs().maxCoeff());
  }
}

TEST(UnscentedTransform, SquareHasExactMeanAndJulierVariance) {
  // y = x², x ~ N(m, σ²): E y = m² + σ², var y = 4 m² σ² + 2 σ⁴. The UT's mean is exact for any
  // parameters; with N + κ = 3 (α = 1, β = 0) it also matches the fourth moment, so the
  // variance is exact too [J02].
  const double m = 1.5;
  const double sigma = 0.7;
  const Vec<1> x(m);
  const Mat<1, 1> P(sigma * sigma);
  const auto g = [](const Vec<1>& v) -> Vec<1> { return Vec<1>(v(0) * v(0)); };
  for (const UnscentedParams& p : {UnscentedParams{}, UnscentedParams{1.0, 0.0, 2.0}}) {
    const UnscentedWeights<1> w = unscented_weights<1>(p);
    Vec<1> y = Vec<1>::Zero();
    Mat<1, 1> P_yy = Mat<1, 1>::Zero();
    ASSERT_EQ((unscented_transform<1, 1>(x, P, w, g, y, P_yy)), UnscentedStatus::kOk);
    EXPECT_NEAR(y(0), m * m + sigma * sigma, 1e-14);
  }
  const UnscentedWeights<1> w3 = unscented_weights<1>(UnscentedParams{1.0, 0.0, 2.0});
  Vec<1> y = Vec<1>::Zero();
  Mat<1, 1> P_yy = Mat<1, 1>::Zero();
  ASSERT_EQ((unscented_transform<1, 1>(x, P, w3, g, y, P_yy)), UnscentedStatus::kOk);
  const double s2 = sigma * sigma;
  EXPECT_NEAR(P_yy(0, 0), 4.0 * m * m * s2 + 2.0 * s2 * s2, 1e-13);
}

TEST(SigmaPoints, CovarianceNotPositiveDefiniteIsReportedNotACrash) {
  const UnscentedWeights<2> w = unscented_weights<2>(UnscentedParams{});
  const Vec<2> x(1.0, 2.0);
  const Mat<2, 2> indefinite = (Mat<2, 2>() << 1.0, 2.0, 2.0, 1.0).finished();
  SigmaPoints<2> X = SigmaPoints<2>::Constant(7.0);
  EXPECT_EQ(sigma_points<2>(x, indefinite, w.gamma, X), UnscentedStatus::kCholeskyFailed);
  EXPECT_TRUE((X.array() == 7.0).all());  // untouched
  EXPECT_EQ(sigma_points<2>(x, Mat<2, 2>::Zero(), w.gamma, X), UnscentedStatus::kCholeskyFailed);
  const Mat<2, 2> nan_P = (Mat<2, 2>() << 1.0, kNaN, kNaN, 1.0).finished();
  EXPECT_EQ(sigma_points<2>(x, nan_P, w.gamma, X), UnscentedStatus::kRejectedInvalid);
  EXPECT_EQ(sigma_points<2>(Vec<2>(kInf, 0.0), Mat<2, 2>::Identity(), w.gamma, X),
            UnscentedStatus::kRejectedInvalid);
  EXPECT_TRUE((X.array() == 7.0).all());

  // The same through the predict and the update: x, P untouched.
  Vec<2> x_kf = x;
  Mat<2, 2> P_kf = indefinite;
  const auto f = [](const Vec<2>& v) -> Vec<2> { return v; };
  EXPECT_EQ(ukf_predict<2>(x_kf, P_kf, w, f, Mat<2, 2>::Identity()),
            UnscentedStatus::kCholeskyFailed);
  const auto h = [](const Vec<2>& v) -> Vec<1> { return Vec<1>(v(0)); };
  const UpdateReport<1> r = ukf_update<2, 1>(x_kf, P_kf, w, h, Vec<1>(0.5), Mat<1, 1>(1.0));
  EXPECT_EQ(r.status, UpdateStatus::kNumericalFault);
  EXPECT_EQ(x_kf, x);
  EXPECT_EQ(P_kf, indefinite);
}

TEST(UkfUpdate, UpdatedCovarianceNotPositiveDefiniteIsANumericalFault) {
  // P = 1, h(x) = x, R = 1e-300: S = 1 exactly, K = 1, P − K S Kᵀ = 0: the LLT check fails.
  const UnscentedWeights<1> w = unscented_weights<1>(UnscentedParams{});
  Vec<1> x(0.0);
  Mat<1, 1> P(1.0);
  const auto h = [](const Vec<1>& v) -> Vec<1> { return v; };
  UkfFactors<1> factors;
  factors.L_post(0, 0) = 42.0;
  const UpdateReport<1> r =
      ukf_update<1, 1>(x, P, w, h, Vec<1>(0.3), Mat<1, 1>(1e-300), 0.0, &factors);
  EXPECT_EQ(r.status, UpdateStatus::kNumericalFault);
  EXPECT_EQ(x(0), 0.0);
  EXPECT_EQ(P(0, 0), 1.0);
  EXPECT_EQ(factors.L_post(0, 0), 42.0);
}

TEST(UkfUpdate, InvalidMeasurementIsRefusedWithStateUntouched) {
  const UnscentedWeights<2> w = unscented_weights<2>(UnscentedParams{});
  Vec<2> x(1.0, -1.0);
  Mat<2, 2> P = Mat<2, 2>::Identity();
  const auto h = [](const Vec<2>& v) -> Vec<1> { return Vec<1>(v(0) + v(1)); };
  EXPECT_EQ((ukf_update<2, 1>(x, P, w, h, Vec<1>(kNaN), Mat<1, 1>(1.0)).status),
            UpdateStatus::kRejectedInvalid);
  EXPECT_EQ((ukf_update<2, 1>(x, P, w, h, Vec<1>(kInf), Mat<1, 1>(1.0)).status),
            UpdateStatus::kRejectedInvalid);
  EXPECT_EQ((ukf_update<2, 1>(x, P, w, h, Vec<1>(0.0), Mat<1, 1>(kNaN)).status),
            UpdateStatus::kRejectedInvalid);
  // A measurement function that returns NaN.
  const auto h_nan = [](const Vec<2>&) -> Vec<1> { return Vec<1>(kNaN); };
  EXPECT_EQ((ukf_update<2, 1>(x, P, w, h_nan, Vec<1>(0.0), Mat<1, 1>(1.0)).status),
            UpdateStatus::kNumericalFault);
  EXPECT_EQ(x, Vec<2>(1.0, -1.0));
  EXPECT_EQ(P, (Mat<2, 2>::Identity()));
}

TEST(UkfPredict, NonFiniteProcessOrNoiseLeavesStateUntouched) {
  const UnscentedWeights<2> w = unscented_weights<2>(UnscentedParams{});
  Vec<2> x(1.0, -1.0);
  Mat<2, 2> P = Mat<2, 2>::Identity();
  const auto f_nan = [](const Vec<2>& v) -> Vec<2> { return v * kNaN; };
  EXPECT_EQ(ukf_predict<2>(x, P, w, f_nan, Mat<2, 2>::Identity()), UnscentedStatus::kNonFinite);
  const auto f = [](const Vec<2>& v) -> Vec<2> { return v; };
  EXPECT_EQ(ukf_predict<2>(x, P, w, f, Mat<2, 2>::Constant(kNaN)),
            UnscentedStatus::kRejectedInvalid);
  EXPECT_EQ(x, Vec<2>(1.0, -1.0));
  EXPECT_EQ(P, (Mat<2, 2>::Identity()));
}

TEST(UkfUpdate, GateRefusesAndReportsTheLinearKfNis) {
  const UnscentedWeights<2> w = unscented_weights<2>(UnscentedParams{});
  const Mat<1, 2> H(1.0, 0.5);
  const auto h = [&](const Vec<2>& v) -> Vec<1> { return H * v; };
  Vec<2> x(0.0, 0.0);
  Mat<2, 2> P = Mat<2, 2>::Identity();
  Vec<2> x_kf = x;
  Mat<2, 2> P_kf = P;
  const Vec<1> z(10.0);
  const Mat<1, 1> R(0.5);
  const UpdateReport<1> r = ukf_update<2, 1>(x, P, w, h, z, R, 9.0);
  const UpdateReport<1> r_kf = linear_update<2, 1>(x_kf, P_kf, z, H, R, 9.0);
  EXPECT_EQ(r.status, UpdateStatus::kRejectedGate);
  EXPECT_EQ(r_kf.status, UpdateStatus::kRejectedGate);
  EXPECT_NEAR(r.nis, r_kf.nis, 1e-12 * r_kf.nis);
  EXPECT_NEAR(r.S(0, 0), r_kf.S(0, 0), 1e-12);
  EXPECT_EQ(x, Vec<2>::Zero().eval());
  EXPECT_EQ(P, (Mat<2, 2>::Identity()));
}

/// A 2-D constant-velocity model [p_N, p_E, v_N, v_E] with acceleration noise, measured by
/// position and by a combination of position and velocity.
struct LinearCase {
  static constexpr double kDt = 0.1;  // [s]
  Mat<4, 4> F = Mat<4, 4>::Identity();
  Mat<4, 4> Q = Mat<4, 4>::Zero();
  Mat<2, 4> H = Mat<2, 4>::Zero();
  Mat<2, 2> R = Mat<2, 2>::Zero();
  LinearCase() {
    F(0, 2) = kDt;
    F(1, 3) = kDt;
    const double q = 0.3;  // acceleration noise density² [m²/s³]
    for (int k = 0; k < 2; ++k) {
      Q(k, k) = q * kDt * kDt * kDt / 3.0;  // Van Loan discretisation
      Q(k, k + 2) = Q(k + 2, k) = q * kDt * kDt / 2.0;
      Q(k + 2, k + 2) = q * kDt;
    }
    H << 1.0, 0.0, 0.0, 0.0, 0.2, 1.0, 0.5, 0.0;
    R << 0.8, 0.1, 0.1, 0.5;
  }
};

TEST(Ukf, AgreesWithLinearKalmanFilterOverManySteps) {
  const LinearCase lc;
  Rng rng(2024);
  Vec<4> truth(0.0, 0.0, 1.0, -0.5);
  Vec<4> x_kf(2.0, -1.0, 0.0, 0.0);
  Mat<4, 4> P_kf = Vec<4>(9.0, 9.0, 1.0, 1.0).asDiagonal();
  Vec<4> x_ukf = x_kf;
  Mat<4, 4> P_ukf = P_kf;
  const Eigen::LLT<Mat<4, 4>> Q_llt(lc.Q);
  const Eigen::LLT<Mat<2, 2>> R_llt(lc.R);
  const Mat<4, 4> L_Q = Q_llt.matrixL();
  const Mat<2, 2> L_R = R_llt.matrixL();
  const auto f = [&](const Vec<4>& v) -> Vec<4> { return lc.F * v; };
  const auto h = [&](const Vec<4>& v) -> Vec<2> { return lc.H * v; };
  for (const UnscentedParams& p : {UnscentedParams{}, UnscentedParams{0.5, 2.0, 1.0}}) {
    const UnscentedWeights<4> w = unscented_weights<4>(p);
    for (int step = 0; step < 300; ++step) {
      SCOPED_TRACE("step " + std::to_string(step));
      truth = lc.F * truth + L_Q * Vec<4>(rng.normal(), rng.normal(), rng.normal(), rng.normal());
      x_kf = lc.F * x_kf;
      predict_covariance<4>(P_kf, lc.F, lc.Q);
      ASSERT_EQ(ukf_predict<4>(x_ukf, P_ukf, w, f, lc.Q), UnscentedStatus::kOk);
      if (step % 3 == 2) {  // a measurement every third step
        const Vec<2> z = lc.H * truth + L_R * Vec<2>(rng.normal(), rng.normal());
        const UpdateReport<2> r_kf = linear_update<4, 2>(x_kf, P_kf, z, lc.H, lc.R);
        const UpdateReport<2> r_ukf = ukf_update<4, 2>(x_ukf, P_ukf, w, h, z, lc.R);
        ASSERT_EQ(r_kf.status, UpdateStatus::kFused);
        ASSERT_EQ(r_ukf.status, UpdateStatus::kFused);
        EXPECT_NEAR(r_ukf.nis, r_kf.nis, 1e-9 * (1.0 + r_kf.nis));
        EXPECT_LT((r_ukf.S - r_kf.S).cwiseAbs().maxCoeff(), 1e-9);
      }
      EXPECT_LT((x_ukf - x_kf).cwiseAbs().maxCoeff(), 1e-9);
      EXPECT_LT((P_ukf - P_kf).cwiseAbs().maxCoeff(), 1e-9);
    }
  }
}

}  // namespace
}  // namespace nav::estimator

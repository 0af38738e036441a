// SPDX-License-Identifier: MIT
// Particle-filter building blocks (particle_filter.hpp): the generator (the standard's fixed
// mt19937_64 output, reproducible uniform and normal draws, normal moments with stated
// bounds), ESS on hand-made weights, log-space normalisation of log-weights near −1000,
// systematic resampling (exact ancestors on hand-made weights, ⌊N w⌋/⌈N w⌉ counts, same seed →
// same indices, refusals) and the Gaussian log-density. Every seed is fixed.
#include "nav/estimator/particle_filter.hpp"

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "test_support.hpp"

namespace nav::estimator {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(Rng, EngineIsTheStandardMt19937_64) {
  // [rand.predef]: the 10000th invocation of a default-constructed mt19937_64 (seed 5489)
  // produces 9981545732273789042.
  Rng rng(5489);
  std::uint64_t v = 0;
  for (int i = 0; i < 10000; ++i) v = rng.next_u64();
  EXPECT_EQ(v, 9981545732273789042ULL);
}

TEST(Rng, UniformIsTheTop53BitsOfTheRawOutput) {
  Rng rng(42);
  std::mt19937_64 reference(42);
  for (int i = 0; i < 1000; ++i) {
    const double u = rng.uniform();
    EXPECT_EQ(u, static_cast<double>(reference() >> 11) / 9007199254740992.0);  // 2^53
    EXPECT_GE(u, 0.0);
    EXPECT_LT(u, 1.0);
  }
}

TEST(Rng, SameSeedSameDrawsDifferentSeedDifferentDraws) {
  Rng a(7);
  Rng b(7);
  Rng c(8);
  int differ = 0;
  for (int i = 0; i < 1000; ++i) {
    const double na = a.normal();
    const double nb = b.normal();
    EXPECT_EQ(na, nb);  // bit-identical
    if (na != c.normal()) ++differ;
    EXPECT_EQ(a.uniform(), b.uniform());
    c.uniform();
  }
  EXPECT_GT(differ, 990);
}

TEST(Rng, NormalDrawsHaveStandardMoments) {
  // n = 200000 draws; bounds at 5 standard errors: mean ±5/√n, variance ±5·√(2/n), the
  // fraction within ±1 at ±5·√(p(1−p)/n), p = 0.6827, fourth moment ±5·√(96/n).
  constexpr int n = 200000;
  Rng rng(99);
  double sum = 0.0;
  double sum2 = 0.0;
  double sum4 = 0.0;
  int within_one = 0;
  for (int i = 0; i < n; ++i) {
    const double x = rng.normal();
    ASSERT_TRUE(std::isfinite(x));
    sum += x;
    sum2 += x * x;
    sum4 += x * x * x * x;
    if (std::abs(x) < 1.0) ++within_one;
  }
  const double dn = n;
  EXPECT_NEAR(sum / dn, 0.0, 5.0 / std::sqrt(dn));
  EXPECT_NEAR(sum2 / dn, 1.0, 5.0 * std::sqrt(2.0 / dn));
  EXPECT_NEAR(sum4 / dn, 3.0, 5.0 * std::sqrt(96.0 / dn));
  const double p = 0.682689492137;
  EXPECT_NEAR(within_one / dn, p, 5.0 * std::sqrt(p * (1.0 - p) / dn));
}

TEST(EffectiveSampleSize, HandMadeCases) {
  const std::vector<double> uniform(250, 1.0 / 250.0);
  EXPECT_NEAR(effective_sample_size(uniform), 250.0, 1e-9);
  const std::array<double, 5> one_hot = {0.0, 0.0, 1.0, 0.0, 0.0};
  EXPECT_EQ(effective_sample_size(one_hot), 1.0);
  const std::array<double, 3> halves = {0.5, 0.25, 0.25};
  EXPECT_DOUBLE_EQ(effective_sample_size(halves), 1.0 / 0.375);  // 8/3
  const std::array<double, 4> two_equal = {0.5, 0.0, 0.5, 0.0};
  EXPECT_DOUBLE_EQ(effective_sample_size(two_equal), 2.0);
  EXPECT_EQ(effective_sample_size(std::span<const double>()), 0.0);
}

TEST(NormalizeLogWeights, LogWeightsNearMinus1000DoNotUnderflow) {
  // exp(−1000) is 0 in double: normalising the linear weights would divide 0 by 0.
  ASSERT_EQ(std::exp(-1000.0), 0.0);
  // Doubles near 1000 are 1.1e-13 apart: the inputs themselves are that coarse, so the weights
  // are checked to 1e-12.
  std::array<double, 4> log_w = {-1000.0, -1000.0 - std::numbers::ln2, -1001.5, -kInf};
  std::array<double, 4> w{};
  ASSERT_EQ(normalize_log_weights(log_w, w), WeightStatus::kOk);
  const double total = 1.0 + 0.5 + std::exp(-1.5);
  EXPECT_NEAR(w[0], 1.0 / total, 1e-12);
  EXPECT_NEAR(w[1], 0.5 / total, 1e-12);
  EXPECT_NEAR(w[2], std::exp(-1.5) / total, 1e-12);
  EXPECT_EQ(w[3], 0.0);  // a dead particle
  EXPECT_NEAR(w[0] + w[1] + w[2] + w[3], 1.0, 1e-15);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(std::exp(log_w[i]), w[i]);  // normalised in place
  EXPECT_NEAR(log_w[0], -std::log(total), 1e-12);

  // Invariant to a common offset: the same weights from log-weights near +700 and −1e5 (to
  // the spacing of doubles there, 1.1e-13 and 1.5e-11, times a few).
  for (const double offset : {1700.0, -99000.0}) {
    std::array<double, 4> shifted = {-1000.0 + offset, -1000.0 - std::numbers::ln2 + offset,
                                     -1001.5 + offset, -kInf};
    std::array<double, 4> w2{};
    ASSERT_EQ(normalize_log_weights(shifted, w2), WeightStatus::kOk);
    const double tol = 1e-12 * (1.0 + std::abs(offset) / 1e3);
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(w2[i], w[i], tol);
  }
}

TEST(NormalizeLogWeights, InvalidInputIsRefusedUntouched) {
  std::array<double, 3> w = {7.0, 7.0, 7.0};
  std::array<double, 3> nan_l = {0.0, kNaN, 1.0};
  EXPECT_EQ(normalize_log_weights(nan_l, w), WeightStatus::kInvalid);
  std::array<double, 3> inf_l = {0.0, kInf, 1.0};
  EXPECT_EQ(normalize_log_weights(inf_l, w), WeightStatus::kInvalid);
  std::array<double, 3> dead = {-kInf, -kInf, -kInf};
  EXPECT_EQ(normalize_log_weights(dead, w), WeightStatus::kInvalid);
  std::array<double, 2> short_l = {0.0, 0.0};
  EXPECT_EQ(normalize_log_weights(short_l, w), WeightStatus::kInvalid);
  for (const double wi : w) EXPECT_EQ(wi, 7.0);
  EXPECT_EQ(nan_l[0], 0.0);
  EXPECT_EQ(dead[0], -kInf);
}

TEST(SystematicResample, HandMadeWeightsGiveTheExpectedAncestors) {
  const std::array<double, 4> w = {0.1, 0.2, 0.3, 0.4};
  std::array<std::size_t, 4> a{};
  // u = 0.5: pointers 0.125, 0.375, 0.625, 0.875; cumulative sums 0.1, 0.3, 0.6, 1.0.
  ASSERT_EQ(systematic_resample(w, 0.5, a), WeightStatus::kOk);
  EXPECT_EQ(a, (std::array<std::size_t, 4>{1, 2, 3, 3}));
  // u = 0: pointers 0, 0.25, 0.5, 0.75.
  ASSERT_EQ(systematic_resample(w, 0.0, a), WeightStatus::kOk);
  EXPECT_EQ(a, (std::array<std::size_t, 4>{0, 1, 2, 3}));
  // Unnormalised weights are scaled by their sum: the same ancestors.
  const std::array<double, 4> w10 = {1.0, 2.0, 3.0, 4.0};
  ASSERT_EQ(systematic_resample(w10, 0.5, a), WeightStatus::kOk);
  EXPECT_EQ(a, (std::array<std::size_t, 4>{1, 2, 3, 3}));
  // Zero weights, including the first and the last, are never chosen.
  const std::array<double, 4> w0 = {0.0, 0.5, 0.5, 0.0};
  ASSERT_EQ(systematic_resample(w0, 0.0, a), WeightStatus::kOk);
  EXPECT_EQ(a, (std::array<std::size_t, 4>{1, 1, 2, 2}));
  ASSERT_EQ(systematic_resample(w0, 0.3, a), WeightStatus::kOk);
  EXPECT_EQ(a, (std::array<std::size_t, 4>{1, 1, 2, 2}));
  // u just below 1: 1 + u rounds to 2, the pointer lands on the boundary 0.5 (round-off, see
  // W5), but the last pointer, rounded up to the total, still stops at the last live particle.
  ASSERT_EQ(systematic_resample(w0, 1.0 - 0x1.0p-53, a), WeightStatus::kOk);
  EXPECT_EQ(a[0], 1U);
  EXPECT_EQ(a[3], 2U);
  for (const std::size_t i : a) EXPECT_TRUE(i == 1 || i == 2);
}

TEST(SystematicResample, CountsAreFloorOrCeilOfNTimesWeight) {
  constexpr std::size_t n = 10;
  Rng rng(5);
  std::array<double, n> w{};
  std::array<std::size_t, n> a{};
  for (int trial = 0; trial < 200; ++trial) {
    double total = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double u = rng.uniform();
      w[i] = (i == 3) ? 0.0 : u * u;  // uneven weights; particle 3 dead
      total += w[i];
    }
    for (double& wi : w) wi /= total;
    for (int k = 0; k < 20; ++k) {
      ASSERT_EQ(systematic_resample(w, rng, a), WeightStatus::kOk);
      std::array<int, n> count{};
      for (std::size_t j = 0; j < n; ++j) {
        ASSERT_LT(a[j], n);
        if (j > 0) {
          EXPECT_LE(a[j - 1], a[j]);  // non-decreasing
        }
        ++count[a[j]];
      }
      for (std::size_t i = 0; i < n; ++i) {
        const double expected = static_cast<double>(n) * w[i];
        EXPECT_GE(count[i], static_cast<int>(std::floor(expected))) << "particle " << i;
        EXPECT_LE(count[i], static_cast<int>(std::ceil(expected))) << "particle " << i;
      }
      EXPECT_EQ(count[3], 0);
    }
  }
}

TEST(SystematicResample, SameSeedSameIndicesDifferentSeedDifferent) {
  constexpr std::size_t n = 50;
  std::array<double, n> w{};
  Rng weights_rng(1);
  for (double& wi : w) wi = weights_rng.uniform();
  const auto run = [&](std::uint64_t seed) {
    Rng rng(seed);
    std::vector<std::size_t> all;
    std::array<std::size_t, n> a{};
    for (int k = 0; k < 10; ++k) {
      EXPECT_EQ(systematic_resample(w, rng, a), WeightStatus::kOk);
      all.insert(all.end(), a.begin(), a.end());
    }
    return all;
  };
  EXPECT_EQ(run(123), run(123));
  EXPECT_NE(run(123), run(124));
}

TEST(SystematicResample, InvalidInputIsRefusedUntouched) {
  std::array<std::size_t, 3> a = {9, 9, 9};
  const std::array<double, 3> negative = {0.5, -0.1, 0.6};
  const std::array<double, 3> nan_w = {0.5, kNaN, 0.5};
  const std::array<double, 3> inf_w = {0.5, kInf, 0.5};
  const std::array<double, 3> zeros = {0.0, 0.0, 0.0};
  const std::array<double, 3> fine = {0.2, 0.3, 0.5};
  const std::array<double, 2> short_w = {0.5, 0.5};
  EXPECT_EQ(systematic_resample(negative, 0.5, a), WeightStatus::kInvalid);
  EXPECT_EQ(systematic_resample(nan_w, 0.5, a), WeightStatus::kInvalid);
  EXPECT_EQ(systematic_resample(inf_w, 0.5, a), WeightStatus::kInvalid);
  EXPECT_EQ(systematic_resample(zeros, 0.5, a), WeightStatus::kInvalid);
  EXPECT_EQ(systematic_resample(fine, 1.0, a), WeightStatus::kInvalid);
  EXPECT_EQ(systematic_resample(fine, -0.1, a), WeightStatus::kInvalid);
  EXPECT_EQ(systematic_resample(fine, kNaN, a), WeightStatus::kInvalid);
  EXPECT_EQ(systematic_resample(short_w, 0.5, a), WeightStatus::kInvalid);
  EXPECT_EQ(a, (std::array<std::size_t, 3>{9, 9, 9}));
}

TEST(GaussianLogDensity, MatchesClosedForms) {
  const double two_pi = 2.0 * std::numbers::pi;
  // 1-D: r = 0.3, σ = 2.
  const double l1 = gaussian_log_density<1>(Vec<1>(0.3), Mat<1, 1>(2.0));
  EXPECT_NEAR(l1, -0.5 * 0.15 * 0.15 - std::log(2.0) - 0.5 * std::log(two_pi), 1e-15);
  // 2-D, Σ = [[4, 1.2], [1.2, 1]]: ln N = −½ rᵀ Σ⁻¹ r − ½ ln |Σ| − ln 2π, Σ⁻¹ by hand.
  const Mat<2, 2> Sigma = (Mat<2, 2>() << 4.0, 1.2, 1.2, 1.0).finished();
  const Eigen::LLT<Mat<2, 2>> llt(Sigma);
  const Mat<2, 2> L = llt.matrixL();
  const Vec<2> r(0.7, -0.4);
  const double det = 4.0 * 1.0 - 1.2 * 1.2;
  const double quad = (1.0 * r(0) * r(0) - 2.0 * 1.2 * r(0) * r(1) + 4.0 * r(1) * r(1)) / det;
  EXPECT_NEAR(gaussian_log_density<2>(r, L), -0.5 * quad - 0.5 * std::log(det) - std::log(two_pi),
              1e-14);
}

}  // namespace
}  // namespace nav::estimator

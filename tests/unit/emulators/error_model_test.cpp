// SPDX-License-Identifier: MIT
// Error models and device seeds. Statistical checks use fixed seeds (deterministic) and state
// their bounds in standard errors of the estimator: for N samples the sample mean has standard
// error sigma/sqrt(N) and the sample standard deviation sigma/sqrt(2N).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "nav/emulators/device.hpp"

namespace nav::emulators {
namespace {

struct Moments {
  Vec3 mean = Vec3::Zero();
  Vec3 std = Vec3::Zero();
};

Moments moments(const std::vector<Vec3>& xs) {
  Moments m;
  for (const Vec3& x : xs) m.mean += x;
  m.mean /= static_cast<double>(xs.size());
  Vec3 var = Vec3::Zero();
  for (const Vec3& x : xs) var += (x - m.mean).cwiseAbs2();
  var /= static_cast<double>(xs.size() - 1);
  m.std = var.cwiseSqrt();
  return m;
}

TEST(DeviceSeed, MatchesSplitmix64OfSeedXorFnv1a64) {
  // Expected values from an independent Python implementation of FNV-1a 64 and splitmix64
  // (check values: fnv1a64("a") = 0xaf63dc4c8601ec8c, splitmix64(0) = 0xe220a8397b1dcdaf).
  EXPECT_EQ(device_seed(0, ""), 0xc3817c016ba4ff30ULL);
  EXPECT_EQ(device_seed(0xcbf29ce484222325ULL, ""), 0xe220a8397b1dcdafULL);
  EXPECT_EQ(device_seed(42, "ahrs"), 0x9aaf32ce129b5828ULL);
  EXPECT_EQ(device_seed(42, "gps"), 0x18327136f3b95e9fULL);
  EXPECT_EQ(device_seed(1, "ahrs"), 0xb013d76b58f688c9ULL);
}

TEST(StandardNormal, HasZeroMeanUnitVarianceAndConsumesTwoOutputs) {
  std::mt19937_64 rng(7);
  constexpr int kN = 200'000;
  double sum = 0.0, sum2 = 0.0, sum4 = 0.0;
  int beyond_3sigma = 0;
  for (int i = 0; i < kN; ++i) {
    const double z = standard_normal(rng);
    sum += z;
    sum2 += z * z;
    sum4 += z * z * z * z;
    beyond_3sigma += std::abs(z) > 3.0 ? 1 : 0;
  }
  const double n = kN;
  EXPECT_NEAR(sum / n, 0.0, 5.0 / std::sqrt(n));             // 5 standard errors
  EXPECT_NEAR(std::sqrt(sum2 / n), 1.0, 5.0 / std::sqrt(2 * n));
  EXPECT_NEAR(sum4 / n, 3.0, 5.0 * std::sqrt(96.0 / n));     // Var(z^4) = 105 - 9 = 96
  // P(|z| > 3) = 0.0027: binomial standard error sqrt(p/n).
  EXPECT_NEAR(beyond_3sigma / n, 0.0027, 5.0 * std::sqrt(0.0027 / n));

  std::mt19937_64 a(99), b(99);
  (void)standard_normal(a);
  b.discard(2);
  EXPECT_EQ(a(), b());
}

TEST(TriadErrorModel, ConstantBiasOnlyIsExact) {
  TriadErrorModel m(TriadErrors{0.0, 0.25, 0.0});
  std::mt19937_64 rng(1);
  const Vec3 truth{1.0, -2.0, 3.0};
  for (int i = 0; i < 10; ++i) {
    EXPECT_EQ(m.apply(truth, 0.01, rng), truth + Vec3::Constant(0.25));
  }
}

TEST(TriadErrorModel, DrawsSixNormalsPerCallWhateverTheParameters) {
  // Enabling one error term must not shift the random stream of the others.
  std::mt19937_64 a(5), b(5);
  TriadErrorModel zero(TriadErrors{});
  EXPECT_EQ(zero.apply(Vec3::Ones(), 0.1, a), Vec3::Ones());
  b.discard(12);
  EXPECT_EQ(a(), b());
}

TEST(TriadErrorModel, WhiteNoiseHasTheStatedStandardDeviation) {
  constexpr double kStd = 0.5, kBias = -0.1;
  constexpr int kN = 100'000;
  TriadErrorModel m(TriadErrors{kStd, kBias, 0.0});
  std::mt19937_64 rng(2024);
  std::vector<Vec3> errors;
  for (int i = 0; i < kN; ++i) errors.push_back(m.apply(Vec3::Zero(), 0.01, rng));
  const Moments mo = moments(errors);
  for (int i = 0; i < 3; ++i) {
    // mean: 5 standard errors (0.008); std: within 5 % (about 22 standard errors at N = 1e5).
    EXPECT_NEAR(mo.mean[i], kBias, 5.0 * kStd / std::sqrt(kN));
    EXPECT_NEAR(mo.std[i], kStd, 0.05 * kStd);
    EXPECT_NEAR(mo.std[i], kStd, 5.0 * kStd / std::sqrt(2.0 * kN));  // the tight bound too
  }
  // Axes are independent: sample correlation within 5 standard errors (1/sqrt(N)).
  double cxy = 0.0;
  for (const Vec3& e : errors) cxy += (e.x() - mo.mean.x()) * (e.y() - mo.mean.y());
  cxy /= (kN - 1) * mo.std.x() * mo.std.y();
  EXPECT_NEAR(cxy, 0.0, 5.0 / std::sqrt(kN));
}

TEST(TriadErrorModel, BiasRandomWalkVarianceGrowsLinearly) {
  // M independent walks, sigma_w = 0.2 unit/sqrt(s), sampled at 10 Hz for 10 s.
  // Var(w(t)) = sigma_w^2 t. The sample variance over M walks has relative standard error
  // sqrt(2/M) = 2 % at M = 5000; the bound below is 5 of those (10 %).
  constexpr int kWalks = 5000;
  constexpr double kWalkStd = 0.2, kDt = 0.1;
  const std::vector<int> check_steps = {10, 25, 50, 100};
  std::vector<std::vector<double>> values(check_steps.size());
  std::mt19937_64 rng(31337);
  for (int w = 0; w < kWalks; ++w) {
    TriadErrorModel m(TriadErrors{0.0, 0.0, kWalkStd});
    (void)m.apply(Vec3::Zero(), 0.0, rng);  // first sample: no walk yet
    EXPECT_EQ(m.walk(), Vec3::Zero());
    std::size_t next = 0;
    for (int k = 1; k <= check_steps.back(); ++k) {
      const Vec3 y = m.apply(Vec3::Zero(), kDt, rng);
      if (k == check_steps[next]) values[next++].push_back(y.x());
    }
  }
  for (std::size_t i = 0; i < check_steps.size(); ++i) {
    double var = 0.0;
    for (const double v : values[i]) var += v * v;  // mean is 0 by construction
    var /= kWalks;
    const double t = check_steps[i] * kDt;
    const double expected = kWalkStd * kWalkStd * t;
    EXPECT_NEAR(var / expected, 1.0, 5.0 * std::sqrt(2.0 / kWalks)) << "t = " << t << " s";
  }
}

TEST(TriadErrorModel, BiasInstabilityIsAStationaryGaussMarkovProcess) {
  // sigma 2, tau 5 s, sampled at 10 Hz for 20000 s: variance sigma^2, autocorrelation at
  // lag tau e^-1 (within a few percent: 4000 correlation times).
  TriadErrors e;
  e.instability_std = 2.0;
  e.instability_tau_s = 5.0;
  TriadErrorModel m(e);
  std::mt19937_64 rng(9);
  std::vector<double> x;
  for (int k = 0; k < 200000; ++k) x.push_back(m.apply(Vec3::Zero(), k == 0 ? 0.0 : 0.1, rng).x());
  double var = 0.0, lag = 0.0;
  for (std::size_t k = 0; k < x.size(); ++k) var += x[k] * x[k];
  for (std::size_t k = 0; k + 50 < x.size(); ++k) lag += x[k] * x[k + 50];
  var /= static_cast<double>(x.size());
  lag /= static_cast<double>(x.size() - 50);
  EXPECT_NEAR(var, 4.0, 4.0 * 0.08);
  EXPECT_NEAR(lag / var, std::exp(-1.0), 0.04);
}

TEST(TriadErrorModel, BiasInstabilityIsStationaryFromTheFirstSample) {
  // Across seeds, the very first sample already has variance sigma^2 (no warm-up).
  TriadErrors e;
  e.instability_std = 1.0;
  double var = 0.0;
  for (std::uint64_t seed = 1; seed <= 4000; ++seed) {
    TriadErrorModel m(e);
    std::mt19937_64 rng(seed);
    const double v = m.apply(Vec3::Zero(), 0.0, rng).y();
    var += v * v / 4000.0;
  }
  EXPECT_NEAR(var, 1.0, 0.08);
}

TEST(TriadErrorModel, WithoutBiasInstabilityTheDrawsAreUnchanged) {
  // Six normals per sample: the engine ends where six standard_normal calls leave it; with
  // an instability, three more.
  TriadErrors e;
  e.white_std = 1.0;
  TriadErrorModel plain(e);
  std::mt19937_64 a(4), b(4);
  plain.apply(Vec3::Zero(), 0.0, a);
  for (int i = 0; i < 6; ++i) standard_normal(b);
  EXPECT_EQ(a(), b());
  e.instability_std = 1.0;
  TriadErrorModel unstable(e);
  std::mt19937_64 c(4), d(4);
  unstable.apply(Vec3::Zero(), 0.0, c);
  for (int i = 0; i < 9; ++i) standard_normal(d);
  EXPECT_EQ(c(), d());
}

}  // namespace
}  // namespace nav::emulators

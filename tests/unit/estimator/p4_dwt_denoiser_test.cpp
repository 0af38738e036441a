// SPDX-License-Identifier: MIT
// Paper P4's streaming de-noiser (dwt_denoiser.hpp): the stated latency, startup, λ = 0 giving
// the input delayed by D, streaming = block of the window it saw (bit for bit) and = block of
// the whole record with a fixed λ (and not with a shorter delay), refusal of non-finite
// samples and bad configurations, and white noise removed from a 0.19 Hz wave at 50 Hz.
#include "nav/estimator/dwt_denoiser.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

#include <Eigen/Cholesky>

#include "test_support.hpp"

namespace nav::estimator {
namespace {

constexpr Wavelet kWavelets[] = {Wavelet::kHaar, Wavelet::kDb4, Wavelet::kSym4};

// A seeded record: a slow sine plus white noise of standard deviation `noise_std`.
Eigen::VectorXd record(int n, double noise_std, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  Eigen::VectorXd x(n);
  for (int i = 0; i < n; ++i) {
    x(i) = std::sin(2.0 * std::numbers::pi * 0.19 * i / 50.0) + noise_std * n01(rng);
  }
  return x;
}

// Every output of a stream fed x, in push order.
std::vector<DwtStreamOutput> run(DwtDenoiser& f, const Eigen::VectorXd& x) {
  std::vector<DwtStreamOutput> out;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    out.push_back(f.push(x(i)));
  }
  return out;
}

// Latency D: 8 samples for the 8-tap wavelets (0.16 s at 50 Hz), 1 for haar, for any W >= 2L.
TEST(P4DwtDenoiser, LatencyIsFixedByTheFilterLength) {
  for (int W = 16; W <= 256; W += 2) {
    EXPECT_EQ(dwt_denoiser_latency(8, W), 8) << W;
  }
  for (int W = 4; W <= 256; W += 2) {
    EXPECT_EQ(dwt_denoiser_latency(2, W), 1) << W;
  }
  const DwtDenoiser f;  // defaults: sym4, W = 64
  EXPECT_EQ(f.window(), 64);
  EXPECT_EQ(f.latency_samples(), 8);
  EXPECT_DOUBLE_EQ(f.latency_samples() / 50.0, 0.16);
}

// GIVEN W = 16, sym4 (D = 8) WHEN samples are pushed THEN pushes 1..8 give nothing (NaN),
// pushes 9..15 the raw input 8 samples back, and from push 16 (the first full window) on the
// de-noised sample 8 back. reset() starts again.
TEST(P4DwtDenoiser, StartupPassesTheRawInputDelayed) {
  DwtDenoiser f({Wavelet::kSym4, 16, {}});
  ASSERT_EQ(f.latency_samples(), 8);
  const Eigen::VectorXd x = record(40, 0.3, 1);
  for (int round = 0; round < 2; ++round) {
    const std::vector<DwtStreamOutput> out = run(f, x);
    for (int c = 1; c <= 40; ++c) {
      const DwtStreamOutput& o = out[static_cast<std::size_t>(c - 1)];
      if (c <= 8) {
        EXPECT_EQ(o.status, DwtStreamStatus::kStartupEmpty) << c;
        EXPECT_TRUE(std::isnan(o.value)) << c;
        EXPECT_EQ(o.index, -1) << c;
      } else if (c < 16) {
        EXPECT_EQ(o.status, DwtStreamStatus::kStartupRaw) << c;
        EXPECT_EQ(o.index, c - 9) << c;
        EXPECT_EQ(o.value, x(c - 9)) << c;
        EXPECT_EQ(o.lambda, 0.0) << c;
      } else {
        EXPECT_EQ(o.status, DwtStreamStatus::kDenoised) << c;
        EXPECT_EQ(o.index, c - 9) << c;
        EXPECT_GT(o.lambda, 0.0) << c;
      }
    }
    EXPECT_EQ(f.accepted(), 40);
    f.reset();
    EXPECT_EQ(f.accepted(), 0);
  }
}

// GIVEN λ = 0 WHEN a long random record is streamed THEN every output from push D + 1 on is the
// input D samples back (perfect reconstruction), for each wavelet and for W = 2L and 64; to
// 1e-12 relative to max|x| (pywt's sym4 taps are orthonormal to ~1e-12, p4_dwt_test.cpp).
TEST(P4DwtDenoiser, ZeroThresholdIsTheInputDelayed) {
  const Eigen::VectorXd x = record(1001, 2.0, 2);
  const double tol = 1e-12 * x.cwiseAbs().maxCoeff();
  for (const Wavelet w : kWavelets) {
    for (const int W : {2 * filter_bank(w).length, 64}) {
      DwtDenoiser f({w, W, {ThresholdRule::kFixed, 0.0}});
      const int D = f.latency_samples();
      const std::vector<DwtStreamOutput> out = run(f, x);
      for (int c = D + 1; c <= static_cast<int>(x.size()); ++c) {
        const DwtStreamOutput& o = out[static_cast<std::size_t>(c - 1)];
        ASSERT_EQ(o.index, c - 1 - D);
        EXPECT_NEAR(o.value, x(c - 1 - D), tol) << to_string(w) << " W " << W << " c " << c;
      }
    }
  }
}

// GIVEN the default rule (λ from each window's MAD) WHEN a long record is streamed THEN each
// de-noised output i (i >= W − 1 − D) is, bit for bit, sample i − s of denoise() of the W
// samples starting at s = window_start(i), a window that ends at i + D or i + D − 1 (causal),
// with the same λ.
TEST(P4DwtDenoiser, StreamingEqualsTheBlockOfTheWindowItSaw) {
  const Eigen::VectorXd x = record(1000, 0.3, 3);
  for (const Wavelet w : kWavelets) {
    DwtDenoiser f({w, 64, {}});
    const int D = f.latency_samples();
    int checked = 0;
    for (const DwtStreamOutput& o : run(f, x)) {
      if (o.status != DwtStreamStatus::kDenoised) {
        continue;
      }
      const std::int64_t s = f.window_start(o.index);
      ASSERT_EQ(s % 2, 0);
      ASSERT_GE(s, 0);
      ASSERT_TRUE(s + 63 == o.index + D || s + 63 == o.index + D - 1) << o.index;
      const Result<DwtDenoised> block = denoise(x.segment(s, 64), w, {});
      ASSERT_TRUE(block.has_value());
      EXPECT_EQ(o.value, block->x(o.index - s)) << to_string(w) << " i " << o.index;
      EXPECT_EQ(o.lambda, block->lambda);
      ++checked;
    }
    EXPECT_EQ(checked, 1000 - 63);  // every push from the 64th on
  }
}

// GIVEN a fixed λ WHEN a long record is streamed THEN output i equals sample i of denoise() of
// the whole record for every output i in [W − 1 − D, N − L] (to rounding; the last output is
// N − 1 − D); AND a delay of D − 1 would
// not: the window position W − D + 1 is reached by the window's wrap-round.
TEST(P4DwtDenoiser, WithAFixedThresholdStreamingEqualsTheWholeRecordsBlock) {
  const int N = 1000;
  const Eigen::VectorXd x = record(N, 0.3, 4);
  const DwtThreshold fixed{ThresholdRule::kFixed, 0.4};  // thresholds most noise coefficients
  for (const Wavelet w : kWavelets) {
    const int L = filter_bank(w).length;
    const Result<DwtDenoised> whole = denoise(x, w, fixed);
    ASSERT_TRUE(whole.has_value());
    ASSERT_GT((whole->x - x).cwiseAbs().maxCoeff(), 0.1);  // the threshold does something
    DwtDenoiser f({w, 64, fixed});
    const int D = f.latency_samples();
    int checked = 0;
    for (const DwtStreamOutput& o : run(f, x)) {
      if (o.status == DwtStreamStatus::kDenoised && o.index <= N - L) {
        EXPECT_NEAR(o.value, whole->x(o.index), 1e-12) << to_string(w) << " i " << o.index;
        ++checked;
      }
    }
    EXPECT_EQ(checked, std::min(N - L, N - 1 - D) - (64 - 1 - D) + 1);
    if (L > 2) {
      double worst = 0.0;
      for (int s = 0; s + 64 <= N; s += 2) {
        const Result<DwtDenoised> win = denoise(x.segment(s, 64), w, fixed);
        worst = std::max(worst, std::abs(win->x(64 - D + 1) - whole->x(s + 64 - D + 1)));
      }
      EXPECT_GT(worst, 1e-3) << to_string(w);
    }
  }
}

// GIVEN NaN and ±Inf among the samples WHEN pushed THEN each is refused (kRejectedInvalid, NaN,
// index −1), not counted, and the outputs of the finite samples are those of a stream that
// never saw them.
TEST(P4DwtDenoiser, NonFiniteSamplesAreRefused) {
  const Eigen::VectorXd x = record(300, 0.3, 5);
  DwtDenoiser clean;
  DwtDenoiser dirty;
  const double bad[] = {std::nan(""), INFINITY, -INFINITY};
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    if (i % 37 == 5) {
      const DwtStreamOutput r = dirty.push(bad[i % 3]);
      EXPECT_EQ(r.status, DwtStreamStatus::kRejectedInvalid);
      EXPECT_TRUE(std::isnan(r.value));
      EXPECT_EQ(r.index, -1);
      EXPECT_EQ(dirty.accepted(), i);
    }
    const DwtStreamOutput a = clean.push(x(i));
    const DwtStreamOutput b = dirty.push(x(i));
    EXPECT_EQ(a.status, b.status);
    EXPECT_EQ(a.index, b.index);
    if (a.status != DwtStreamStatus::kStartupEmpty) {
      EXPECT_EQ(a.value, b.value) << i;
    }
  }
  EXPECT_EQ(dirty.accepted(), 300);
}

// Configurations that cannot work are refused by validate(); constructing with one is a
// contract violation (NAV_ENSURE, which the test support turns into an exception).
TEST(P4DwtDenoiser, BadConfigurationsAreRefused) {
  EXPECT_TRUE(validate(DwtDenoiserConfig{}).has_value());
  EXPECT_TRUE(validate(DwtDenoiserConfig{Wavelet::kHaar, 4, {}}).has_value());
  EXPECT_FALSE(validate(DwtDenoiserConfig{Wavelet::kSym4, 14, {}}).has_value());   // < 2L
  EXPECT_FALSE(validate(DwtDenoiserConfig{Wavelet::kSym4, 63, {}}).has_value());   // odd
  EXPECT_FALSE(validate(DwtDenoiserConfig{Wavelet::kDb4, 8192, {}}).has_value());  // > 4096
  EXPECT_FALSE(
      validate(DwtDenoiserConfig{Wavelet::kDb4, 64, {ThresholdRule::kFixed, -0.1}}).has_value());
  EXPECT_THROW(DwtDenoiser({Wavelet::kSym4, 10, {}}), std::logic_error);
}

// GIVEN a 0.19 Hz wave (period 5.3 s, amplitude 1 m/s²) sampled at 50 Hz plus white noise of
// 0.3 m/s² (seed 2013) WHEN streamed through the default de-noiser (sym4, W = 64, MAD) THEN
// the RMS error to the wave drops below 0.8 of the raw error (a level-1 transform can at best
// remove the half of white noise above fs/4: ~1/√2), AND the wave comes out delayed by exactly
// D samples with its amplitude within 1 % (least-squares fit; the fit's noise is ~0.3 %).
// Without noise the wave passes to 1e-6 (its detail coefficients are far below any λ).
TEST(P4DwtDenoiser, RemovesWhiteNoiseAndPassesTheWave) {
  const int N = 6000;
  const double fs = 50.0;
  const double w0 = 2.0 * std::numbers::pi * 0.19;
  const Eigen::VectorXd x = record(N, 0.3, 2013);
  const Eigen::VectorXd clean = record(N, 0.0, 2013);
  DwtDenoiser f;
  double err_before = 0.0, err_after = 0.0;
  int n = 0;
  Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
  Eigen::Vector2d b = Eigen::Vector2d::Zero();
  for (const DwtStreamOutput& o : run(f, x)) {
    if (o.status != DwtStreamStatus::kDenoised) {
      continue;
    }
    const double truth = clean(o.index);
    err_before += (x(o.index) - truth) * (x(o.index) - truth);
    err_after += (o.value - truth) * (o.value - truth);
    ++n;
    const double t = static_cast<double>(o.index) / fs;  // [s]
    const Eigen::Vector2d basis(std::sin(w0 * t), std::cos(w0 * t));
    A += basis * basis.transpose();
    b += basis * o.value;
  }
  const double rms_before = std::sqrt(err_before / n);
  const double rms_after = std::sqrt(err_after / n);
  EXPECT_NEAR(rms_before, 0.3, 0.01);
  EXPECT_LT(rms_after, 0.8 * rms_before) << rms_before << " -> " << rms_after;
  const Eigen::Vector2d ab = A.ldlt().solve(b);  // y ≈ a sin + b cos
  EXPECT_NEAR(ab.norm(), 1.0, 0.01);
  EXPECT_NEAR(std::atan2(ab(1), ab(0)), 0.0, 0.01);  // in phase: the delay is exactly D

  DwtDenoiser g;
  for (const DwtStreamOutput& o : run(g, clean)) {
    if (o.status == DwtStreamStatus::kDenoised) {
      EXPECT_NEAR(o.value, clean(o.index), 1e-6) << o.index;
    }
  }
}

}  // namespace
}  // namespace nav::estimator

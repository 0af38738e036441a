// SPDX-License-Identifier: MIT
// The hand-guided truth kind and its band-limited signals: consistent (integration recovers
// the states), the requested RMS in the requested band, on its mark at t = 0, on the nominal
// path when only the speed is uneven, deterministic per seed, and refusals naming the band.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <random>

#include "emulator_test_support.hpp"
#include "nav/emulators/band_limited.hpp"
#include "nav/emulators/hand_guided_truth.hpp"
#include "truth_consistency.hpp"

namespace nav::emulators {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;
constexpr double kG = 9.80665;
constexpr double kDeg = std::numbers::pi / 180.0;

/// Mean square of the order-th derivative of s over [0, T] on steps of h.
double mean_square(const BandLimitedSignal& s, int order, double T, double h) {
  double sum = 0.0;
  int n = 0;
  for (double t = 0.0; t < T; t += h, ++n) {
    const SignalValue v = s.at(t);
    const double x = order == 0 ? v.x : order == 1 ? v.dx : v.ddx;
    sum += x * x;
  }
  return sum / n;
}

TEST(BandLimitedSignal, HasTheRequestedRmsOfTheRequestedDerivative) {
  for (const int order : {0, 1, 2}) {
    std::mt19937_64 rng(7);
    const BandLimitedSignal s(BandSpec{0.3, order, 0.5, 2.0, 24}, rng);
    // Over 2000 s (1000 periods of the lowest frequency) the cross terms average out.
    EXPECT_NEAR(std::sqrt(mean_square(s, order, 2000.0, 0.01)), 0.3, 0.3 * 0.02)
        << "order " << order;
  }
}

TEST(BandLimitedSignal, DerivativesAreThoseOfTheSignal) {
  std::mt19937_64 rng(3);
  const BandLimitedSignal s(BandSpec{1.0, 0, 0.1, 3.0, 16}, rng);
  const double h = 1e-5;
  for (const double t : {0.0, 1.234, 77.7}) {
    const SignalValue a = s.at(t - h), m = s.at(t), b = s.at(t + h);
    EXPECT_NEAR(m.dx, (b.x - a.x) / (2 * h), 1e-6);
    EXPECT_NEAR(m.ddx, (b.dx - a.dx) / (2 * h), 1e-5);
  }
}

TEST(BandLimitedSignal, HoldsNoPowerOutsideItsBand) {
  // Correlate with a sinusoid: inside the band the projection is of the order of the
  // amplitude; well outside it (a tenth of the lower edge, 3x the upper) it vanishes.
  std::mt19937_64 rng(11);
  const BandLimitedSignal s(BandSpec{1.0, 0, 1.0, 2.0, 8}, rng);
  const auto power_at = [&](double f_hz) {
    const double T = 400.0, h = 0.02;
    double c = 0.0, d = 0.0;
    for (double t = 0.0; t < T; t += h) {
      c += s.at(t).x * std::cos(2 * std::numbers::pi * f_hz * t) * h;
      d += s.at(t).x * std::sin(2 * std::numbers::pi * f_hz * t) * h;
    }
    return (c * c + d * d) / (T * T);
  };
  double inside = 0.0;
  for (double f = 1.0; f <= 2.0; f += 0.005) inside = std::max(inside, power_at(f));
  EXPECT_GT(inside, 0.01);
  EXPECT_LT(power_at(0.1), 1e-6);
  EXPECT_LT(power_at(6.0), 1e-6);
}

TEST(BandLimitedSignal, ZeroRmsIsSilent) {
  std::mt19937_64 rng(1);
  const BandLimitedSignal s(BandSpec{0.0, 0, 0.1, 1.0, 24}, rng);
  const SignalValue v = s.at(12.0);
  EXPECT_EQ(v.x, 0.0);
  EXPECT_EQ(v.dx, 0.0);
  EXPECT_EQ(v.ddx, 0.0);
}

/// Every band on, at the magnitudes of the P0 paper scenarios.
HandGuidedSpec everything_on() {
  HandGuidedSpec h;
  h.speed.rms = 0.2;
  h.sway.rms = 0.2;
  h.heave.rms = 0.05;
  h.roll.rms = 3 * kDeg;
  h.pitch.rms = 3 * kDeg;
  h.yaw.rms = 3 * kDeg;
  h.shake.rms = 0.3;
  return h;
}

std::shared_ptr<const TruthTrajectory> nominal() {
  return std::make_shared<const TruthTrajectory>(testing::manoeuvring_truth(0.7, 2.0, 0.0, 0.0));
}

TEST(HandGuidedTruth, IsConsistent) {
  const auto h = HandGuidedTruth::build(nominal(), everything_on(), 42, kG, seconds(40));
  ASSERT_TRUE(h) << h.error().detail;
  testing::expect_consistent_truth(*h, seconds(0), seconds(30), kG, milliseconds(2));
}

TEST(HandGuidedTruth, StartsOnItsMarkAndWandersOffThePath) {
  const auto base = nominal();
  const auto h = HandGuidedTruth::build(base, everything_on(), 42, kG, seconds(40));
  ASSERT_TRUE(h);
  EXPECT_LT((h->at(seconds(0)).p_n - base->at(seconds(0)).p_n).norm(), 1e-12);
  double worst_m = 0.0, worst_tilt = 0.0;
  for (int k = 0; k <= 300; ++k) {
    const auto t = milliseconds(100 * k);
    const TruthSample s = h->at(t);
    worst_m = std::max(worst_m, (s.p_n - base->at(t).p_n).norm());
    const Euler e = euler_from_quat(s.q_nb);
    worst_tilt = std::max({worst_tilt, std::abs(e.roll), std::abs(e.pitch)});
  }
  // Off the nominal by decimetres (sway plus being ahead or behind), tilted by degrees.
  EXPECT_GT(worst_m, 0.05);
  EXPECT_LT(worst_m, 5.0);
  EXPECT_GT(worst_tilt, 1 * kDeg);
  EXPECT_LT(worst_tilt, 20 * kDeg);
}

TEST(HandGuidedTruth, UnevenSpeedAloneKeepsToThePath) {
  HandGuidedSpec spec;
  spec.speed.rms = 0.2;
  const auto base = nominal();
  const auto h = HandGuidedTruth::build(base, spec, 5, kG, seconds(40));
  ASSERT_TRUE(h);
  bool ahead_or_behind = false;
  for (int k = 1; k <= 200; ++k) {
    const auto t = milliseconds(150 * k);
    const TruthSample s = h->at(t);
    // Somewhere on the nominal path: the nominal at the warped time, a point it passes.
    double nearest = 1e9;
    for (int j = -400; j <= 400; ++j) {
      const auto u = t + milliseconds(10 * j);
      if (u.count() < 0) continue;
      nearest = std::min(nearest, (base->at(u).p_n - s.p_n).norm());
    }
    EXPECT_LT(nearest, 0.01) << "off the path at " << to_seconds(t) << " s";
    if ((base->at(t).p_n - s.p_n).norm() > 0.05) ahead_or_behind = true;
    EXPECT_NEAR(euler_from_quat(s.q_nb).roll, 0.0, 1e-9);
  }
  EXPECT_TRUE(ahead_or_behind);
}

TEST(HandGuidedTruth, IsDeterministicPerSeed) {
  const auto a = HandGuidedTruth::build(nominal(), everything_on(), 1, kG, seconds(40));
  const auto b = HandGuidedTruth::build(nominal(), everything_on(), 1, kG, seconds(40));
  const auto c = HandGuidedTruth::build(nominal(), everything_on(), 2, kG, seconds(40));
  const TruthSample sa = a->at(seconds(17)), sb = b->at(seconds(17)), sc = c->at(seconds(17));
  EXPECT_EQ(sa.p_n, sb.p_n);
  EXPECT_EQ(sa.f_b, sb.f_b);
  EXPECT_NE(sa.p_n, sc.p_n);
}

TEST(HandGuidedTruth, RefusesABadBandOrASpeedThatRunsBackwards) {
  HandGuidedSpec bad = everything_on();
  bad.sway.f_lo_hz = 0.0;
  const auto r = HandGuidedTruth::build(nominal(), bad, 1, kG, seconds(40));
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().detail.find("hand_guided.sway"), std::string::npos) << r.error().detail;

  HandGuidedSpec wild = everything_on();
  wild.speed.rms = 3.0;  // the rig would run backwards along its path
  const auto w = HandGuidedTruth::build(nominal(), wild, 1, kG, seconds(40));
  ASSERT_FALSE(w);
  EXPECT_NE(w.error().detail.find("hand_guided.speed"), std::string::npos) << w.error().detail;
}

}  // namespace
}  // namespace nav::emulators

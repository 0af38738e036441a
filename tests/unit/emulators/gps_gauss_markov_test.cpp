// SPDX-License-Identifier: MIT
// The GPS receiver's time-correlated position error (gps_emulator.cpp G1, G2): a first-order
// Gauss–Markov process per axis with the configured σ, whose autocorrelation at lag τ is
// e^(−1); drawn from its own engine, so the white noise of the same seed is unchanged.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "nav/common/geodesy.hpp"
#include "nav/common/units.hpp"
#include "nav/emulators/device.hpp"
#include "nav/protocols/nmea0183.hpp"

#include "emulator_test_support.hpp"

namespace nav::emulators {
namespace {

using std::chrono::seconds;
namespace nmea = protocols::nmea;

GpsConfig config() {
  GpsConfig cfg;
  cfg.rate_hz = 1.0;
  cfg.horizontal_std_m = 0.0;
  cfg.vertical_std_m = 0.0;
  cfg.velocity_std_mps = 0.0;
  cfg.datum_lat_rad = units::deg_to_rad(35.1);
  cfg.datum_lon_rad = units::deg_to_rad(129.04);
  return cfg;
}

/// Each epoch's position error against truth, NED [m].
std::vector<Vec3> errors_of(const GpsConfig& cfg, const Truth& truth, Duration duration,
                            std::uint64_t seed) {
  const geodesy::LocalTangentPlane ltp(
      geodesy::Geodetic{cfg.datum_lat_rad, cfg.datum_lon_rad, cfg.datum_alt_m});
  std::vector<Vec3> out;
  for (const WireMessage& m : generate_gps(cfg, truth, duration, seed)) {
    const auto s = nmea::parse(m.bytes);
    EXPECT_TRUE(s.message.has_value());
    const auto gga = nmea::decode_gga(*s.message);
    EXPECT_TRUE(gga.has_value());
    const Vec3 p = ltp.to_ned(geodesy::Geodetic{units::deg_to_rad(*gga->lat_deg),
                                                units::deg_to_rad(*gga->lon_deg),
                                                *gga->alt_msl_m});
    out.push_back(p - truth.at(m.t_valid).p_n);
  }
  return out;
}

/// Sample autocorrelation of axis i at lag k.
double autocorrelation(const std::vector<Vec3>& e, int i, std::size_t k) {
  double mean = 0.0;
  for (const auto& v : e) mean += v(i);
  mean /= static_cast<double>(e.size());
  double c0 = 0.0, ck = 0.0;
  for (std::size_t n = 0; n < e.size(); ++n) {
    const double a = e[n](i) - mean;
    c0 += a * a;
    if (n + k < e.size()) ck += a * (e[n + k](i) - mean);
  }
  return ck / c0;
}

TEST(GpsGaussMarkov, StdAndAutocorrelationAtTauAreTheConfiguredOnes) {
  GpsConfig cfg = config();
  cfg.correlated_horizontal_std_m = 2.0;
  cfg.correlated_vertical_std_m = 3.0;
  cfg.correlation_time_s = 20.0;
  const TruthTrajectory truth = testing::surface_turn_truth();
  const auto e = errors_of(cfg, truth, seconds(20000), device_seed(5, "gps"));
  ASSERT_EQ(e.size(), 20000u);
  const Vec3 sigma(2.0, 2.0, 3.0);
  for (int i = 0; i < 3; ++i) {
    double s2 = 0.0;
    for (const auto& v : e) s2 += v(i) * v(i);
    // 20 000 epochs of a process correlated over 20: about 500 independent samples, so the
    // std is known to ~3 %; 10 % is over 3 standard errors.
    EXPECT_NEAR(std::sqrt(s2 / static_cast<double>(e.size())), sigma(i), 0.10 * sigma(i)) << i;
    // ρ(τ) = e^(−1) = 0.368, its estimate's standard error about 0.03 here.
    EXPECT_NEAR(autocorrelation(e, i, 20), std::exp(-1.0), 0.1) << i;
    EXPECT_NEAR(autocorrelation(e, i, 1), std::exp(-1.0 / 20.0), 0.03) << i;
  }
}

TEST(GpsGaussMarkov, TheWhiteNoiseOfTheSameSeedIsUnchanged) {
  GpsConfig white = config();
  white.horizontal_std_m = 1.0;
  white.vertical_std_m = 1.0;
  GpsConfig both = white;
  both.correlated_horizontal_std_m = 0.5;
  both.correlated_vertical_std_m = 0.5;
  both.correlation_time_s = 30.0;
  const TruthTrajectory truth = testing::surface_turn_truth();
  const auto a = errors_of(white, truth, seconds(3000), device_seed(9, "gps"));
  const auto b = errors_of(both, truth, seconds(3000), device_seed(9, "gps"));
  ASSERT_EQ(a.size(), b.size());
  // b − a is the wander alone: smooth from one epoch to the next (ρ(1) = e^(−1/30) = 0.967),
  // which it could not be if the white draws had moved.
  std::vector<Vec3> d;
  for (std::size_t k = 0; k < a.size(); ++k) d.push_back(b[k] - a[k]);
  for (int i = 0; i < 3; ++i) EXPECT_GT(autocorrelation(d, i, 1), 0.9) << i;
}

}  // namespace
}  // namespace nav::emulators

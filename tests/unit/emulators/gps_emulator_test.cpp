// SPDX-License-Identifier: MIT
// GPS emulator: the GGA/RMC text it emits, decoded with the NMEA codec, against truth.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "nav/common/geodesy.hpp"
#include "nav/common/units.hpp"
#include "nav/emulators/device.hpp"
#include "nav/protocols/nmea0183.hpp"

#include "emulator_test_support.hpp"

namespace nav::emulators {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;
using units::deg_to_rad;
namespace nmea = protocols::nmea;

/// One epoch's two sentences, framed and decoded.
struct Epoch {
  nmea::Sentence gga_sentence, rmc_sentence;
  nmea::Gga gga;
  nmea::Rmc rmc;
};

Epoch decode(const WireMessage& msg) {
  Epoch e;
  protocols::ByteSpan rest(msg.bytes);
  const auto first = nmea::parse(rest);
  EXPECT_EQ(first.status, protocols::ParseStatus::kComplete) << first.error;
  rest = rest.subspan(first.consumed);
  const auto second = nmea::parse(rest);
  EXPECT_EQ(second.status, protocols::ParseStatus::kComplete) << second.error;
  EXPECT_EQ(second.consumed, rest.size()) << "bytes after RMC";
  if (!first.message || !second.message) return e;
  e.gga_sentence = *first.message;
  e.rmc_sentence = *second.message;
  auto gga = nmea::decode_gga(e.gga_sentence);
  auto rmc = nmea::decode_rmc(e.rmc_sentence);
  EXPECT_TRUE(gga.has_value()) << (gga ? "" : gga.error().detail);
  EXPECT_TRUE(rmc.has_value()) << (rmc ? "" : rmc.error().detail);
  if (gga) e.gga = *gga;
  if (rmc) e.rmc = *rmc;
  return e;
}

GpsConfig zero_noise_config() {
  GpsConfig cfg;
  cfg.horizontal_std_m = 0.0;
  cfg.vertical_std_m = 0.0;
  cfg.velocity_std_mps = 0.0;
  cfg.datum_lat_rad = deg_to_rad(36.3833);
  cfg.datum_lon_rad = deg_to_rad(127.3600);
  cfg.datum_alt_m = 0.0;
  return cfg;
}

geodesy::LocalTangentPlane plane(const GpsConfig& cfg) {
  return geodesy::LocalTangentPlane(
      geodesy::Geodetic{cfg.datum_lat_rad, cfg.datum_lon_rad, cfg.datum_alt_m});
}

/// A surface run with a turn: heading sweeps through several quadrants.
TruthTrajectory surface_truth() { return testing::surface_turn_truth(); }

/// Surface, then a dive to 5 m, a run underwater, and back up.
TruthTrajectory diving_truth() { return testing::diving_truth(10.0, 10.0, 0.3); }

TEST(GpsEmulator, ZeroNoiseDecodesToTruthWithinNmeaResolution) {
  const GpsConfig cfg = zero_noise_config();
  const TruthTrajectory truth = surface_truth();
  const auto ltp = plane(cfg);
  const auto msgs = generate_gps(cfg, truth, seconds(60), 1);
  ASSERT_EQ(msgs.size(), 60u);
  int with_course = 0;
  for (std::size_t k = 0; k < msgs.size(); ++k) {
    const WireMessage& msg = msgs[k];
    EXPECT_EQ(msg.t_valid, seconds(static_cast<std::int64_t>(k)));
    EXPECT_EQ(msg.t_send, msg.t_valid + milliseconds(50));
    EXPECT_FALSE(msg.trigger_tag.has_value());
    const Epoch e = decode(msg);
    const TruthSample s = truth.at(msg.t_valid);
    EXPECT_EQ(e.gga_sentence.talker, "GP");
    EXPECT_EQ(e.gga.quality, 1);
    EXPECT_EQ(e.gga.satellites, 10);
    ASSERT_TRUE(e.gga.hdop && e.gga.alt_msl_m && e.gga.geoid_sep_m && e.gga.lat_deg);
    EXPECT_DOUBLE_EQ(*e.gga.hdop, 0.9);
    EXPECT_DOUBLE_EQ(*e.gga.geoid_sep_m, 0.0);
    // GGA altitude has 0.1 m resolution; the Earth's curvature over 50 m adds < 1 mm.
    EXPECT_NEAR(*e.gga.alt_msl_m, -s.p_n.z(), 0.05 + 1e-3);
    const Vec3 p_n = ltp.to_ned(geodesy::Geodetic{deg_to_rad(*e.gga.lat_deg),
                                                  deg_to_rad(*e.gga.lon_deg), -s.p_n.z()});
    // 1e-5 arcmin = 1.85 cm of latitude: rounding error at most half of that per axis.
    EXPECT_LT((p_n - s.p_n).head<2>().norm(), 0.0135) << "epoch " << k;

    EXPECT_TRUE(e.rmc.valid);
    EXPECT_EQ(e.rmc.mode, 'A');
    EXPECT_EQ(e.rmc.lat_deg, e.gga.lat_deg);
    EXPECT_EQ(e.rmc.lon_deg, e.gga.lon_deg);
    ASSERT_TRUE(e.rmc.sog_kn.has_value());
    const double speed = s.v_n.head<2>().norm();
    EXPECT_NEAR(*e.rmc.sog_kn * units::kKnotToMps, speed, 0.0006 * units::kKnotToMps);
    if (speed >= 0.05) {
      ASSERT_TRUE(e.rmc.cog_deg.has_value()) << "epoch " << k;
      const double yaw_deg = units::rad_to_deg(std::atan2(s.v_n.y(), s.v_n.x()));
      EXPECT_NEAR(std::remainder(*e.rmc.cog_deg - yaw_deg, 360.0), 0.0, 0.006);
      EXPECT_GE(*e.rmc.cog_deg, 0.0);
      EXPECT_LT(*e.rmc.cog_deg, 360.0);
      ++with_course;
    }
  }
  // At rest (t = 0, and t = 1 s at 0.015 m/s) no course exists yet: the field is empty.
  EXPECT_FALSE(decode(msgs[0]).rmc.cog_deg.has_value());
  EXPECT_FALSE(decode(msgs[1]).rmc.cog_deg.has_value());
  EXPECT_GE(with_course, 55);
}

TEST(GpsEmulator, UtcFollowsScenarioTime) {
  GpsConfig cfg = zero_noise_config();
  cfg.rate_hz = 4.0;
  const auto msgs = generate_gps(cfg, surface_truth(), seconds(3), 1);
  ASSERT_EQ(msgs.size(), 12u);
  for (const WireMessage& msg : msgs) {
    const Epoch e = decode(msg);
    const double expected = cfg.utc_start_unix_s + to_seconds(msg.t_valid);
    EXPECT_NEAR(e.rmc.time.unix_seconds(), expected, 1e-6);
    EXPECT_EQ(e.rmc.time.year, 2026);
    EXPECT_EQ(e.rmc.time.month, 6);
    EXPECT_EQ(e.rmc.time.day, 1);
    EXPECT_EQ(e.gga.time.hour, 12);
    EXPECT_EQ(e.gga.time.minute, 0);
    EXPECT_NEAR(e.gga.time.second, to_seconds(msg.t_valid), 1e-9);
  }
}

TEST(GpsEmulator, UnderwaterReceiverReportsNoFixWithEmptyFields) {
  const GpsConfig cfg = zero_noise_config();
  const TruthTrajectory truth = diving_truth();
  const auto msgs = generate_gps(cfg, truth, truth.path_duration() + seconds(5), 1);
  int fixes = 0, no_fixes = 0;
  for (const WireMessage& msg : msgs) {
    const Epoch e = decode(msg);
    const bool deep = truth.at(msg.t_valid).p_n.z() > cfg.max_depth_for_fix_m;
    if (!deep) {
      EXPECT_EQ(e.gga.quality, 1);
      EXPECT_TRUE(e.rmc.valid);
      ++fixes;
      continue;
    }
    ++no_fixes;
    EXPECT_EQ(e.gga.quality, 0);
    EXPECT_EQ(e.gga.satellites, 0);
    EXPECT_FALSE(e.gga.lat_deg || e.gga.lon_deg || e.gga.hdop || e.gga.alt_msl_m ||
                 e.gga.geoid_sep_m);
    EXPECT_FALSE(e.rmc.valid);
    EXPECT_FALSE(e.rmc.lat_deg || e.rmc.lon_deg || e.rmc.sog_kn || e.rmc.cog_deg);
    EXPECT_EQ(e.rmc.mode, 'N');
    // The raw fields are empty, not zero: GGA 2..5, 8..12 and RMC 3..8.
    for (const std::size_t i : {1u, 2u, 3u, 4u, 7u, 8u, 9u, 10u, 11u}) {
      EXPECT_EQ(e.gga_sentence.fields.at(i), "") << "GGA field " << i + 1;
    }
    for (const std::size_t i : {2u, 3u, 4u, 5u, 6u, 7u}) {
      EXPECT_EQ(e.rmc_sentence.fields.at(i), "") << "RMC field " << i + 1;
    }
    EXPECT_EQ(e.rmc_sentence.fields.at(1), "V");
    EXPECT_FALSE(e.rmc_sentence.fields.at(8).empty()) << "the date keeps running";
  }
  EXPECT_GT(fixes, 20);
  EXPECT_GT(no_fixes, 10);
}

TEST(GpsEmulator, NoisyFixesHaveTheConfiguredErrors) {
  GpsConfig cfg = zero_noise_config();
  cfg.rate_hz = 10.0;
  cfg.horizontal_std_m = 1.0;
  cfg.vertical_std_m = 2.0;
  cfg.velocity_std_mps = 0.05;
  const TruthTrajectory truth = surface_truth();
  const auto ltp = plane(cfg);
  const auto msgs = generate_gps(cfg, truth, seconds(600), device_seed(42, "gps"));
  ASSERT_EQ(msgs.size(), 6000u);
  const auto n = static_cast<double>(msgs.size());
  Vec3 sum = Vec3::Zero(), sum2 = Vec3::Zero();
  double sum_sog_err = 0.0, sum2_sog_err = 0.0;
  int fast = 0;
  for (const WireMessage& msg : msgs) {
    const Epoch e = decode(msg);
    const TruthSample s = truth.at(msg.t_valid);
    const Vec3 p_n = ltp.to_ned(geodesy::Geodetic{deg_to_rad(*e.gga.lat_deg),
                                                  deg_to_rad(*e.gga.lon_deg), *e.gga.alt_msl_m});
    const Vec3 err = p_n - s.p_n;
    sum += err;
    sum2 += err.cwiseAbs2();
    if (s.v_n.head<2>().norm() > 1.0) {  // SOG error ~ along-track velocity noise
      const double d = *e.rmc.sog_kn * units::kKnotToMps - s.v_n.head<2>().norm();
      sum_sog_err += d;
      sum2_sog_err += d * d;
      ++fast;
    }
  }
  const Vec3 mean = sum / n;
  const Vec3 std = (sum2 / n - mean.cwiseAbs2()).cwiseSqrt();
  const Vec3 sigma{1.0, 1.0, 2.0};
  for (int i = 0; i < 3; ++i) {
    // mean within 5 standard errors; std within 5 % (5.5 standard errors at N = 6000);
    // NMEA rounding (1 cm, 5 cm) is negligible against both.
    EXPECT_NEAR(mean[i], 0.0, 5.0 * sigma[i] / std::sqrt(n)) << "axis " << i;
    EXPECT_NEAR(std[i], sigma[i], 0.05 * sigma[i]) << "axis " << i;
  }
  ASSERT_GT(fast, 1000);
  const double sog_std = std::sqrt(sum2_sog_err / fast - std::pow(sum_sog_err / fast, 2));
  EXPECT_NEAR(sog_std, 0.05, 0.05 * 0.05 + 5.0 * 0.05 / std::sqrt(2.0 * fast));
}

TEST(GpsEmulator, SameSeedSameBytesOtherSeedOtherBytes) {
  GpsConfig cfg = zero_noise_config();
  cfg.horizontal_std_m = 0.5;
  cfg.talker = "GN";
  const TruthTrajectory truth = surface_truth();
  const auto a = generate_gps(cfg, truth, seconds(20), device_seed(7, "gps"));
  const auto b = generate_gps(cfg, truth, seconds(20), device_seed(7, "gps"));
  const auto c = generate_gps(cfg, truth, seconds(20), device_seed(7, "gps2"));
  ASSERT_EQ(a.size(), 20u);
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].bytes, b[k].bytes);
    EXPECT_NE(a[k].bytes, c[k].bytes);
    EXPECT_EQ(decode(a[k]).rmc_sentence.talker, "GN");
  }
}

}  // namespace
}  // namespace nav::emulators

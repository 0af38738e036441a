// SPDX-License-Identifier: MIT
// GPS emulator options: VTG, HDT and ZDA sentences decoded against truth, the re-acquisition
// delay after surfacing, and the draws of GGA/RMC left unchanged by the options.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "nav/common/frames.hpp"
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

/// Every sentence of one epoch, in order.
std::vector<nmea::Sentence> sentences(const WireMessage& msg) {
  std::vector<nmea::Sentence> out;
  protocols::ByteSpan rest(msg.bytes);
  while (!rest.empty()) {
    const auto r = nmea::parse(rest);
    EXPECT_EQ(r.status, protocols::ParseStatus::kComplete) << r.error;
    if (r.status != protocols::ParseStatus::kComplete || !r.message) break;
    out.push_back(*r.message);
    rest = rest.subspan(r.consumed);
  }
  return out;
}

GpsConfig all_sentences_config() {
  GpsConfig cfg;
  cfg.horizontal_std_m = 0.0;
  cfg.vertical_std_m = 0.0;
  cfg.velocity_std_mps = 0.0;
  cfg.datum_lat_rad = deg_to_rad(36.3833);
  cfg.datum_lon_rad = deg_to_rad(127.3600);
  cfg.vtg = true;
  cfg.hdt = true;
  cfg.zda = true;
  return cfg;
}

/// A surface run with a turn through every quadrant, rolling (heading != course).
TruthTrajectory surface_truth() {
  TrajectorySpec spec;
  spec.start_yaw_rad = deg_to_rad(-100.0);
  spec.max_accel_mps2 = 0.3;
  Segment s1;
  s1.length_m = 20.0;
  s1.speed_mps = 1.5;
  Segment s2;
  s2.kind = Segment::Kind::kArc;
  s2.radius_m = 15.0;
  s2.angle_rad = deg_to_rad(300.0);
  s2.speed_mps = 1.5;
  spec.segments = {s1, s2};
  spec.motion.roll_amplitude_rad = 0.1;
  spec.motion.period_s = 5.0;
  return *TruthTrajectory::build(spec);
}

/// Surface run, dive to 5 m, run underwater, surface, long surface run.
TruthTrajectory diving_truth() { return testing::diving_truth(10.0, 30.0, 0.3); }

TEST(GpsEmulatorExt, VtgHdtZdaFollowGgaRmcAndDecodeToTruth) {
  const GpsConfig cfg = all_sentences_config();
  const TruthTrajectory truth = surface_truth();
  const auto msgs = generate_gps(cfg, truth, seconds(60), 1);
  ASSERT_EQ(msgs.size(), 60u);
  int with_course = 0;
  for (std::size_t k = 0; k < msgs.size(); ++k) {
    const auto s = sentences(msgs[k]);
    ASSERT_EQ(s.size(), 5u);
    EXPECT_EQ(s[0].type, "GGA");
    EXPECT_EQ(s[1].type, "RMC");
    EXPECT_EQ(s[2].type, "VTG");
    EXPECT_EQ(s[3].type, "HDT");
    EXPECT_EQ(s[4].type, "ZDA");
    for (const auto& x : s) EXPECT_EQ(x.talker, "GP");
    const auto rmc = nmea::decode_rmc(s[1]);
    const auto vtg = nmea::decode_vtg(s[2]);
    const auto hdt = nmea::decode_hdt(s[3]);
    const auto zda = nmea::decode_zda(s[4]);
    ASSERT_TRUE(rmc && vtg && hdt && zda);
    const TruthSample t = truth.at(msgs[k].t_valid);
    const double speed = t.v_n.head<2>().norm();

    // VTG: the RMC's course and speed; km/h with 3 decimals.
    EXPECT_EQ(vtg->cog_true_deg, rmc->cog_deg);
    EXPECT_FALSE(vtg->cog_mag_deg.has_value());
    EXPECT_EQ(vtg->sog_kn, rmc->sog_kn);
    ASSERT_TRUE(vtg->sog_kmh.has_value());
    EXPECT_NEAR(*vtg->sog_kmh / 3.6, speed, 0.0005 / 3.6 + 1e-9);
    EXPECT_EQ(vtg->mode, std::optional<char>('A'));
    if (speed >= 0.05) {
      ASSERT_TRUE(vtg->cog_true_deg.has_value());
      const double course = units::rad_to_deg(std::atan2(t.v_n.y(), t.v_n.x()));
      EXPECT_NEAR(std::remainder(*vtg->cog_true_deg - course, 360.0), 0.0, 0.006);
      ++with_course;
    }

    // HDT: true heading of the body, [0, 360), 2 decimals.
    ASSERT_TRUE(hdt->heading_deg.has_value());
    const double yaw = units::rad_to_deg(euler_from_quat(t.q_nb).yaw);
    EXPECT_NEAR(std::remainder(*hdt->heading_deg - yaw, 360.0), 0.0, 0.005 + 1e-9) << k;
    EXPECT_GE(*hdt->heading_deg, 0.0);
    EXPECT_LT(*hdt->heading_deg, 360.0);

    // ZDA: receiver UTC with date, zone 00:00.
    EXPECT_NEAR(zda->time.unix_seconds(), cfg.utc_start_unix_s + to_seconds(msgs[k].t_valid),
                1e-6);
    EXPECT_EQ(zda->time.year, 2026);
    EXPECT_EQ(zda->time.month, 6);
    EXPECT_EQ(zda->time.day, 1);
    EXPECT_EQ(zda->zone_hours, std::optional<int>(0));
    EXPECT_EQ(zda->zone_minutes, std::optional<int>(0));
  }
  EXPECT_GE(with_course, 55);
}

TEST(GpsEmulatorExt, OptionsAppendAfterGgaRmcAndDrawOnlyWhenEnabled) {
  GpsConfig plain = all_sentences_config();
  plain.vtg = plain.hdt = plain.zda = false;
  plain.horizontal_std_m = 1.0;
  plain.vertical_std_m = 2.0;
  plain.velocity_std_mps = 0.1;
  GpsConfig no_draws = plain;  // VTG and ZDA draw nothing
  no_draws.vtg = no_draws.zda = true;
  GpsConfig all = no_draws;    // HDT draws its noise after the GGA/RMC draws of each epoch
  all.hdt = true;
  all.heading_std_rad = 0.01;
  const TruthTrajectory truth = surface_truth();
  const auto a = generate_gps(plain, truth, seconds(30), device_seed(4, "gps"));
  const auto b = generate_gps(no_draws, truth, seconds(30), device_seed(4, "gps"));
  const auto c = generate_gps(all, truth, seconds(30), device_seed(4, "gps"));
  ASSERT_EQ(a.size(), 30u);
  ASSERT_EQ(b.size(), 30u);
  ASSERT_EQ(c.size(), 30u);
  const auto is_prefix = [](const WireMessage& p, const WireMessage& m) {
    return p.bytes.size() < m.bytes.size() &&
           std::equal(p.bytes.begin(), p.bytes.end(), m.bytes.begin());
  };
  for (std::size_t k = 0; k < a.size(); ++k) EXPECT_TRUE(is_prefix(a[k], b[k])) << k;
  // Epoch 0's GGA/RMC noise is drawn before the heading noise; later epochs shift by one draw.
  EXPECT_TRUE(is_prefix(a[0], c[0]));
  EXPECT_FALSE(is_prefix(a[1], c[1]));
}

TEST(GpsEmulatorExt, HeadingNoiseHasTheConfiguredStd) {
  GpsConfig cfg = all_sentences_config();
  cfg.rate_hz = 10.0;
  cfg.heading_std_rad = 0.01;
  const TruthTrajectory truth = surface_truth();
  const auto msgs = generate_gps(cfg, truth, seconds(400), device_seed(11, "gps"));
  const double n = static_cast<double>(msgs.size());
  double sum = 0.0, sum2 = 0.0;
  for (const WireMessage& msg : msgs) {
    const auto hdt = nmea::decode_hdt(sentences(msg).at(3));
    const double yaw = units::rad_to_deg(euler_from_quat(truth.at(msg.t_valid).q_nb).yaw);
    const double e = deg_to_rad(std::remainder(*hdt->heading_deg - yaw, 360.0));
    sum += e;
    sum2 += e * e;
  }
  const double mean = sum / n, std = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 5.0 * 0.01 / std::sqrt(n));
  EXPECT_NEAR(std, 0.01, 0.05 * 0.01);  // 5 % = 6.3 standard errors at N = 4000
}

/// Surfacing time: the first time the depth is back at or above `max_depth`, found by a
/// 1 ms scan of truth after t_from [ns].
Duration surfacing_after(const TruthTrajectory& truth, double max_depth, Duration t_from) {
  bool was_deep = false;
  for (Duration t = t_from;; t += milliseconds(1)) {
    const bool deep = truth.at(t).p_n.z() > max_depth;
    if (was_deep && !deep) return t;
    was_deep = deep;
  }
}

TEST(GpsEmulatorExt, NoFixUntilReacquisitionHasElapsedAfterSurfacing) {
  GpsConfig cfg = all_sentences_config();
  cfg.rate_hz = 10.0;
  cfg.reacquisition = seconds(7);
  const TruthTrajectory truth = diving_truth();
  const Duration surfaced = surfacing_after(truth, cfg.max_depth_for_fix_m, Duration{0});
  const auto msgs = generate_gps(cfg, truth, truth.path_duration() + seconds(5), 1);
  ASSERT_GT(to_seconds(truth.path_duration()) + 5.0, to_seconds(surfaced) + 15.0);

  std::optional<Duration> first_fix_after_dive;
  bool dived = false;
  int waiting = 0;
  for (const WireMessage& msg : msgs) {
    const auto s = sentences(msg);
    ASSERT_EQ(s.size(), 5u);
    const auto gga = nmea::decode_gga(s[0]);
    const auto rmc = nmea::decode_rmc(s[1]);
    const auto vtg = nmea::decode_vtg(s[2]);
    const auto hdt = nmea::decode_hdt(s[3]);
    const auto zda = nmea::decode_zda(s[4]);
    ASSERT_TRUE(gga && rmc && vtg && hdt && zda);
    const bool deep = truth.at(msg.t_valid).p_n.z() > cfg.max_depth_for_fix_m;
    dived = dived || deep;
    const bool expect_fix = !deep && (!dived || msg.t_valid >= surfaced + cfg.reacquisition);
    EXPECT_EQ(gga->quality, expect_fix ? 1 : 0) << to_seconds(msg.t_valid);
    EXPECT_EQ(rmc->valid, expect_fix);
    EXPECT_EQ(hdt->heading_deg.has_value(), expect_fix);
    EXPECT_EQ(vtg->sog_kn.has_value(), expect_fix);
    EXPECT_EQ(vtg->mode, std::optional<char>(expect_fix ? 'A' : 'N'));
    EXPECT_EQ(zda->time.year, 2026) << "ZDA keeps running without a fix";
    if (!expect_fix) {
      EXPECT_FALSE(gga->lat_deg || gga->alt_msl_m || rmc->lat_deg || rmc->sog_kn);
      EXPECT_EQ(s[3].fields.at(0), "");
    }
    if (dived && !deep && !expect_fix) ++waiting;
    if (dived && gga->quality == 1 && !first_fix_after_dive) first_fix_after_dive = msg.t_valid;
  }
  ASSERT_TRUE(first_fix_after_dive.has_value());
  // The measured delay is the configured one, up to one epoch (0.1 s) and the 1 ms scan.
  const double delay_s = to_seconds(*first_fix_after_dive - surfaced);
  EXPECT_GE(delay_s, 7.0 - 1e-3);
  EXPECT_LT(delay_s, 7.1);
  EXPECT_GE(waiting, 69);  // 7 s at 10 Hz shallow without a fix
}

TEST(GpsEmulatorExt, ZeroReacquisitionFixesAsSoonAsShallow) {
  GpsConfig cfg = all_sentences_config();
  cfg.reacquisition = Duration{0};
  const TruthTrajectory truth = diving_truth();
  const auto msgs = generate_gps(cfg, truth, truth.path_duration(), 1);
  for (const WireMessage& msg : msgs) {
    const bool deep = truth.at(msg.t_valid).p_n.z() > cfg.max_depth_for_fix_m;
    EXPECT_EQ(nmea::decode_gga(sentences(msg).at(0))->quality, deep ? 0 : 1);
  }
}

}  // namespace
}  // namespace nav::emulators

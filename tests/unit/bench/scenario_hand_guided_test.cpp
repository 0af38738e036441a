// SPDX-License-Identifier: MIT
// vehicle.hand_guided and the triads' bias instability keys: read in SI, defaults, and refusals
// at their line.
#include <gtest/gtest.h>

#include <numbers>
#include <string>

#include "nav/bench/scenario.hpp"
#include "temp_file.hpp"

namespace nav::bench {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

std::string write_temp(const std::string& name, const std::string& text) {
  return testing::write_temp_file("navbench_hand_guided_test", name, text);
}

/// A small scenario with `vehicle_extra` lines after the path and `gyro` as the GX3's gyro
/// error map.
std::string scenario(const std::string& vehicle_extra, const std::string& gyro = "{}") {
  return "name: hand\nseed: 7\nduration: 10 s\ndatum: {lat: 36.38, lon: 127.36}\n"
         "vehicle:\n"
         "  path:\n"
         "    - {straight: 10 m, speed: 1 m/s}\n" +
         vehicle_extra +
         "  devices:\n"
         "    - {name: ahrs, type: microstrain-gx3-25, errors: {gyro: " + gyro + "}}\n"
         "dut:\n  command: [navd, --ahrs, \"{port:ahrs}\"]\n  trigger: ahrs\n";
}

TEST(HandGuidedScenario, ReadsEveryBandInSi) {
  const auto s = load_scenario(write_temp("all.yaml", scenario(
      "  hand_guided:\n"
      "    speed: {rms: 15 %, band: [0.02 Hz, 0.3 Hz]}\n"
      "    sway: {rms: 20 cm, band: [0.02 Hz, 0.2 Hz], components: 8}\n"
      "    heave: {rms: 0.05 m}\n"
      "    roll: {rms: 2 deg, band: [0.3 Hz, 0.8 Hz]}\n"
      "    pitch: {rms: 1 deg}\n"
      "    yaw: {rms: 0.5 deg}\n"
      "    shake: {rms: 0.3 m/s^2, band: [1.5 Hz, 2.5 Hz]}\n")));
  ASSERT_TRUE(s) << s.error().detail;
  ASSERT_TRUE(s->hand_guided);
  const auto& h = *s->hand_guided;
  EXPECT_DOUBLE_EQ(h.speed.rms, 0.15);
  EXPECT_EQ(h.speed.order, 1);
  EXPECT_DOUBLE_EQ(h.speed.f_lo_hz, 0.02);
  EXPECT_DOUBLE_EQ(h.speed.f_hi_hz, 0.3);
  EXPECT_DOUBLE_EQ(h.sway.rms, 0.2);
  EXPECT_EQ(h.sway.components, 8u);
  EXPECT_EQ(h.heave.components, 24u);  // default
  EXPECT_DOUBLE_EQ(h.heave.f_lo_hz, emulators::HandGuidedSpec{}.heave.f_lo_hz);
  EXPECT_NEAR(h.roll.rms, 2 * kDeg, 1e-15);
  EXPECT_NEAR(h.pitch.rms, 1 * kDeg, 1e-15);
  EXPECT_EQ(h.shake.order, 2);
  EXPECT_DOUBLE_EQ(h.shake.rms, 0.3);
  EXPECT_NE(s->hand_guided_location.find("all.yaml:9:"), std::string::npos)
      << s->hand_guided_location;
}

TEST(HandGuidedScenario, AbsentMeansThePathExactly) {
  const auto s = load_scenario(write_temp("none.yaml", scenario("")));
  ASSERT_TRUE(s) << s.error().detail;
  EXPECT_FALSE(s->hand_guided);
}

TEST(HandGuidedScenario, RefusesBadBandsAtTheirLine) {
  const auto check = [](const std::string& name, const std::string& extra,
                        const std::string& where, const std::string& what) {
    const auto s = load_scenario(write_temp(name, scenario(extra)));
    ASSERT_FALSE(s) << name;
    EXPECT_NE(s.error().detail.find(name + ":" + where), std::string::npos) << s.error().detail;
    EXPECT_NE(s.error().detail.find(what), std::string::npos) << s.error().detail;
  };
  check("reversed.yaml", "  hand_guided:\n    sway: {rms: 1 m, band: [2 Hz, 1 Hz]}\n", "9:",
        "upper edge");
  check("one_edge.yaml", "  hand_guided:\n    sway: {rms: 1 m, band: [2 Hz]}\n", "9:",
        "[low, high]");
  check("no_rms.yaml", "  hand_guided:\n    roll: {band: [1 Hz, 2 Hz]}\n", "9:", "rms");
  check("unit.yaml", "  hand_guided:\n    roll: {rms: 2 m}\n", "9:", "angle");
  check("negative.yaml", "  hand_guided:\n    heave: {rms: -1 m}\n", "9:", "heave");
  check("unknown.yaml", "  hand_guided:\n    surge: {rms: 1 m}\n", "9:", "surge");
  check("components.yaml", "  hand_guided:\n    yaw: {rms: 1 deg, components: 0}\n", "9:",
        "integer from 1");
}

TEST(TriadInstability, ReadsTheBiasInstabilityAndItsCorrelationTime) {
  const auto s = load_scenario(write_temp(
      "instability.yaml", scenario("", "{instability: 18 deg/h, correlation_time: 60 s}")));
  ASSERT_TRUE(s) << s.error().detail;
  const auto& g = s->devices.at(0).config<emulators::Gx3Config>();
  EXPECT_NEAR(g.gyro.random.instability_std, 18.0 / 3600.0 * kDeg, 1e-18);
  EXPECT_DOUBLE_EQ(g.gyro.random.instability_tau_s, 60.0);
  EXPECT_EQ(g.accel.random.instability_std, 0.0);  // none unless given

  const auto lonely = load_scenario(
      write_temp("lonely_tau.yaml", scenario("", "{correlation_time: 60 s}")));
  ASSERT_FALSE(lonely);
  EXPECT_NE(lonely.error().detail.find("needs an instability"), std::string::npos)
      << lonely.error().detail;
}

}  // namespace
}  // namespace nav::bench

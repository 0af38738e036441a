// SPDX-License-Identifier: MIT
// vehicle.sea: read in SI with its defaults, and refusals at their line and column (a bad
// height, period or gamma, another truth kind beside it, a depth segment or a start below the
// surface, an unknown key).
#include <gtest/gtest.h>

#include <numbers>
#include <string>

#include "nav/bench/runner.hpp"
#include "nav/bench/scenario.hpp"
#include "temp_file.hpp"

namespace nav::bench {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

std::string write_temp(const std::string& name, const std::string& text) {
  return testing::write_temp_file("navbench_sea_test", name, text);
}

/// A beacon with `vehicle_extra` lines before its path (line 6 on) and `segment` as its
/// second path item.
std::string scenario(const std::string& vehicle_extra,
                     const std::string& segment = "{arc: 90 deg, radius: 20 m, speed: 1 m/s}") {
  return "name: sea\nseed: 7\nduration: 10 s\ndatum: {lat: 35.1, lon: 129.04}\n"
         "vehicle:\n" +
         vehicle_extra +
         "  path:\n"
         "    - {straight: 10 m, speed: 1 m/s}\n"
         "    - " + segment + "\n"
         "  devices:\n"
         "    - {name: ahrs, type: microstrain-gx3-25}\n"
         "dut:\n  command: [navd, --ahrs, \"{port:ahrs}\"]\n  trigger: ahrs\n";
}

TEST(SeaScenario, ReadsP4sSeaInSi) {
  const auto s = load_scenario(write_temp("p4.yaml", scenario(
      "  sea: {significant_height: 0.6 m, peak_period: 5.3 s, from: 90 deg, gamma: 3.3,\n"
      "        components: 96, wind: {speed: 3.2 m/s, from: 67.5 deg}}\n")));
  ASSERT_TRUE(s) << s.error().detail;
  ASSERT_TRUE(s->sea);
  const auto& sea = *s->sea;
  EXPECT_DOUBLE_EQ(sea.spectrum.significant_height_m, 0.6);
  EXPECT_DOUBLE_EQ(sea.spectrum.peak_period_s, 5.3);
  EXPECT_DOUBLE_EQ(sea.spectrum.gamma, 3.3);
  EXPECT_NEAR(sea.from_rad, 90 * kDeg, 1e-15);
  EXPECT_EQ(sea.components, 96u);
  EXPECT_DOUBLE_EQ(sea.wind.speed_mps, 3.2);
  EXPECT_NEAR(sea.wind.from_rad, 67.5 * kDeg, 1e-15);
  EXPECT_DOUBLE_EQ(sea.wind.drift_factor, 0.03);  // default
  EXPECT_FALSE(sea.free_drift);
  EXPECT_NE(s->sea_location.find("p4.yaml:6:"), std::string::npos) << s->sea_location;
}

TEST(SeaScenario, PreflightBuildsTheCraftsTruth) {
  // The runner builds the sea-state truth around the path (the DUT: any program there is).
  std::string text = scenario(
      "  sea: {significant_height: 0.6 m, peak_period: 5.3 s, from: 90 deg,\n"
      "        wind: {speed: 3.2 m/s, from: 67.5 deg}}\n");
  text.replace(text.find("[navd,"), 6, "[/bin/true,");
  const auto s = preflight_scenario(write_temp("preflight.yaml", text));
  ASSERT_TRUE(s) << s.error().detail;
  EXPECT_TRUE(s->sea);
}

TEST(SeaScenario, DefaultsAndOptions) {
  const auto s = load_scenario(write_temp("min.yaml", scenario(
      "  sea:\n"
      "    significant_height: 1.2 m\n"
      "    peak_period: 7 s\n"
      "    from: -45 deg\n"
      "    wind: {speed: 5 m/s, from: 0 deg, drift_factor: 2.5 %}\n"
      "    free_drift: true\n")));
  ASSERT_TRUE(s) << s.error().detail;
  const auto& sea = *s->sea;
  EXPECT_DOUBLE_EQ(sea.spectrum.gamma, 3.3);
  EXPECT_EQ(sea.components, 96u);
  EXPECT_DOUBLE_EQ(sea.wind.drift_factor, 0.025);
  EXPECT_TRUE(sea.free_drift);
  const auto none = load_scenario(write_temp("none.yaml", scenario("")));
  ASSERT_TRUE(none) << none.error().detail;
  EXPECT_FALSE(none->sea);
}

TEST(SeaScenario, RefusesAtTheLineAndColumn) {
  const std::string p4 = "significant_height: 0.6 m, peak_period: 5.3 s, from: 90 deg";
  const struct {
    std::string text;
    std::string where;
    std::string what;
  } cases[] = {
      {scenario("  sea: {significant_height: -0.6 m, peak_period: 5.3 s, from: 90 deg}\n"),
       ":6:29: ", "length"},
      {scenario("  sea: {significant_height: 0.6 m, peak_period: 0 s, from: 90 deg}\n"),
       ":6:49: ", "duration"},
      // 2 pi 5 / (g 1.5^2) = 1.4: no such sea; 1000 m at 5.3 s neither.
      {scenario("  sea: {significant_height: 5 m, peak_period: 1.5 s, from: 90 deg}\n"),
       ":6:47: ", "is 1.4 steep"},
      {scenario("  sea: {significant_height: 1000 m, peak_period: 5.3 s, from: 90 deg}\n"),
       ":6:50: ", "seas stay below 1/10"},
      {scenario("  sea: {" + p4 + ", gamma: 8}\n"), ":6:77: ", "to 7"},
      {scenario("  sea: {" + p4 + ", components: 0}\n"), ":6:82: ", "integer from 1"},
      {scenario("  sea: {significant_height: 0.6 m, from: 90 deg}\n"), ":6:", "peak_period"},
      {scenario("  sea: {" + p4 + ", swell: 1 m}\n"), ":6:", "swell"},
      {scenario("  sea: {" + p4 + ", wind: {speed: -1 m/s, from: 0 deg}}\n"), ":6:84: ",
       "speed"},
      {scenario("  sea: {" + p4 + ", wind: {speed: 3 m/s, from: 0 deg, drift_factor: 20 %}}\n"),
       ":6:", "drift factor"},
      {scenario("  wall: {}\n  sea: {" + p4 + "}\n"), ":7:8: ", "vehicle.wall"},
      {scenario("  hand_guided: {heave: {rms: 1 cm}}\n  sea: {" + p4 + "}\n"), ":7:8: ",
       "vehicle.hand_guided (one truth kind at a time)"},
      {scenario("  motion: {roll: 2 deg}\n  sea: {" + p4 + "}\n"), ":7:8: ", "vehicle.motion"},
      {scenario("  start: {depth: 2 m}\n  sea: {" + p4 + "}\n"), ":7:8: ", "start.depth"},
      {scenario("  sea: {" + p4 + "}\n", "{depth: 2 m, rate: 0.1 m/s}"), ":9:7: ",
       "floats at the surface"},
  };
  for (const auto& c : cases) {
    const auto s = load_scenario(write_temp("bad.yaml", c.text));
    ASSERT_FALSE(s) << c.text;
    const std::string& detail = s.error().detail;
    EXPECT_NE(detail.find("bad.yaml" + c.where), std::string::npos) << detail;
    EXPECT_NE(detail.find(c.what), std::string::npos) << detail;
    EXPECT_EQ(detail.find('\n'), std::string::npos) << "one line: " << detail;
  }
}

}  // namespace
}  // namespace nav::bench

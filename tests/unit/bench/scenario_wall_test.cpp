// SPDX-License-Identifier: MIT
// vehicle.wall: read in SI with its defaults, and refusals at their line (a slope beyond
// vertical, a depth segment on a wall, an unknown key).
#include <gtest/gtest.h>

#include <numbers>
#include <string>

#include "nav/bench/scenario.hpp"
#include "temp_file.hpp"

namespace nav::bench {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

std::string write_temp(const std::string& name, const std::string& text) {
  return testing::write_temp_file("navbench_wall_test", name, text);
}

/// A crawler with `wall` as its vehicle.wall line and `segment` as its second path item.
std::string scenario(const std::string& wall,
                     const std::string& segment = "{arc: 90 deg, radius: 1 m, speed: 0.2 m/s}") {
  return "name: wall\nseed: 7\nduration: 10 s\ndatum: {lat: 36.38, lon: 127.36}\n"
         "vehicle:\n"
         "  start: {north: 2 m, east: 1 m, depth: 3 m, heading: 0 deg}\n" +
         wall +
         "  path:\n"
         "    - {straight: 2 m, speed: 0.2 m/s}\n"
         "    - " + segment + "\n"
         "  devices:\n"
         "    - {name: ahrs, type: microstrain-gx3-25}\n"
         "dut:\n  command: [navd, --ahrs, \"{port:ahrs}\"]\n  trigger: ahrs\n";
}

TEST(WallScenario, ReadsSlopeAndAzimuthInSiWithDefaults) {
  const auto s = load_scenario(write_temp("wall.yaml", scenario(
      "  wall: {slope: 45 deg, azimuth: 90 deg}\n")));
  ASSERT_TRUE(s) << s.error().detail;
  ASSERT_TRUE(s->wall);
  EXPECT_DOUBLE_EQ(s->wall->slope_rad, 45 * kDeg);
  EXPECT_DOUBLE_EQ(s->wall->azimuth_rad, 90 * kDeg);
  const auto d = load_scenario(write_temp("default.yaml", scenario("  wall: {}\n")));
  ASSERT_TRUE(d) << d.error().detail;
  EXPECT_DOUBLE_EQ(d->wall->slope_rad, 90 * kDeg);  // a vertical wall
  EXPECT_DOUBLE_EQ(d->wall->azimuth_rad, 0.0);
  const auto none = load_scenario(write_temp("none.yaml", scenario("")));
  ASSERT_TRUE(none);
  EXPECT_FALSE(none->wall);
}

TEST(WallScenario, RefusesWhatCannotBeOnAWall) {
  const struct {
    std::string text;
    std::string expected;
  } cases[] = {
      {scenario("  wall: {slope: 100 deg}\n"), ":7:17: "},
      {scenario("  wall: {slope: 100 deg}\n"), "from 0 deg (the floor) to 90 deg"},
      {scenario("  wall: {}\n", "{depth: 2 m, rate: 0.1 m/s}"), ":10:7: "},
      {scenario("  wall: {}\n", "{depth: 2 m, rate: 0.1 m/s}"), "straight, arc and turn"},
      {scenario("  wall: {tilt: 3 deg}\n"), "tilt"},
  };
  for (const auto& c : cases) {
    const auto s = load_scenario(write_temp("bad.yaml", c.text));
    ASSERT_FALSE(s) << c.text;
    EXPECT_NE(s.error().detail.find(c.expected), std::string::npos) << s.error().detail;
  }
}

}  // namespace
}  // namespace nav::bench

// SPDX-License-Identifier: MIT
// The `nmea0183-gps` device's errors.correlated: read in SI, time required, refusals at their
// line.
#include <gtest/gtest.h>

#include <string>

#include "nav/bench/scenario.hpp"
#include "nav/emulators/device.hpp"
#include "temp_file.hpp"

namespace nav::bench {
namespace {

std::string scenario(const std::string& errors) {
  return "name: gps-wander\nseed: 1\nduration: 10 s\ndatum: {lat: 35.1, lon: 129.04}\n"
         "vehicle:\n  path:\n    - {straight: 10 m, speed: 1 m/s}\n  devices:\n"
         "    - {name: ahrs, type: microstrain-gx3-25}\n"
         "    - {name: gps, type: nmea0183-gps, errors: " + errors + "}\n"
         "dut:\n  command: [navd, --ahrs, \"{port:ahrs}\"]\n  trigger: ahrs\n";
}

Result<Scenario> load(const std::string& errors) {
  return load_scenario(
      testing::write_temp_file("navbench_device_gps_test", "gps.yaml", scenario(errors)));
}

TEST(DeviceGps, CorrelatedErrorIsReadInSi) {
  const auto s = load("{horizontal: 0.5 m, correlated: {horizontal: 2 m, vertical: 300 cm, "
                      "time: 1 min}}");
  ASSERT_TRUE(s) << s.error().detail;
  const auto& c = s->devices[1].config<emulators::GpsConfig>();
  EXPECT_DOUBLE_EQ(c.horizontal_std_m, 0.5);
  EXPECT_DOUBLE_EQ(c.correlated_horizontal_std_m, 2.0);
  EXPECT_DOUBLE_EQ(c.correlated_vertical_std_m, 3.0);
  EXPECT_DOUBLE_EQ(c.correlation_time_s, 60.0);
  const auto none = load("{horizontal: 0.5 m}");
  ASSERT_TRUE(none) << none.error().detail;
  EXPECT_DOUBLE_EQ(none->devices[1].config<emulators::GpsConfig>().correlated_horizontal_std_m,
                   0.0);
}

TEST(DeviceGps, CorrelatedErrorRefusals) {
  const struct {
    const char* errors;
    const char* says;
  } bad[] = {{"{correlated: {horizontal: 2 m}}", "missing required key 'time'"},
             {"{correlated: {horizontal: 2 m, time: 0 s}}", "correlated.time"},
             {"{correlated: {horizontal: -1 m, time: 10 s}}", "correlated.horizontal"},
             {"{correlated: {sigma: 1 m, time: 10 s}}", "sigma"}};
  for (const auto& b : bad) {
    const auto s = load(b.errors);
    ASSERT_FALSE(s) << b.errors;
    EXPECT_NE(s.error().detail.find(b.says), std::string::npos) << s.error().detail;
    EXPECT_NE(s.error().detail.find("gps.yaml:10:"), std::string::npos) << s.error().detail;
  }
}

}  // namespace
}  // namespace nav::bench

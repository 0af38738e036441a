// SPDX-License-Identifier: MIT
// The `beacon-ins` device (paper P4's beacon): its keys read in SI, its stream decodes with
// the timer as trigger tag, refusals at their line, and `navbench decode --protocol beacon-ins`.
#include <gtest/gtest.h>

#include <string>

#include "nav/bench/decode.hpp"
#include "nav/bench/scenario.hpp"
#include "nav/emulators/beacon_ins_emulator.hpp"
#include "nav/protocols/beacon_ins.hpp"
#include "temp_file.hpp"

namespace nav::bench {
namespace {

std::string scenario(const std::string& beacon) {
  return "name: beacon\nseed: 1\nduration: 2 s\ndatum: {lat: 35.1, lon: 129.04}\n"
         "vehicle:\n  path:\n    - {straight: 10 m, speed: 1 m/s}\n  devices:\n"
         "    - {name: ins, type: beacon-ins" + beacon + "}\n"
         "dut:\n  command: [navd, \"{port:ins}\"]\n  trigger: ins\n";
}

Result<Scenario> load(const std::string& beacon) {
  return load_scenario(testing::write_temp_file("navbench_device_beacon_ins_test", "beacon.yaml",
                                                scenario(beacon)));
}

TEST(DeviceBeaconIns, KeysAreReadInSi) {
  const auto s = load(", rate: 25 Hz, timer_start: 7, errors: {accel: {white: 2 mg}, "
                      "gyro: {bias: 0.5 deg/s}, compass: {white: 0.1 uT, hard_iron: "
                      "{x: 1 uT, y: 0 uT, z: 0 uT}}}, drag: {water_area: 1500 cm^2, "
                      "air_coefficient: 0.9}, thruster_field: {x: 0 uT, y: 0.4 uT, z: 0 uT, "
                      "at: 20 N}, mag_field: {north: 30 uT, east: 1 uT, down: 45 uT}");
  ASSERT_TRUE(s) << s.error().detail;
  const auto& c = s->devices[0].config<emulators::BeaconInsConfig>();
  EXPECT_DOUBLE_EQ(c.rate_hz, 25.0);
  EXPECT_EQ(c.timer_start_ticks, 7u);
  EXPECT_NEAR(c.accel.random.white_std, 2e-3 * 9.80665, 1e-12);
  EXPECT_NEAR(c.gyro.random.bias, 0.5 * 3.141592653589793 / 180.0, 1e-15);
  EXPECT_DOUBLE_EQ(c.compass.random.white_std, 0.1e-6);
  EXPECT_DOUBLE_EQ(c.iron.hard_iron_T.x(), 1e-6);
  EXPECT_DOUBLE_EQ(c.drag.water_area_m2, 0.15);
  EXPECT_DOUBLE_EQ(c.drag.air_coefficient, 0.9);
  EXPECT_DOUBLE_EQ(c.drag.air_area_m2, 0.3);  // default kept
  EXPECT_DOUBLE_EQ(c.thruster_field_T_per_N.y(), 0.4e-6 / 20.0);
  EXPECT_DOUBLE_EQ(c.mag_field_n.y(), 1e-6);
  EXPECT_EQ(s->devices[0].baud, 115200);
}

TEST(DeviceBeaconIns, Refusals) {
  const struct {
    const char* keys;
    const char* says;
  } bad[] = {{", thruster_field: {x: 1 uT, y: 0 uT, z: 0 uT}", "missing required key 'at'"},
             {", thruster_field: {x: 1 uT, y: 0 uT, z: 0 uT, at: 0 N}", "at"},
             {", drag: {water_area: 2 m}", "'m' is a length unit"},
             {", drag: {air_coefficient: -1}", "air_coefficient"},
             {", mag_field: {north: 0 uT, east: 0 uT, down: 45 uT}", "horizontal part"},
             {", errors: {mag: {white: 1 uT}}", "mag"}};
  for (const auto& b : bad) {
    const auto s = load(b.keys);
    ASSERT_FALSE(s) << b.keys;
    EXPECT_NE(s.error().detail.find(b.says), std::string::npos) << s.error().detail;
    EXPECT_NE(s.error().detail.find("beacon.yaml:9:"), std::string::npos) << s.error().detail;
  }
}

TEST(DeviceBeaconIns, DecodeCommandReadsItsFrames) {
  protocols::beacon_ins::Sample a;
  a.sequence = 1;
  a.heading_rad = 1.0;
  protocols::Bytes bytes = protocols::beacon_ins::encode(a);
  bytes.push_back(0x00);  // garbage between frames
  a.sequence = 2;
  const protocols::Bytes b = protocols::beacon_ins::encode(a);
  bytes.insert(bytes.end(), b.begin(), b.end());
  const ProtocolDecoder* d = find_decoder("beacon-ins");
  ASSERT_NE(d, nullptr);
  std::vector<std::string> records;
  const DecodeCounts n =
      decode_stream(*d, bytes, [&](const auto& j) { records.push_back(j.dump()); });
  EXPECT_EQ(n.messages, 2u);
  EXPECT_EQ(n.errors, 1u);
  ASSERT_EQ(records.size(), 3u);  // frame, the garbage byte, frame
  EXPECT_NE(records[0].find("\"type\":\"beacon_ins\""), std::string::npos) << records[0];
  EXPECT_NE(records[2].find("\"sequence\":2"), std::string::npos) << records[2];
}

}  // namespace
}  // namespace nav::bench

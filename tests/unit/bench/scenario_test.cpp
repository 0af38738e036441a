// SPDX-License-Identifier: MIT
// Scenario loading: the smoke scenario in SI, defaults, and every malformed scenario of
// tests/integration/malformed/ refused at the line its "# line:" comment names.
#include "nav/bench/scenario.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace nav::bench {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using emulators::Segment;

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
constexpr double kMg = 9.80665e-3;

const std::string kSourceDir = NAV_SOURCE_DIR;

/// Writes text to a fresh file under the test temp dir and returns its path.
std::string write_temp(const std::string& name, const std::string& text) {
  const fs::path dir = fs::path(::testing::TempDir()) / "navbench_scenario_test";
  fs::create_directories(dir);
  const fs::path p = dir / name;
  std::ofstream(p) << text;
  return p.string();
}

/// A small valid scenario; tests append or replace lines.
const std::string kMinimal = R"(name: minimal
seed: 7
duration: 10 s
datum: {lat: 36.38, lon: 127.36}
vehicle:
  path:
    - {straight: 10 m, speed: 1 m/s}
  devices:
    - {name: ahrs, type: microstrain-gx3-25}
dut:
  command: [navd, --ahrs, "{port:ahrs}"]
  trigger: ahrs
)";

TEST(LoadScenario, SmokeScenarioInSi) {
  const std::string path = kSourceDir + "/scenarios/smoke.yaml";
  const auto s = load_scenario(path);
  ASSERT_TRUE(s) << s.error().detail;
  EXPECT_EQ(s->file, path);
  EXPECT_EQ(s->name, "smoke");
  EXPECT_FALSE(s->description.empty());
  EXPECT_EQ(s->seed, 42u);
  EXPECT_EQ(s->duration, 60s);
  EXPECT_EQ(s->mode, TimeMode::kRealtime);
  EXPECT_NEAR(s->datum.lat_rad, 36.3833 * kDeg, 1e-12);
  EXPECT_NEAR(s->datum.lon_rad, 127.36 * kDeg, 1e-12);
  EXPECT_EQ(s->datum.alt_m, 0.0);
  EXPECT_EQ(s->truth_rate_hz, 50.0);
  EXPECT_EQ(s->lateness_budget_p99, 5ms);
  EXPECT_EQ(s->vehicle_name, "uuv");

  const auto& t = s->trajectory;
  EXPECT_EQ(t.start_p_n, Vec3::Zero());
  EXPECT_EQ(t.start_yaw_rad, 0.0);
  EXPECT_DOUBLE_EQ(t.max_accel_mps2, 0.5);
  EXPECT_DOUBLE_EQ(t.arc_transition_m, 1.0);
  EXPECT_NEAR(t.gravity_mps2, 9.798, 0.001);  // normal gravity at 36.4 deg N
  EXPECT_NEAR(t.motion.roll_amplitude_rad, 2 * kDeg, 1e-15);
  EXPECT_NEAR(t.motion.pitch_amplitude_rad, 1 * kDeg, 1e-15);
  EXPECT_DOUBLE_EQ(t.motion.period_s, 6.0);
  ASSERT_EQ(t.segments.size(), 5u);
  EXPECT_EQ(t.segments[0].kind, Segment::Kind::kStraight);
  EXPECT_DOUBLE_EQ(t.segments[0].length_m, 10.0);
  EXPECT_DOUBLE_EQ(t.segments[0].speed_mps, 1.0);
  EXPECT_EQ(t.segments[1].kind, Segment::Kind::kArc);
  EXPECT_NEAR(t.segments[1].angle_rad, kPi / 2, 1e-15);
  EXPECT_DOUBLE_EQ(t.segments[1].radius_m, 8.0);
  EXPECT_NEAR(t.segments[1].length_m, 8.0 * kPi / 2, 1e-12);
  EXPECT_EQ(t.segments[2].kind, Segment::Kind::kStraight);
  EXPECT_DOUBLE_EQ(t.segments[2].length_m, 6.0);
  EXPECT_EQ(t.segments[3].kind, Segment::Kind::kTurn);
  EXPECT_NEAR(t.segments[3].angle_rad, kPi / 2, 1e-15);
  EXPECT_NEAR(t.segments[3].rate_radps, 20 * kDeg, 1e-15);
  EXPECT_EQ(t.segments[4].kind, Segment::Kind::kStraight);
  ASSERT_EQ(s->segment_locations.size(), 5u);
  EXPECT_TRUE(s->segment_locations[0].starts_with(path + ":")) << s->segment_locations[0];

  ASSERT_EQ(s->devices.size(), 2u);
  const DeviceSpec& ahrs = s->devices[0];
  EXPECT_EQ(ahrs.name, "ahrs");
  EXPECT_EQ(ahrs.type, DeviceSpec::Type::kMicrostrainGx3);
  EXPECT_EQ(ahrs.port, "pty");
  EXPECT_EQ(ahrs.baud, 115200);
  EXPECT_EQ(ahrs.gx3.rate_hz, 100.0);
  EXPECT_EQ(ahrs.gx3.latency, 0ns);
  EXPECT_NEAR(ahrs.gx3.accel.white_std, 0.5 * kMg, 1e-15);
  EXPECT_NEAR(ahrs.gx3.accel.bias, 2 * kMg, 1e-15);
  EXPECT_EQ(ahrs.gx3.accel.bias_walk_std, 0.0);
  EXPECT_NEAR(ahrs.gx3.gyro.white_std, 0.03 * kDeg, 1e-15);
  EXPECT_NEAR(ahrs.gx3.gyro.bias, 0.05 * kDeg, 1e-15);
  EXPECT_NEAR(ahrs.gx3.mag.white_std, 0.2e-6, 1e-18);
  EXPECT_NEAR(ahrs.gx3.mag_field_n.x(), 20e-6, 1e-18);
  EXPECT_NEAR(ahrs.gx3.mag_field_n.z(), 40e-6, 1e-18);

  const DeviceSpec& gps = s->devices[1];
  EXPECT_EQ(gps.name, "gps");
  EXPECT_EQ(gps.type, DeviceSpec::Type::kNmeaGps);
  EXPECT_EQ(gps.baud, 9600);
  EXPECT_EQ(gps.gps.rate_hz, 1.0);
  EXPECT_EQ(gps.gps.latency, 50ms);
  EXPECT_DOUBLE_EQ(gps.gps.horizontal_std_m, 0.5);
  EXPECT_DOUBLE_EQ(gps.gps.vertical_std_m, 1.0);
  EXPECT_DOUBLE_EQ(gps.gps.velocity_std_mps, 0.05);
  EXPECT_EQ(gps.gps.talker, "GP");
  EXPECT_DOUBLE_EQ(gps.gps.utc_start_unix_s, 1780315200.0);
  EXPECT_EQ(gps.gps.datum_lat_rad, s->datum.lat_rad);
  EXPECT_EQ(gps.gps.datum_lon_rad, s->datum.lon_rad);
  EXPECT_EQ(gps.gps.datum_alt_m, s->datum.alt_m);

  const std::vector<std::string> argv{"navd",       "--ahrs",   "{port:ahrs}",  "--gps",
                                      "{port:gps}", "--output", "{port:output}"};
  EXPECT_EQ(s->dut.command, argv);
  EXPECT_EQ(s->dut.output_port, "pty");
  EXPECT_EQ(s->dut.output_baud, 115200);
  EXPECT_EQ(s->dut.trigger, "ahrs");
  EXPECT_EQ(s->dut.startup, 500ms);
  EXPECT_EQ(s->dut.watchdog, 2s);

  using Kind = CheckSpec::Kind;
  ASSERT_EQ(s->checks.size(), 6u);
  EXPECT_EQ(s->checks[0].kind, Kind::kHorizontalError);
  EXPECT_EQ(s->checks[0].name, "horizontal_error");
  EXPECT_DOUBLE_EQ(s->checks[0].max, 3.0);
  EXPECT_EQ(s->checks[0].after, 5s);
  EXPECT_EQ(s->checks[1].kind, Kind::kVerticalError);
  EXPECT_EQ(s->checks[2].kind, Kind::kAttitudeError);
  EXPECT_NEAR(s->checks[2].max, 3 * kDeg, 1e-15);
  EXPECT_EQ(s->checks[2].after, 2s);
  EXPECT_EQ(s->checks[3].kind, Kind::kEndpointError);
  EXPECT_EQ(s->checks[4].kind, Kind::kDeadline);
  EXPECT_EQ(s->checks[4].input, "ahrs");
  EXPECT_DOUBLE_EQ(s->checks[4].max, 0.020);
  EXPECT_EQ(s->checks[4].max_misses, 3);
  EXPECT_EQ(s->checks[5].kind, Kind::kDutAlive);
}

TEST(LoadScenario, DefaultsOfAMinimalScenario) {
  const auto s = load_scenario(write_temp("minimal.yaml", kMinimal));
  ASSERT_TRUE(s) << s.error().detail;
  EXPECT_EQ(s->mode, TimeMode::kRealtime);
  EXPECT_EQ(s->vehicle_name, "vehicle");
  EXPECT_EQ(s->truth_rate_hz, 50.0);
  EXPECT_EQ(s->lateness_budget_p99, 5ms);
  EXPECT_EQ(s->datum.alt_m, 0.0);
  EXPECT_DOUBLE_EQ(s->trajectory.max_accel_mps2, 0.2);
  EXPECT_DOUBLE_EQ(s->trajectory.motion.roll_amplitude_rad, 0.0);
  const DeviceSpec& d = s->devices.at(0);
  EXPECT_EQ(d.port, "pty");
  EXPECT_EQ(d.baud, 115200);
  EXPECT_EQ(d.gx3.rate_hz, 100.0);
  EXPECT_EQ(d.gx3.latency, 0ns);
  EXPECT_EQ(d.gx3.timer_start_ticks, 0u);
  EXPECT_FALSE(d.gx3_continuous);  // waits for the DUT's start command, like the device
  EXPECT_EQ(d.gx3.accel.white_std, 0.0);
  EXPECT_EQ(s->dut.output_port, "pty");
  EXPECT_EQ(s->dut.startup, 500ms);
  EXPECT_EQ(s->dut.watchdog, 2s);
  EXPECT_TRUE(s->checks.empty());
}

TEST(LoadScenario, Gx3ContinuousKey) {
  for (const auto& [value, expected] :
       std::vector<std::pair<std::string, bool>>{{"true", true}, {"false", false}}) {
    std::string text = kMinimal;
    const auto at = text.find("type: microstrain-gx3-25");
    ASSERT_NE(at, std::string::npos);
    text.insert(at, "continuous: " + value + ", ");
    const auto s = load_scenario(write_temp("gx3-continuous.yaml", text));
    ASSERT_TRUE(s) << s.error().detail;
    EXPECT_EQ(s->devices.at(0).gx3_continuous, expected) << value;
  }
  std::string text = kMinimal;
  text.insert(text.find("type: microstrain-gx3-25"), "continuous: maybe, ");
  const auto bad = load_scenario(write_temp("gx3-continuous-bad.yaml", text));
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().detail.find("gx3-continuous-bad.yaml:"), std::string::npos)
      << bad.error().detail;
}

TEST(LoadScenario, OptionalFieldsAndAlternativeSpellings) {
  std::string text = kMinimal;
  text.replace(text.find("datum:"), text.find('\n', text.find("datum:")) - text.find("datum:"),
               "datum: {lat: '-0.5 rad', lon: -70.25 deg, alt: 12 m}");
  text.replace(text.find("    - {straight"), text.find("  devices:") - text.find("    - {straight"),
               "    - {straight: 10 m, speed: 2 kn}\n"
               "    - {depth: 2 m, rate: 0.2 m/s}\n"
               "    - {turn: -180 deg, rate: 0.2 rad/s}\n"
               "    - {depth: -1.5 m, rate: 0.1 m/s, speed: 0.5 m/s}\n"
               "    - {arc: -45 deg, radius: 0.02 km, speed: 1 m/s}\n");
  text.replace(text.find("    - {name: ahrs"), text.find("dut:") - text.find("    - {name: ahrs"),
               "    - {name: ahrs, type: microstrain-gx3-25, timer_start: 4294967295,\n"
               "       rate: 50 Hz, baud: 38400, latency: 2 ms,\n"
               "       errors: {accel: {bias_walk: 0.05 mg/sqrt(s)},\n"
               "                gyro: {bias_walk: 0.001 deg/s/sqrt(s), bias: -0.1 deg/s},\n"
               "                mag: {white: 2 mG, bias_walk: 0.01 uT/sqrt(s)}}}\n"
               "    - {type: nmea0183-gps, port: /dev/ttyUSB1, rate: 5 Hz, baud: 9600,\n"
               "       talker: GN, utc_start: '2024-02-29T23:59:59.5Z', max_depth_for_fix: 1 m}\n");
  text +=
      "mode: lockstep\n"
      "truth_rate: 100 Hz\n"
      "bench: {lateness_budget_p99: 500 us}\n"
      "checks:\n"
      "  - {kind: horizontal_error, max: 1 m, per_distance: 2 %, after: 0.1 min}\n"
      "  - {kind: vertical_error, name: depth_error, max: 50 cm, per_distance: 0.01}\n"
      "  - {kind: deadline, input: ahrs, max_latency: 10 ms}\n";
  const auto s = load_scenario(write_temp("optional.yaml", text));
  ASSERT_TRUE(s) << s.error().detail;
  EXPECT_EQ(s->mode, TimeMode::kLockstep);
  EXPECT_DOUBLE_EQ(s->datum.lat_rad, -0.5);
  EXPECT_NEAR(s->datum.lon_rad, -70.25 * kDeg, 1e-15);
  EXPECT_EQ(s->datum.alt_m, 12.0);
  EXPECT_EQ(s->truth_rate_hz, 100.0);
  EXPECT_EQ(s->lateness_budget_p99, 500us);

  const auto& seg = s->trajectory.segments;
  ASSERT_EQ(seg.size(), 5u);
  EXPECT_NEAR(seg[0].speed_mps, 2 * 1852.0 / 3600.0, 1e-12);
  EXPECT_EQ(seg[1].kind, Segment::Kind::kDepth);
  EXPECT_DOUBLE_EQ(seg[1].depth_change_m, 2.0);
  EXPECT_NEAR(seg[1].speed_mps, seg[0].speed_mps, 1e-15);  // keeps the current speed
  EXPECT_NEAR(seg[2].angle_rad, -kPi, 1e-15);
  EXPECT_DOUBLE_EQ(seg[2].rate_radps, 0.2);
  EXPECT_DOUBLE_EQ(seg[3].depth_rate_mps, 0.1);
  EXPECT_DOUBLE_EQ(seg[3].speed_mps, 0.5);
  EXPECT_NEAR(seg[4].length_m, 20.0 * kPi / 4, 1e-12);

  const DeviceSpec& ahrs = s->devices.at(0);
  EXPECT_EQ(ahrs.gx3.timer_start_ticks, 4294967295u);
  EXPECT_EQ(ahrs.gx3.rate_hz, 50.0);
  EXPECT_EQ(ahrs.baud, 38400);
  EXPECT_EQ(ahrs.gx3.latency, 2ms);
  EXPECT_NEAR(ahrs.gx3.accel.bias_walk_std, 0.05 * kMg, 1e-15);
  EXPECT_NEAR(ahrs.gx3.gyro.bias_walk_std, 0.001 * kDeg, 1e-18);
  EXPECT_NEAR(ahrs.gx3.gyro.bias, -0.1 * kDeg, 1e-15);
  EXPECT_NEAR(ahrs.gx3.mag.white_std, 2e-7, 1e-20);
  EXPECT_NEAR(ahrs.gx3.mag.bias_walk_std, 1e-8, 1e-20);
  const DeviceSpec& gps = s->devices.at(1);
  EXPECT_EQ(gps.name, "nmea0183-gps");  // the type names an unnamed device
  EXPECT_EQ(gps.port, "/dev/ttyUSB1");
  EXPECT_EQ(gps.gps.rate_hz, 5.0);
  EXPECT_EQ(gps.gps.latency, 50ms);
  EXPECT_EQ(gps.gps.talker, "GN");
  EXPECT_DOUBLE_EQ(gps.gps.utc_start_unix_s, 1709251199.5);
  EXPECT_DOUBLE_EQ(gps.gps.max_depth_for_fix_m, 1.0);
  EXPECT_DOUBLE_EQ(gps.gps.datum_alt_m, 12.0);

  ASSERT_EQ(s->checks.size(), 3u);
  EXPECT_DOUBLE_EQ(s->checks[0].max_per_distance, 0.02);
  EXPECT_EQ(s->checks[0].after, 6s);
  EXPECT_EQ(s->checks[1].name, "depth_error");
  EXPECT_DOUBLE_EQ(s->checks[1].max, 0.5);
  EXPECT_DOUBLE_EQ(s->checks[1].max_per_distance, 0.01);
  EXPECT_EQ(s->checks[2].max_misses, 0);
}

TEST(LoadScenario, NewDeviceTypesAndFaultsInSi) {
  std::string text = kMinimal;
  text.replace(text.find("  path:"), 0, "  seabed: 15 m\n");
  text.replace(text.find("dut:"), 0,
               "    - name: gps\n"
               "      type: nmea0183-gps\n"
               "      sentences: [GGA, RMC, VTG, HDT, ZDA]\n"
               "      reacquisition: 5 s\n"
               "      errors: {heading: 0.5 deg}\n"
               "      faults:\n"
               "        - {kind: checksum, from: 1 s, to: 2 s}\n"
               "        - {kind: delayed, from: 2 s, to: 3 s, delay: 200 ms}\n"
               "        - {kind: slow, from: 3 s, to: 10 s, factor: 4}\n"
               "        - {kind: byte_loss, from: 0 s, to: 1 s}\n"
               "        - {kind: intermittent, from: 4 s, to: 5 s, probability: 30 %}\n"
               "    - {name: dvl1, type: dvl, protocol: navquest-nq1}\n"
               "    - name: dvl2\n"
               "      type: dvl\n"
               "      protocol: rdi-pd6\n"
               "      rate: 8 Hz\n"
               "      latency: 20 ms\n"
               "      beam_angle: 30 deg\n"
               "      max_altitude: 80 m\n"
               "      blanking: 0.5 m\n"
               "      errors: {velocity: 0.002 m/s, scale: -0.5 %}\n"
               "      beam_dropout: 0.1\n"
               "      sound_speed: 1480 m/s\n"
               "    - name: imu\n"
               "      type: ebimu-9dof\n"
               "      output: quaternion\n"
               "      gyro: true\n"
               "      accel: false\n"
               "      rate: 50 Hz\n"
               "      errors: {attitude: 0.1 deg, heading_bias: -2 deg,\n"
               "               gyro: {white: 0.01 deg/s}, accel: {bias: 1 mg}}\n"
               "    - name: usbl\n"
               "      type: evologics-usbl\n"
               "      transceiver: {north: 10 m, east: -5 m, depth: 2 m, heading: 90 deg}\n"
               "      sound_speed: 1490 m/s\n"
               "      errors: {range: 0.1 m, range_per_distance: 0.5 %, angle: 0.5 deg}\n"
               "      outliers: {probability: 0.05, std: 10 m}\n"
               "      dropout: 10 %\n"
               "      angles_only: true\n"
               "      processing: 150 ms\n");
  const auto s = load_scenario(write_temp("new_devices.yaml", text));
  ASSERT_TRUE(s) << s.error().detail;
  ASSERT_EQ(s->devices.size(), 6u);
  ASSERT_TRUE(s->seabed_depth_m);
  EXPECT_EQ(*s->seabed_depth_m, 15.0);
  EXPECT_TRUE(s->devices[0].faults.empty());

  const DeviceSpec& gps = s->devices[1];
  EXPECT_TRUE(gps.gps.vtg && gps.gps.hdt && gps.gps.zda);
  EXPECT_EQ(gps.gps.reacquisition, 5s);
  EXPECT_NEAR(gps.gps.heading_std_rad, 0.5 * kDeg, 1e-15);
  using FK = emulators::FaultSpec::Kind;
  ASSERT_EQ(gps.faults.size(), 5u);
  EXPECT_EQ(gps.faults[0].kind, FK::kChecksum);
  EXPECT_EQ(gps.faults[0].start, 1s);
  EXPECT_EQ(gps.faults[0].end, 2s);
  EXPECT_EQ(gps.faults[0].probability, 1.0);  // default for checksum
  EXPECT_EQ(gps.faults[1].kind, FK::kDelayed);
  EXPECT_EQ(gps.faults[1].delay, 200ms);
  EXPECT_EQ(gps.faults[2].kind, FK::kSlow);
  EXPECT_EQ(gps.faults[2].factor, 4.0);
  EXPECT_EQ(gps.faults[3].kind, FK::kByteLoss);
  EXPECT_EQ(gps.faults[3].start, 0s);
  EXPECT_EQ(gps.faults[3].probability, 0.05);
  EXPECT_EQ(gps.faults[4].kind, FK::kIntermittent);
  EXPECT_DOUBLE_EQ(gps.faults[4].probability, 0.3);

  const DeviceSpec& dvl1 = s->devices[2];  // defaults
  EXPECT_EQ(dvl1.type, DeviceSpec::Type::kDvl);
  EXPECT_EQ(dvl1.dvl.protocol, emulators::DvlProtocol::kNavQuestNq1);
  EXPECT_EQ(dvl1.baud, 115200);
  EXPECT_EQ(dvl1.dvl.rate_hz, 5.0);
  EXPECT_EQ(dvl1.dvl.latency, 0ns);
  EXPECT_EQ(dvl1.dvl.seabed_depth_m, 15.0);
  EXPECT_EQ(dvl1.dvl.max_altitude_m, 50.0);
  const DeviceSpec& dvl2 = s->devices[3];
  EXPECT_EQ(dvl2.dvl.protocol, emulators::DvlProtocol::kRdiPd6);
  EXPECT_EQ(dvl2.dvl.rate_hz, 8.0);
  EXPECT_EQ(dvl2.dvl.latency, 20ms);
  EXPECT_NEAR(dvl2.dvl.beam_angle_rad, 30 * kDeg, 1e-15);
  EXPECT_EQ(dvl2.dvl.max_altitude_m, 80.0);
  EXPECT_EQ(dvl2.dvl.blanking_m, 0.5);
  EXPECT_NEAR(dvl2.dvl.velocity_std_mps, 0.002, 1e-15);
  EXPECT_DOUBLE_EQ(dvl2.dvl.scale_factor, -0.005);
  EXPECT_DOUBLE_EQ(dvl2.dvl.beam_dropout_probability, 0.1);
  EXPECT_EQ(dvl2.dvl.sound_speed_mps, 1480.0);

  const DeviceSpec& imu = s->devices[4];
  EXPECT_EQ(imu.type, DeviceSpec::Type::kEbimu);
  EXPECT_EQ(imu.baud, 115200);
  EXPECT_EQ(imu.ebimu.rate_hz, 50.0);
  EXPECT_TRUE(imu.ebimu.quaternion);
  EXPECT_TRUE(imu.ebimu.gyro);
  EXPECT_FALSE(imu.ebimu.accel);
  EXPECT_NEAR(imu.ebimu.attitude_std_rad, 0.1 * kDeg, 1e-15);
  EXPECT_NEAR(imu.ebimu.attitude_bias_rad, -2 * kDeg, 1e-15);
  EXPECT_NEAR(imu.ebimu.gyro_errors.white_std, 0.01 * kDeg, 1e-15);
  EXPECT_NEAR(imu.ebimu.accel_errors.bias, kMg, 1e-15);

  const DeviceSpec& usbl = s->devices[5];
  EXPECT_EQ(usbl.type, DeviceSpec::Type::kEvologicsUsbl);
  EXPECT_EQ(usbl.baud, 19200);
  EXPECT_EQ(usbl.usbl.rate_hz, 1.0);
  EXPECT_EQ(usbl.usbl.transceiver_p_n, Vec3(10.0, -5.0, 2.0));
  EXPECT_NEAR(usbl.usbl.transceiver_yaw_rad, kPi / 2, 1e-15);
  EXPECT_EQ(usbl.usbl.sound_speed_mps, 1490.0);
  EXPECT_EQ(usbl.usbl.range_std_m, 0.1);
  EXPECT_DOUBLE_EQ(usbl.usbl.range_std_fraction, 0.005);
  EXPECT_NEAR(usbl.usbl.angle_std_rad, 0.5 * kDeg, 1e-15);
  EXPECT_DOUBLE_EQ(usbl.usbl.outlier_probability, 0.05);
  EXPECT_EQ(usbl.usbl.outlier_std_m, 10.0);
  EXPECT_DOUBLE_EQ(usbl.usbl.dropout_probability, 0.1);
  EXPECT_TRUE(usbl.usbl.angles_only);
  EXPECT_EQ(usbl.usbl.processing, 150ms);

  EXPECT_STREQ(device_type_name(DeviceSpec::Type::kDvl), "dvl");
  EXPECT_STREQ(device_type_name(DeviceSpec::Type::kEbimu), "ebimu-9dof");
  EXPECT_STREQ(device_type_name(DeviceSpec::Type::kEvologicsUsbl), "evologics-usbl");
}

TEST(LoadScenario, GpsDefaultsToGgaAndRmc) {
  std::string text = kMinimal;
  text.replace(text.find("dut:"), 0, "    - {name: gps, type: nmea0183-gps}\n");
  const auto s = load_scenario(write_temp("gps_default.yaml", text));
  ASSERT_TRUE(s) << s.error().detail;
  const auto& g = s->devices.at(1).gps;
  EXPECT_FALSE(g.vtg || g.hdt || g.zda);
  EXPECT_EQ(g.reacquisition, 0s);
  EXPECT_EQ(g.heading_std_rad, 0.0);
}

TEST(LoadScenario, ByteBudgetCountsOptionalSentences) {
  // 2 Hz x (150 + 60 + 24 + 40) bytes x 10 bits = 5480 bit/s fits 9600; at 4 Hz it does not.
  std::string text = kMinimal;
  text.replace(text.find("dut:"), 0,
               "    - {name: gps, type: nmea0183-gps, rate: 4 Hz, baud: 9600,\n"
               "       sentences: [GGA, RMC, VTG, HDT, ZDA]}\n");
  const auto s = load_scenario(write_temp("gps_budget.yaml", text));
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().detail.find("too low for 4 Hz x 274-byte messages"), std::string::npos)
      << s.error().detail;
}

TEST(LoadScenario, MissingFileSaysWhy) {
  const std::string path = kSourceDir + "/scenarios/no-such-scenario.yaml";
  const auto s = load_scenario(path);
  ASSERT_FALSE(s);
  EXPECT_EQ(s.error().code, ErrorCode::kNotFound);
  EXPECT_EQ(s.error().detail, path + ": cannot open: No such file or directory");
}

TEST(LoadScenario, DirectoryIsNotAScenario) {
  const auto s = load_scenario(kSourceDir + "/scenarios");
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().detail.find(": cannot open: Is a directory"), std::string::npos)
      << s.error().detail;
}

TEST(LoadScenario, EmptyFileIsRefusedAtLineOne) {
  const std::string path = write_temp("empty.yaml", "");
  const auto s = load_scenario(path);
  ASSERT_FALSE(s);
  EXPECT_TRUE(s.error().detail.starts_with(path + ":1:1: expected a map with keys name, "))
      << s.error().detail;
}

TEST(LoadScenario, ErrorsCarryLineAndColumn) {
  std::string text = kMinimal;
  text.replace(text.find("speed: 1 m/s"), 12, "speed: 1 m");
  const std::string path = write_temp("column.yaml", text);
  const auto s = load_scenario(path);
  ASSERT_FALSE(s);
  EXPECT_EQ(s.error().detail,
            path +
                ":7:31: vehicle.path[0].speed: expected a speed such as '1.5 m/s', got '1 m' "
                "('m' is a length unit; units: m/s, kn, km/h)");
}

TEST(LoadScenario, EmptyValueIsReportedAtItsKey) {
  std::string text = kMinimal;
  text.replace(text.find("duration: 10 s"), 14, "duration:");
  const std::string path = write_temp("empty_value.yaml", text);
  const auto s = load_scenario(path);
  ASSERT_FALSE(s);
  EXPECT_TRUE(s.error().detail.starts_with(path + ":3:1: duration: expected a positive duration"))
      << s.error().detail;
  EXPECT_NE(s.error().detail.find("got nothing"), std::string::npos) << s.error().detail;
}

/// "# expect: TEXT" and "# line: N" from the head of a malformed scenario.
struct Expectation {
  std::string text;
  int line = 0;
};

Expectation read_expectation(const fs::path& p) {
  std::ifstream in(p);
  Expectation e;
  std::string l;
  for (int i = 0; i < 2 && std::getline(in, l); ++i) {
    if (l.starts_with("# expect: ")) e.text = l.substr(10);
    if (l.starts_with("# line: ")) e.line = std::stoi(l.substr(8));
  }
  return e;
}

TEST(LoadScenario, EveryMalformedScenarioIsRefusedWhereItsCommentSays) {
  const fs::path dir = fs::path(kSourceDir) / "tests/integration/malformed";
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() == ".yaml") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 12u);
  for (const auto& p : files) {
    SCOPED_TRACE(p.filename().string());
    const Expectation e = read_expectation(p);
    ASSERT_FALSE(e.text.empty()) << "first line must be '# expect: <text>'";
    ASSERT_GT(e.line, 0) << "second line must be '# line: N'";
    const auto s = load_scenario(p.string());
    ASSERT_FALSE(s) << "loaded although malformed";
    const std::string& msg = s.error().detail;
    const std::string prefix = p.string() + ":" + std::to_string(e.line) + ":";
    EXPECT_TRUE(msg.starts_with(prefix)) << msg << "\n  expected prefix " << prefix;
    EXPECT_NE(msg.find(e.text), std::string::npos) << msg << "\n  expected: " << e.text;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "not one line: " << msg;
  }
}

}  // namespace
}  // namespace nav::bench

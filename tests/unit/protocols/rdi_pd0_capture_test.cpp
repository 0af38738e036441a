// SPDX-License-Identifier: MIT
// Teledyne RDI PD0 against a real capture: 51 ensembles from an AUV's Explorer DVL with bottom
// track (fixtures-external/rdi-pd0/adcp_auv_51.pd0) and OOI mi-instrument's decode of them
// (adcp_auv_51.yml). Every yml field our decoder provides is compared; the test fails on a
// yml field it neither compares nor lists as not provided.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <set>
#include <string>
#include <vector>

#include "dvl_test_support.hpp"
#include "fixtures.hpp"
#include "nav/protocols/rdi_pd0.hpp"

namespace nav::protocols::rdi_pd0 {
namespace {

using test_support::drain;
using test_support::ExternalFixtureTest;
using test_support::read_bytes;

constexpr double kNtpToUnix = 2208988800.0;  ///< 1900-01-01 to 1970-01-01 [s]
constexpr std::size_t kEnsembleBytes = 432;  ///< N = 430 plus the checksum

/// Compares the fields of one mi-instrument particle and remembers which ones it saw.
class Particle {
 public:
  explicit Particle(const YAML::Node& node) : node_(node) {}
  void eq(const std::string& key, long long actual) {
    seen_.insert(key);
    ASSERT_TRUE(node_[key].IsDefined()) << key;
    EXPECT_EQ(node_[key].as<long long>(), actual) << key;
  }
  /// A per-cell list, e.g. correlation_magnitude_beam2 = profile[cell * beams + 1].
  template <typename T>
  void cells(const std::string& key, const Profile<T>& p, std::size_t beam, std::size_t beams) {
    seen_.insert(key);
    ASSERT_TRUE(node_[key].IsSequence()) << key;
    std::vector<long long> got;
    for (std::size_t c = 0; c * beams + beam < p.values.size(); ++c) {
      got.push_back(p.values[c * beams + beam]);
    }
    EXPECT_EQ(node_[key].as<std::vector<long long>>(), got) << key;
  }
  void bits(const std::string& key, unsigned value, int shift, unsigned mask) {
    eq(key, (value >> shift) & mask);
  }
  double number(const std::string& key) {
    seen_.insert(key);
    return node_[key].as<double>();
  }
  /// Fails on a yml field that was neither compared nor declared not provided.
  void all_seen(const std::set<std::string>& not_provided = {}) const {
    for (const auto& kv : node_) {
      const auto key = kv.first.as<std::string>();
      if (key == "_index" || key == "particle_object" || key == "particle_type") continue;
      EXPECT_TRUE(seen_.count(key) != 0 || not_provided.count(key) != 0)
          << "yml field " << key << " not compared";
    }
  }

 private:
  YAML::Node node_;
  std::set<std::string> seen_;
};

void check_velocity_particle(Particle& p, const Ensemble& e, ByteSpan raw) {
  const FixedLeader& f = *e.fixed_leader;
  const VariableLeader& v = *e.variable_leader;
  EXPECT_NEAR(p.number("internal_timestamp"), unix_seconds(v.rtc) + kNtpToUnix, 1e-4);
  p.eq("bin_1_distance", f.bin1_distance_cm);
  p.eq("cell_length", f.cell_length_cm);
  p.eq("num_cells", f.num_cells);
  p.eq("sysconfig_vertical_orientation", looks_up(f) ? 1 : 0);
  p.eq("ensemble_number", v.ensemble_number);
  p.eq("heading", v.heading_cdeg);
  p.eq("pitch", v.pitch_cdeg);
  p.eq("roll", v.roll_cdeg);
  p.eq("salinity", v.salinity_ppt);
  p.eq("temperature", v.temperature_cdegc);
  p.eq("transducer_depth", v.transducer_depth_dm);
  // This DVL's variable leader is 46 bytes: it has no pressure. mi-instrument's "pressure" is
  // bytes 48-51 after the leader's ID, i.e. the next data type's ID and first velocity.
  EXPECT_EQ(v.length, 46);
  EXPECT_FALSE(pressure_pa(v).has_value());
  const std::size_t vl = static_cast<std::size_t>(raw[8] | raw[9] << 8);
  const long long overread = raw[vl + 48] | raw[vl + 49] << 8 | raw[vl + 50] << 16 |
                             static_cast<long long>(raw[vl + 51]) << 24;
  p.eq("pressure", overread);

  const std::size_t nb = f.num_beams;
  const char* const corr[] = {"correlation_magnitude_beam1", "correlation_magnitude_beam2",
                              "correlation_magnitude_beam3", "correlation_magnitude_beam4"};
  const char* const echo[] = {"echo_intensity_beam1", "echo_intensity_beam2",
                              "echo_intensity_beam3", "echo_intensity_beam4"};
  // Velocity and percent good in earth/ship coordinates: E, N, U, error and 3-beam,
  // transformations rejected, more than one beam bad, 4-beam.
  const char* const vel[] = {"water_velocity_east", "water_velocity_north", "water_velocity_up",
                             "error_velocity"};
  const char* const pg[] = {"percent_good_3beam", "percent_transforms_reject", "percent_bad_beams",
                            "percent_good_4beam"};
  for (std::size_t b = 0; b < 4; ++b) {
    p.cells(corr[b], *e.correlation, b, nb);
    p.cells(echo[b], *e.echo_intensity, b, nb);
    p.cells(vel[b], *e.velocity, b, nb);
    p.cells(pg[b], *e.percent_good, b, nb);
  }
  p.all_seen();
}

void check_config_particle(Particle& p, const FixedLeader& f) {
  p.eq("beam_angle", beam_angle_deg(f).value_or(-1));
  p.eq("blank_after_transmit", f.blank_after_transmit_cm);
  p.eq("cell_length", f.cell_length_cm);
  p.bits("coord_transform_mapping", f.coord_transform, 0, 1);
  p.bits("coord_transform_beams", f.coord_transform, 1, 1);
  p.bits("coord_transform_tilts", f.coord_transform, 2, 1);
  p.eq("coord_transform_type", static_cast<int>(coordinates(f)));
  p.eq("data_flag", f.simulated);
  p.eq("error_vel_threshold", f.error_velocity_max_mmps);
  p.eq("false_target_threshold", f.false_target_threshold);
  p.eq("firmware_revision", f.firmware_revision);
  p.eq("firmware_version", f.firmware_version);
  p.eq("heading_alignment", f.heading_alignment_cdeg);
  p.eq("heading_bias", f.heading_bias_cdeg);
  p.eq("lag_length", f.lag_length);
  p.eq("low_corr_threshold", f.low_corr_threshold);
  p.eq("low_latency_trigger", f.spare);
  p.eq("num_beams", f.num_beams);
  p.eq("num_cells", f.num_cells);
  p.eq("num_code_repetitions", f.code_repetitions);
  p.eq("percent_good_min", f.percent_good_min);
  p.eq("pings_per_ensemble", f.pings_per_ensemble);
  p.eq("reference_layer_start", f.ref_layer_start_cell);
  p.eq("reference_layer_stop", f.ref_layer_end_cell);
  p.eq("signal_processing_mode", f.profiling_mode);
  p.eq("time_per_ping_minutes", f.tpp_minutes);
  p.eq("time_per_ping_seconds", f.tpp_seconds);
  p.eq("time_per_ping_hundredths", f.tpp_hundredths);
  p.eq("transmit_lag_distance", f.transmit_lag_distance_cm);
  EXPECT_EQ(p.number("serial_number"), f.serial_number);
  // Sensor bits: 6 sound speed, 5 depth, 4 heading, 3 pitch, 2 roll, 1 conductivity, 0 temp.
  const char* const sensors[] = {"temperature", "conductivity", "roll", "pitch",
                                 "heading",     "depth",        "speed"};
  for (int bit = 0; bit < 7; ++bit) {
    p.bits(std::string("sensor_source_") + sensors[bit], f.sensor_source, bit, 1);
    p.bits(std::string("sensor_available_") + sensors[bit], f.sensors_available, bit, 1);
  }
  static constexpr long long kFrequencyKhz[] = {75, 150, 300, 600, 1200, 2400, -1, -1};
  p.eq("sysconfig_frequency", kFrequencyKhz[f.system_config & 0x7]);
  p.bits("sysconfig_beam_pattern", f.system_config, 3, 1);
  p.bits("sysconfig_sensor_config", f.system_config, 4, 3);
  p.bits("sysconfig_head_attached", f.system_config, 6, 1);
  p.eq("sysconfig_vertical_orientation", looks_up(f) ? 1 : 0);
  p.bits("sysconfig_beam_angle", f.system_config, 8, 3);
  p.bits("sysconfig_beam_config", f.system_config, 12, 0xF);
  p.number("internal_timestamp");
  p.all_seen();
}

void check_engineering_particle(Particle& p, const Ensemble& e) {
  const VariableLeader& v = *e.variable_leader;
  const char* const adc[] = {"adc_transmit_current", "adc_transmit_voltage",    "adc_ambient_temp",
                             "adc_pressure_plus",    "adc_pressure_minus",      "adc_attitude_temp",
                             "adc_attitude",         "adc_contamination_sensor"};
  for (std::size_t i = 0; i < 8; ++i) p.eq(adc[i], v.adc[i]);
  p.eq("bit_result", v.bit_result);
  p.eq("error_status_word", v.error_status_word);
  p.eq("heading_stdev", v.heading_std_deg);
  p.eq("pitch_stdev", v.pitch_std_ddeg);
  p.eq("roll_stdev", v.roll_std_ddeg);
  p.eq("mpt_minutes", v.mpt_minutes);
  p.eq("mpt_seconds", v.mpt_seconds);
  p.eq("mpt_hundredths", v.mpt_hundredths);
  p.eq("speed_of_sound", v.speed_of_sound_mps);
  p.eq("transmit_pulse_length", e.fixed_leader->transmit_pulse_length_cm);
  p.number("internal_timestamp");
  p.all_seen();
}

void check_bottom_track_particle(Particle& p, const BottomTrack& b) {
  for (std::size_t i = 0; i < 4; ++i) {
    const std::string beam = "bt_beam" + std::to_string(i + 1) + "_";
    p.eq(beam + "range", b.range_cm[i]);
    p.eq(beam + "correlation", b.correlation[i]);
    p.eq(beam + "eval_amp", b.eval_amplitude[i]);
    p.eq(beam + "percent_good", b.percent_good[i]);
    p.eq(beam + "ref_correlation", b.ref_layer_correlation[i]);
    p.eq(beam + "ref_intensity", b.ref_layer_echo_intensity[i]);
    p.eq(beam + "ref_percent_good", b.ref_layer_percent_good[i]);
    p.eq(beam + "rssi_amplitude", b.rssi[i]);
  }
  // mi-instrument names velocities 1-4 forward, starboard, vertical, error (by slot).
  const char* const axes[] = {"forward", "starboard", "vertical", "error"};
  for (std::size_t i = 0; i < 4; ++i) {
    p.eq(std::string("bt_") + axes[i] + "_velocity", b.velocity_mmps[i]);
    p.eq(std::string("bt_") + axes[i] + "_ref_layer_velocity", b.ref_layer_velocity_mmps[i]);
  }
  p.eq("bt_gain", b.gain);
  p.eq("bt_ref_layer_min", b.ref_layer_min_dm);
  p.eq("bt_ref_layer_near", b.ref_layer_near_dm);
  p.eq("bt_ref_layer_far", b.ref_layer_far_dm);
  p.number("internal_timestamp");
  p.all_seen();
}

void check_bottom_config_particle(Particle& p, const BottomTrack& b) {
  p.eq("bt_corr_magnitude_min", b.corr_mag_min);
  p.eq("bt_delay_before_reacquire", b.delay_before_reacquire);
  p.eq("bt_error_velocity_max", b.error_velocity_max_mmps);
  p.eq("bt_eval_magnitude_min", b.eval_amp_min);
  p.eq("bt_max_depth", b.max_tracking_depth_dm);
  p.eq("bt_mode", b.mode);
  p.eq("bt_percent_good_min", b.percent_good_min);
  p.eq("bt_pings_per_ensemble", b.pings_per_ensemble);
  p.number("internal_timestamp");
  p.all_seen();
}

class RdiPd0Capture : public ExternalFixtureTest {};

TEST_F(RdiPd0Capture, FiftyOneValidEnsemblesWithBottomTrack) {
  const Bytes bytes = read_bytes(dir() / "rdi-pd0" / "adcp_auv_51.pd0");
  ASSERT_EQ(bytes.size(), 51 * kEnsembleBytes);
  const auto d = drain<Ensemble>(bytes, parse);
  EXPECT_TRUE(d.errors.empty()) << d.errors.front();
  EXPECT_EQ(d.leftover, 0u);
  ASSERT_EQ(d.messages.size(), 51u);
  for (std::size_t i = 0; i < d.messages.size(); ++i) {
    SCOPED_TRACE("ensemble " + std::to_string(i));
    const Ensemble& e = d.messages[i];
    EXPECT_EQ(d.offsets[i], i * kEnsembleBytes);
    EXPECT_EQ(e.data_type_ids, (std::vector<std::uint16_t>{0x0000, 0x0080, 0x0100, 0x0200, 0x0300,
                                                           0x0400, 0x0600, 0x2000}));
    ASSERT_TRUE(e.fixed_leader && e.variable_leader && e.bottom_track && e.velocity);
    EXPECT_EQ(e.fixed_leader->length, 59);
    EXPECT_EQ(e.bottom_track->length, 81);
    EXPECT_EQ(e.variable_leader->ensemble_number, 14 + i);  // consecutive
    if (i > 0) {
      const double dt = unix_seconds(e.variable_leader->rtc) -
                        unix_seconds(d.messages[i - 1].variable_leader->rtc);
      EXPECT_GT(dt, 0.0);
      EXPECT_LT(dt, 10.0);
    }

    // Our encoder reproduces each known data type of the real ensemble byte for byte (the
    // unknown 0x2000 type is not re-encoded, so the offsets shift; compare per data type).
    const ByteSpan raw = ByteSpan(bytes).subspan(i * kEnsembleBytes, kEnsembleBytes);
    const Bytes again = encode(e);
    const std::size_t k_raw = raw[5];
    ASSERT_EQ(again[5], k_raw - 1);
    for (std::size_t t = 0; t + 1 < k_raw; ++t) {
      const std::size_t off_raw = static_cast<std::size_t>(raw[6 + 2 * t] | raw[7 + 2 * t] << 8);
      const std::size_t end_raw = static_cast<std::size_t>(raw[8 + 2 * t] | raw[9 + 2 * t] << 8);
      const std::size_t off = static_cast<std::size_t>(again[6 + 2 * t] | again[7 + 2 * t] << 8);
      EXPECT_TRUE(std::equal(raw.begin() + static_cast<std::ptrdiff_t>(off_raw),
                             raw.begin() + static_cast<std::ptrdiff_t>(end_raw),
                             again.begin() + static_cast<std::ptrdiff_t>(off)))
          << "data type " << t;
    }
  }
}

TEST_F(RdiPd0Capture, EveryFieldOfOoiDecodeMatches) {
  const Bytes bytes = read_bytes(dir() / "rdi-pd0" / "adcp_auv_51.pd0");
  const YAML::Node yml = YAML::LoadFile((dir() / "rdi-pd0" / "adcp_auv_51.yml").string());
  const auto d = drain<Ensemble>(bytes, parse);
  ASSERT_EQ(d.messages.size(), 51u);

  // Particles come grouped per ensemble, each group opened by its adcp_velocity_earth.
  long long ensemble = -1;
  std::size_t counts[5] = {};
  for (const auto& node : yml["data"]) {
    const auto type = node["particle_type"].as<std::string>();
    if (type == "adcp_velocity_earth") ++ensemble;
    ASSERT_GE(ensemble, 0);
    ASSERT_LT(ensemble, 51);
    const auto i = static_cast<std::size_t>(ensemble);
    SCOPED_TRACE("ensemble " + std::to_string(i) + " " + type);
    const Ensemble& e = d.messages[i];
    Particle p(node);
    if (type == "adcp_velocity_earth") {
      check_velocity_particle(p, e, ByteSpan(bytes).subspan(i * kEnsembleBytes, kEnsembleBytes));
      ++counts[0];
    } else if (type == "adcp_config") {
      check_config_particle(p, *e.fixed_leader);
      ++counts[1];
    } else if (type == "adcp_engineering") {
      check_engineering_particle(p, e);
      ++counts[2];
    } else if (type == "adcp_bottom_track_inst") {
      check_bottom_track_particle(p, *e.bottom_track);
      ++counts[3];
    } else if (type == "adcp_bottom_track_config") {
      check_bottom_config_particle(p, *e.bottom_track);
      ++counts[4];
    } else {
      ADD_FAILURE() << "unexpected particle type " << type;
    }
  }
  EXPECT_EQ(ensemble, 50);
  EXPECT_EQ(counts[0], 51u);
  EXPECT_EQ(counts[1], 51u);
  EXPECT_EQ(counts[2], 23u);
  EXPECT_EQ(counts[3], 51u);
  EXPECT_EQ(counts[4], 1u);
}

}  // namespace
}  // namespace nav::protocols::rdi_pd0

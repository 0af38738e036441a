// SPDX-License-Identifier: MIT
#include "nav/bench/decode.hpp"

#include <gtest/gtest.h>

#include <array>
#include <map>
#include <numbers>
#include <random>

#include "../protocols/fixtures.hpp"
#include "nav/protocols/ebimu.hpp"
#include "nav/protocols/evologics_usbl.hpp"
#include "nav/protocols/keller_bus.hpp"
#include "nav/protocols/microstrain_gx3.hpp"
#include "nav/protocols/navquest_nq1.hpp"
#include "nav/protocols/nmea0183.hpp"
#include "nav/protocols/rdi_pd0.hpp"
#include "nav/protocols/rdi_pd6.hpp"
#include "nav/protocols/waterlinked_a50.hpp"

namespace nav::bench {
namespace {

using json = nlohmann::ordered_json;

std::vector<json> decode(const std::string& protocol, const protocols::Bytes& bytes,
                         DecodeCounts* counts = nullptr) {
  std::vector<json> out;
  const auto c = decode_stream(*find_decoder(protocol), bytes,
                               [&](const json& j) { out.push_back(j); });
  if (counts) *counts = c;
  return out;
}

protocols::Bytes text(const std::string& s) { return {s.begin(), s.end()}; }

/// Decodes `message` followed by a copy with byte `index` replaced by `bad`: the first comes
/// out as a message at offset 0, the corrupted copy as (at least) one error record right after.
void expect_corruption_reported(const std::string& protocol, const protocols::Bytes& message,
                                std::size_t index, std::uint8_t bad) {
  protocols::Bytes bytes = message;
  bytes.insert(bytes.end(), message.begin(), message.end());
  ASSERT_NE(bytes[message.size() + index], bad);
  bytes[message.size() + index] = bad;
  DecodeCounts c;
  const auto out = decode(protocol, bytes, &c);
  EXPECT_EQ(c.messages, 1u) << protocol;
  EXPECT_GE(c.errors, 1u) << protocol;
  ASSERT_GE(out.size(), 2u) << protocol;
  EXPECT_NE(out[0]["type"], "error") << protocol;
  EXPECT_EQ(out[1]["type"], "error") << protocol;
  EXPECT_EQ(out[1]["offset"], message.size()) << protocol;
}

TEST(Decode, Gx3PacketsInSiWithOffsetsAndBadBytesReported) {
  protocols::gx3::AccelRateMag m;
  m.accel_g = {0.0F, 0.0F, -1.0F};
  m.rate_radps = {0.01F, -0.02F, 0.03F};
  m.mag_gauss = {0.2F, 0.0F, 0.4F};
  m.timer_ticks = 62500;
  protocols::Bytes bytes = protocols::gx3::encode(m);
  bytes.insert(bytes.end(), {0x00, 0x01, 0x02});  // garbage between packets
  const auto good = protocols::gx3::encode(m);
  bytes.insert(bytes.end(), good.begin(), good.end());
  DecodeCounts c;
  const auto out = decode("microstrain-gx3", bytes, &c);
  EXPECT_EQ(c.messages, 2u);
  EXPECT_EQ(c.errors, 1u);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0]["type"], "gx3_accel_rate_mag");
  EXPECT_EQ(out[0].begin().key(), "type");  // "type" leads every object
  EXPECT_EQ(out[0]["offset"], 0);
  EXPECT_NEAR(out[0]["accel_mps2"][2].get<double>(), -9.80665, 1e-6);
  EXPECT_NEAR(out[0]["mag_uT"][2].get<double>(), 40.0, 1e-4);
  EXPECT_DOUBLE_EQ(out[0]["timer_s"].get<double>(), 1.0);
  EXPECT_EQ(out[1]["type"], "error");
  EXPECT_EQ(out[1]["offset"], 43);
  EXPECT_EQ(out[1]["length"], 3);  // one record for the whole run of garbage
  EXPECT_EQ(out[2]["offset"], 46);
}

TEST(Decode, NmeaSentencesCommentsAndTruncation) {
  const auto out = decode(
      "nmea0183", text("# gpsd-style header\n"
                       "$GNGGA,001043.00,4404.14036,N,12118.85961,W,1,12,0.98,1113.0,M,-21.3,M*47\r\n"
                       "$GNRMC,001031.00,A,4404.13993,N,12118.86023,W,0.146,,100117,,,A*7B\r\n"
                       "$GPHDT,274.07,T*04\r\n"  // wrong checksum (03)
                       "$GPGGA,0010"));
  ASSERT_EQ(out.size(), 4u);
  EXPECT_EQ(out[0]["type"], "GGA");
  EXPECT_EQ(out[0]["offset"], 20);
  EXPECT_NEAR(out[0]["lat_deg"].get<double>(), 44.0 + 4.14036 / 60.0, 1e-9);
  EXPECT_NEAR(out[0]["lon_deg"].get<double>(), -(121.0 + 18.85961 / 60.0), 1e-9);
  EXPECT_DOUBLE_EQ(out[0]["alt_msl_m"].get<double>(), 1113.0);
  EXPECT_EQ(out[1]["type"], "RMC");
  EXPECT_EQ(out[1]["date"], "2017-01-10");
  EXPECT_NEAR(out[1]["sog_mps"].get<double>(), 0.146 * 1852.0 / 3600.0, 1e-12);
  EXPECT_TRUE(out[1]["cog_deg"].is_null());
  EXPECT_EQ(out[2]["type"], "error");
  EXPECT_EQ(out[3]["error"], "truncated message at end of input");
}

TEST(Decode, Gx3EulerAndContinuousModeReplies) {
  namespace gx3 = protocols::gx3;
  const auto euler = gx3::encode(gx3::EulerAngles{0.1F, -0.2F, 1.5F, 125000});
  const auto cont = gx3::encode(gx3::ContinuousModeReply{gx3::kCmdAccelRateMag, 62500});
  const auto arm = gx3::encode(gx3::AccelRateMag{});
  protocols::Bytes bytes = cont;
  bytes.insert(bytes.end(), euler.begin(), euler.end());
  bytes.insert(bytes.end(), arm.begin(), arm.end());
  DecodeCounts c;
  const auto out = decode("microstrain-gx3", bytes, &c);
  EXPECT_EQ(c.errors, 0u);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0]["type"], "gx3_continuous_mode");
  EXPECT_EQ(out[0]["command"], gx3::kCmdAccelRateMag);
  EXPECT_DOUBLE_EQ(out[0]["timer_s"].get<double>(), 1.0);
  EXPECT_EQ(out[1]["type"], "gx3_euler_angles");
  EXPECT_EQ(out[1]["offset"], cont.size());
  EXPECT_NEAR(out[1]["pitch_rad"].get<double>(), -0.2, 1e-6);
  EXPECT_DOUBLE_EQ(out[1]["timer_s"].get<double>(), 2.0);
  EXPECT_EQ(out[2]["type"], "gx3_accel_rate_mag");
  EXPECT_EQ(out[2]["offset"], cont.size() + euler.size());
  expect_corruption_reported("microstrain-gx3", euler, 5, 0x55);
}

TEST(Decode, NmeaVtgHdtZdaDecodedIntoNamedFields) {
  namespace nmea = protocols::nmea;
  const std::string vtg = nmea::frame(nmea::to_sentence(nmea::Vtg{54.7, 34.4, 5.5, 10.186, 'A'}));
  const std::string hdt = nmea::frame(nmea::to_sentence(nmea::Hdt{274.07}, "HE"));
  nmea::Zda zda;
  zda.time = nmea::UtcTime{2017, 1, 10, 0, 10, 43.0};
  zda.zone_hours = -3;
  zda.zone_minutes = 30;
  const std::string z = nmea::frame(nmea::to_sentence(zda));
  const auto out = decode("nmea0183", text(vtg + hdt + z));
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0]["type"], "VTG");
  EXPECT_DOUBLE_EQ(out[0]["cog_true_deg"].get<double>(), 54.7);
  EXPECT_NEAR(out[0]["sog_mps"].get<double>(), 5.5 * 1852.0 / 3600.0, 1e-12);
  EXPECT_NEAR(out[0]["sog_from_kmh_mps"].get<double>(), 10.186 / 3.6, 1e-12);
  EXPECT_EQ(out[0]["mode"], "A");
  EXPECT_EQ(out[1]["type"], "HDT");
  EXPECT_EQ(out[1]["talker"], "HE");
  EXPECT_EQ(out[1]["offset"], vtg.size());
  EXPECT_DOUBLE_EQ(out[1]["heading_deg"].get<double>(), 274.07);
  EXPECT_EQ(out[2]["type"], "ZDA");
  EXPECT_EQ(out[2]["date"], "2017-01-10");
  EXPECT_EQ(out[2]["zone_hours"], -3);
  EXPECT_EQ(out[2]["zone_minutes"], 30);
  EXPECT_NEAR(out[2]["time_unix_s"].get<double>(), 1484007043.0, 1e-3);
  expect_corruption_reported("nmea0183", text(hdt), 8, '5');  // checksum no longer matches
}

TEST(Decode, NavdModemPositionReports) {
  // The worked example of docs/dut-contract.md, then one with a field out of range.
  const std::string good = "$PNVBPOS,42,12.346,36.383300,127.360000,12.50,1.4*60\r\n";
  const std::string body = "PNVBPOS,42,12.346,96.383300,127.360000,12.50,1.4";
  char cs[4];
  std::snprintf(cs, sizeof cs, "%02X", protocols::nmea::checksum(body));
  const auto out = decode("nmea0183", text(good + "$" + body + "*" + cs + "\r\n"));
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0]["type"], "NVBPOS");
  EXPECT_EQ(out[0]["vehicle_id"], 42);
  EXPECT_DOUBLE_EQ(out[0]["t_s"].get<double>(), 12.346);
  EXPECT_DOUBLE_EQ(out[0]["lat_deg"].get<double>(), 36.3833);
  EXPECT_DOUBLE_EQ(out[0]["lon_deg"].get<double>(), 127.36);
  EXPECT_DOUBLE_EQ(out[0]["depth_m"].get<double>(), 12.5);
  EXPECT_DOUBLE_EQ(out[0]["horizontal_std_m"].get<double>(), 1.4);
  EXPECT_EQ(out[1]["type"], "error");  // latitude 96 deg
  EXPECT_EQ(out[1]["offset"], good.size());
}

TEST(Decode, NavquestNq1InSi) {
  namespace nq1 = protocols::navquest_nq1;
  nq1::Nq1 m;
  m.beam_good = {true, true, true, false};
  m.beam_altitude_m = {10.5, 10.6, 10.4, -1.0};
  m.velocity_instrument_mmps = {100.0, -200.0, 30.0};
  m.velocity_instrument_flag = nq1::VelocityFlag::kBottom;
  m.roll_deg = 1.5;
  m.temperature_degc = 12.3;
  const auto line = text(nq1::encode(m));
  const auto out = decode("navquest-nq1", line);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0]["type"], "nq1");
  EXPECT_EQ(out[0]["offset"], 0);
  EXPECT_DOUBLE_EQ(out[0]["velocity_instrument_mps"][1].get<double>(), -0.2);
  EXPECT_EQ(out[0]["velocity_instrument_source"], "bottom");
  EXPECT_DOUBLE_EQ(out[0]["vehicle_velocity_mps"][0].get<double>(), -0.1);  // negated
  EXPECT_DOUBLE_EQ(out[0]["beam_altitude_m"][1].get<double>(), 10.6);
  EXPECT_DOUBLE_EQ(out[0]["temperature_degC"].get<double>(), 12.3);
  EXPECT_EQ(out[0]["beam_good"][3], false);
  expect_corruption_reported("navquest-nq1", line, 12, 'x');
}

TEST(Decode, RdiPd0EnsembleWithBottomTrack) {
  namespace pd0 = protocols::rdi_pd0;
  pd0::Ensemble e;
  e.fixed_leader.emplace();
  e.fixed_leader->coord_transform = 0x18;  // earth coordinates
  e.fixed_leader->beam_angle_deg = 30;
  e.fixed_leader->bin1_distance_cm = 117;
  e.variable_leader.emplace();
  e.variable_leader->ensemble_number = 70000;
  e.variable_leader->rtc = pd0::RtcTime{2014, 12, 19, 17, 17, 55, 94};
  e.variable_leader->heading_cdeg = 26067;
  e.variable_leader->temperature_cdegc = 518;
  e.variable_leader->pressure_dapa = 1234;
  e.bottom_track.emplace();
  e.bottom_track->range_cm = {1423, 1426, 0, 1481};
  e.bottom_track->velocity_mmps = {-58, pd0::kBadVelocity, 12, -3};
  const auto bytes = pd0::encode(e);
  const auto out = decode("rdi-pd0", bytes);
  ASSERT_EQ(out.size(), 1u);
  const auto& j = out[0];
  EXPECT_EQ(j["type"], "pd0_ensemble");
  EXPECT_EQ(j["offset"], 0);
  EXPECT_EQ(j["ensemble_number"], 70000);
  EXPECT_EQ(j["time"], "2014-12-19T17:17:55.94");
  EXPECT_NEAR(j["time_unix_s"].get<double>(), 1419009475.94, 1e-6);
  EXPECT_EQ(j["coordinates"], "earth");
  EXPECT_DOUBLE_EQ(j["bin1_distance_m"].get<double>(), 1.17);
  EXPECT_DOUBLE_EQ(j["heading_deg"].get<double>(), 260.67);
  EXPECT_DOUBLE_EQ(j["temperature_degC"].get<double>(), 5.18);
  EXPECT_DOUBLE_EQ(j["pressure_Pa"].get<double>(), 12340.0);
  const auto& bt = j["bottom_track"];
  EXPECT_DOUBLE_EQ(bt["range_m"][0].get<double>(), 14.23);
  EXPECT_TRUE(bt["range_m"][2].is_null());
  EXPECT_DOUBLE_EQ(bt["velocity_mps"][0].get<double>(), -0.058);
  EXPECT_TRUE(bt["velocity_mps"][1].is_null());
  EXPECT_TRUE(bt["vehicle_velocity_mps"].is_null());  // one of the three is bad
  expect_corruption_reported("rdi-pd0", bytes, bytes.size() / 2, 0x5A);
}

TEST(Decode, RdiPd6Lines) {
  namespace pd6 = protocols::rdi_pd6;
  const std::string bi = pd6::encode(pd6::InstrumentVelocity{pd6::Track::kBottom,
                                                             {250, -13, pd6::kBadVelocity, 7},
                                                             true});
  const std::string bd =
      pd6::encode(pd6::Distance{pd6::Track::kBottom, 12.5, -3.25, 0.5, 20.75, 0.2});
  const std::string sa = pd6::encode(pd6::Attitude{-1.5, 2.25, 180.5});
  const auto out = decode("rdi-pd6", text(bi + bd + sa));
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0]["type"], "pd6_instrument_velocity");
  EXPECT_EQ(out[0]["track"], "bottom");
  EXPECT_DOUBLE_EQ(out[0]["velocity_xyz_mps"][0].get<double>(), 0.25);
  EXPECT_TRUE(out[0]["velocity_xyz_mps"][2].is_null());
  EXPECT_DOUBLE_EQ(out[0]["error_velocity_mps"].get<double>(), 0.007);
  EXPECT_EQ(out[1]["type"], "pd6_distance");
  EXPECT_EQ(out[1]["offset"], bi.size());
  EXPECT_DOUBLE_EQ(out[1]["range_m"].get<double>(), 20.75);
  EXPECT_EQ(out[2]["type"], "pd6_attitude");
  EXPECT_DOUBLE_EQ(out[2]["heading_deg"].get<double>(), 180.5);
  expect_corruption_reported("rdi-pd6", text(bd), 6, 'x');
}

TEST(Decode, WaterlinkedA50Reports) {
  namespace a50 = protocols::waterlinked_a50;
  a50::VelocityReport v;
  v.vx_mps = 0.123;
  v.vy_mps = -0.045;
  v.vz_mps = 0.002;
  v.valid = true;
  v.altitude_m = 3.25;
  v.time_of_validity_us = 1600000000123456;
  v.time_since_last_ms = 100.0;
  const auto wrz = text(a50::frame(a50::to_packet(v)));
  a50::TransducerReport t;
  t.id = 2;
  t.distance_m = 3.5;
  t.rssi_dbm = -40.0;
  const auto wru = text(a50::frame(a50::to_packet(t)));
  protocols::Bytes bytes = wrz;
  bytes.insert(bytes.end(), wru.begin(), wru.end());
  const auto out = decode("waterlinked-a50", bytes);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0]["type"], "a50_velocity");
  EXPECT_DOUBLE_EQ(out[0]["velocity_mps"][1].get<double>(), -0.045);
  EXPECT_EQ(out[0]["valid"], true);
  EXPECT_DOUBLE_EQ(out[0]["altitude_m"].get<double>(), 3.25);
  EXPECT_NEAR(out[0]["time_of_validity_unix_s"].get<double>(), 1600000000.123456, 1e-6);
  EXPECT_DOUBLE_EQ(out[0]["time_since_last_s"].get<double>(), 0.1);
  EXPECT_EQ(out[1]["type"], "a50_transducer");
  EXPECT_EQ(out[1]["offset"], wrz.size());
  EXPECT_EQ(out[1]["id"], 2);
  EXPECT_DOUBLE_EQ(out[1]["distance_m"].get<double>(), 3.5);
  EXPECT_DOUBLE_EQ(out[1]["rssi_dBm"].get<double>(), -40.0);
  expect_corruption_reported("waterlinked-a50", wrz, 6, '9');  // CRC no longer matches
}

TEST(Decode, EbimuLinesByValueCount) {
  namespace ebimu = protocols::ebimu;
  ebimu::Sample s;
  s.euler_deg = std::array<double, 3>{-12.34, 89.99, -180.0};
  s.gyro_dps = std::array<double, 3>{90.0, 0.0, -45.0};
  s.accel_g = std::array<double, 3>{0.0, 0.0, 1.0};
  const std::string first = ebimu::encode(s);
  const auto line = text(first);
  const auto out = decode("ebimu", text(first + "*0.0012,-0.0034,0.7071,0.7071\r\n"));
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0]["type"], "ebimu");
  EXPECT_DOUBLE_EQ(out[0]["roll_deg"].get<double>(), -12.34);
  EXPECT_NEAR(out[0]["rate_radps"][0].get<double>(), std::numbers::pi / 2.0, 1e-12);
  EXPECT_NEAR(out[0]["accel_mps2"][2].get<double>(), 9.80665, 1e-12);
  EXPECT_EQ(out[1]["offset"], line.size());
  EXPECT_DOUBLE_EQ(out[1]["quat_wxyz"][0].get<double>(), 0.7071);  // w, sent last
  EXPECT_DOUBLE_EQ(out[1]["quat_wxyz"][3].get<double>(), 0.0012);  // z, sent first
  expect_corruption_reported("ebimu", line, 3, 'x');
}

TEST(Decode, KellerBusRequestsAndAnswers) {
  // Worked example of the codec tests: read P1 of device 1, answer 1.005182 bar.
  const protocols::Bytes request = {0x01, 0x49, 0x01, 0x50, 0xD6};
  const protocols::Bytes answer = {0x01, 0x49, 0x3F, 0x80, 0xA9, 0xCB, 0x00, 0x4C, 0xBF};
  protocols::Bytes bytes = request;
  bytes.insert(bytes.end(), answer.begin(), answer.end());
  DecodeCounts c;
  const auto out = decode("keller-bus", bytes, &c);
  EXPECT_EQ(c.errors, 0u);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0]["type"], "keller_request");
  EXPECT_EQ(out[0]["function_name"], "read_channel");
  EXPECT_EQ(out[0]["channel_name"], "P1");
  EXPECT_EQ(out[0]["unit"], "bar");
  EXPECT_EQ(out[1]["type"], "keller_channel_value");
  EXPECT_EQ(out[1]["offset"], 5);
  EXPECT_EQ(out[1]["address"], 1);
  EXPECT_NEAR(out[1]["value"].get<double>(), 1.005182, 1e-6);
  expect_corruption_reported("keller-bus", answer, 4, 0x00);
}

TEST(Decode, EvologicsUsblNotifications) {
  // The real USBLLONG sample of the codec tests, in data mode.
  const std::string payload =
      "USBLLONG,10446.991981,10446.534643,3,-0.0604,-1.0888,-0.5851,-0.4233,-1.0020,-0.5901,"
      "0.0063,0.0269,-0.3295,825,-36,77,1.2375";
  const std::string framed = "+++AT:124:" + payload + "\r\n";
  const auto line = text(framed);
  const auto out = decode("evologics-usbl", text(framed + payload + "\r\n"));
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0]["type"], "usbllong");
  EXPECT_EQ(out[0]["framing"], "data");
  EXPECT_EQ(out[0]["remote_address"], 3);
  EXPECT_DOUBLE_EQ(out[0]["xyz_m"][1].get<double>(), -1.0888);
  EXPECT_DOUBLE_EQ(out[0]["yaw_rad"].get<double>(), -0.3295);
  EXPECT_DOUBLE_EQ(out[0]["propagation_time_s"].get<double>(), 825e-6);
  EXPECT_DOUBLE_EQ(out[0]["accuracy_m"].get<double>(), 1.2375);
  EXPECT_EQ(out[1]["framing"], "command");
  EXPECT_EQ(out[1]["offset"], line.size());
  expect_corruption_reported("evologics-usbl", line, 30, 'x');
}

/// The real PD0 capture of fixtures-external decodes whole.
class DecodeCapture : public protocols::test_support::ExternalFixtureTest {};

TEST_F(DecodeCapture, RealRdiPd0CaptureDecodesEveryEnsemble) {
  const auto bytes = protocols::test_support::read_bytes(dir() / "rdi-pd0" / "adcp_auv_51.pd0");
  ASSERT_FALSE(bytes.empty());
  DecodeCounts c;
  const auto out = decode("rdi-pd0", bytes, &c);
  EXPECT_EQ(c.messages, 51u);
  EXPECT_EQ(c.errors, 0u);
  ASSERT_EQ(out.size(), 51u);
  EXPECT_EQ(out[0]["ensemble_number"], 14);
  EXPECT_EQ(out[0]["bottom_track"]["range_m"].size(), 4u);
}

/// The 129029 fast packet of protocols.md section 5 (canboat candumpSample1, ID 0DF80500) as
/// candump -l lines at 1 ms steps from t = 1362166096 s.
std::string gnss_fast_packet_lines(std::size_t skip = 99) {
  static const char* kFrames[] = {"002F01953D00CDC7", "012980C047E8B8C9", "02E50500A10EC43F",
                                  "03D610F67AF22705", "040000000003FC00", "05FFFFFFFFDDF2FF",
                                  "06FF00FFFFFFFFFF"};
  std::string out;
  for (std::size_t i = 0; i < 7; ++i) {
    if (i == skip) continue;
    out += "(1362166096.00" + std::to_string(i) + "000) can0 0DF80500#" + kFrames[i] + "\n";
  }
  return out;
}

TEST(Decode, Nmea2000CandumpLogWithFastPacketsUnknownsAndBadLines) {
  const std::string log =
      "# a comment line\n"
      "(1502984866.421964) slcan0 09F112CC#FF725AFF7FFF7FFD\n"  // protocols.md section 7
      + gnss_fast_packet_lines() +
      "(1502984866.500000) slcan0 09FD0207#000000F504FAFFFF\n"  // 130306: not decoded here
      "(1502984866.600000) slcan0 123#DEADBEEF R\n"             // not N2K: 11-bit ID
      "(1502984866.700000) slcan0 09F112CC#FF72\n"              // 127250 payload too short
      "(1502984866.8) slcan0 09F112CC#FF725AFF7FFF7FFD\n"      // 1 decimal
      "(1502984866.900000) slcan0 123##1112233\n"               // CAN FD
      "(1502984867.000000123) slcan0 15F50B23#FF29000000BC02FF\n";  // 128267, prio 5
  DecodeCounts c;
  const auto out = decode("nmea2000", text(log), &c);
  EXPECT_EQ(c.messages, 5u);
  EXPECT_EQ(c.errors, 3u);
  ASSERT_EQ(out.size(), 8u);

  EXPECT_EQ(out[0]["type"], "n2k_vessel_heading");
  EXPECT_EQ(out[0].begin().key(), "type");
  EXPECT_EQ(out[0]["pgn"], 127250);
  EXPECT_EQ(out[0]["src"], 0xCC);
  EXPECT_EQ(out[0]["prio"], 2);
  EXPECT_TRUE(out[0]["sid"].is_null());
  EXPECT_NEAR(out[0]["heading_rad"].get<double>(), 2.3154, 1e-9);
  EXPECT_TRUE(out[0]["deviation_rad"].is_null());
  EXPECT_TRUE(out[0]["variation_rad"].is_null());
  EXPECT_EQ(out[0]["reference"], "magnetic");
  EXPECT_DOUBLE_EQ(out[0]["t_s"].get<double>(), 1502984866.421964);
  EXPECT_EQ(out[0]["line"], 2);
  EXPECT_EQ(out[0]["offset"], 17);

  EXPECT_EQ(out[1]["type"], "n2k_gnss_position");
  EXPECT_EQ(out[1]["pgn"], 129029);
  EXPECT_EQ(out[1]["prio"], 3);
  EXPECT_EQ(out[1]["src"], 0);
  EXPECT_EQ(out[1]["line"], 9);  // the frame that completed it
  EXPECT_DOUBLE_EQ(out[1]["t_s"].get<double>(), 1362166096.006);
  EXPECT_EQ(out[1]["date"], "2013-03-01");
  EXPECT_DOUBLE_EQ(out[1]["time_of_day_s"].get<double>(), 70096.0);
  EXPECT_NEAR(out[1]["lat_deg"].get<double>(), 42.4967536, 0.5e-7);
  EXPECT_NEAR(out[1]["lon_deg"].get<double>(), -71.5836771, 0.5e-7);
  EXPECT_NEAR(out[1]["alt_m"].get<double>(), 86.504, 1e-3);
  EXPECT_NEAR(out[1]["geoid_sep_m"].get<double>(), -33.63, 1e-12);
  EXPECT_EQ(out[1]["gnss_type"], 3);

  EXPECT_EQ(out[2]["type"], "n2k_raw");
  EXPECT_EQ(out[2]["pgn"], 130306);
  EXPECT_EQ(out[2]["src"], 7);
  EXPECT_EQ(out[2]["data"], "000000F504FAFFFF");

  EXPECT_EQ(out[3]["type"], "can_frame");
  EXPECT_EQ(out[3]["id"], 0x123);
  EXPECT_EQ(out[3]["extended"], false);
  EXPECT_EQ(out[3]["data"], "DEADBEEF");

  EXPECT_EQ(out[4]["type"], "error");
  EXPECT_EQ(out[4]["line"], 12);
  EXPECT_NE(out[4]["error"].get<std::string>().find("PGN 127250"), std::string::npos);
  EXPECT_EQ(out[5]["type"], "error");
  EXPECT_EQ(out[5]["line"], 13);
  EXPECT_EQ(out[5]["error"], "line 13: column 13: timestamp needs 6 or 9 decimals, found 1");
  EXPECT_EQ(out[6]["type"], "error");
  EXPECT_EQ(out[6]["line"], 14);
  EXPECT_NE(out[6]["error"].get<std::string>().find("CAN FD"), std::string::npos);

  EXPECT_EQ(out[7]["type"], "n2k_water_depth");
  EXPECT_EQ(out[7]["prio"], 5);
  EXPECT_EQ(out[7]["src"], 0x23);
  EXPECT_TRUE(out[7]["sid"].is_null());
  EXPECT_NEAR(out[7]["depth_m"].get<double>(), 0.41, 1e-12);
  EXPECT_NEAR(out[7]["offset_m"].get<double>(), 0.700, 1e-12);
  EXPECT_TRUE(out[7]["max_range_m"].is_null());
  EXPECT_DOUBLE_EQ(out[7]["t_s"].get<double>(), 1502984867.000000123);
}

TEST(Decode, Nmea2000FastPacketLostFrameIsReportedNotMisassembled) {
  // Frame 3 lost, then a whole message; then a message cut off by the end of the log.
  const std::string log = gnss_fast_packet_lines(3) + gnss_fast_packet_lines() +
                          gnss_fast_packet_lines().substr(0, 2 * 51);  // frames 0 and 1
  DecodeCounts c;
  const auto out = decode("nmea2000", text(log), &c);
  ASSERT_EQ(out.size(), 5u);
  EXPECT_EQ(out[0]["type"], "error");  // the gap breaks the first message at its frame 4
  EXPECT_EQ(out[0]["line"], 1);
  EXPECT_NE(out[0]["error"].get<std::string>().find("discarded at line 4"), std::string::npos)
      << out[0]["error"];
  EXPECT_EQ(out[1]["type"], "error");  // frames 5 and 6 have no message any more
  EXPECT_EQ(out[1]["line"], 5);
  EXPECT_EQ(out[2]["line"], 6);
  EXPECT_EQ(out[3]["type"], "n2k_gnss_position");
  EXPECT_EQ(out[3]["line"], 13);
  EXPECT_EQ(out[4]["type"], "error");
  EXPECT_EQ(out[4]["line"], 14);
  EXPECT_NE(out[4]["error"].get<std::string>().find("incomplete at end of input"),
            std::string::npos);
  EXPECT_EQ(c.messages, 1u);
  EXPECT_EQ(c.errors, 4u);
}

TEST_F(DecodeCapture, RealNmea2000CaptureDecodesEveryFrame) {
  const auto bytes =
      protocols::test_support::read_bytes(dir() / "nmea2000" / "candumpSample2.txt");
  ASSERT_FALSE(bytes.empty());
  DecodeCounts c;
  const auto out = decode("nmea2000", bytes, &c);
  EXPECT_EQ(c.errors, 0u);
  EXPECT_EQ(c.messages, 267u);  // 402 frames; 35 + 110 of them are 5 + 5 fast packets
  std::map<std::string, std::size_t> types;
  std::map<int, std::size_t> raw_pgns;
  for (const auto& j : out) {
    ++types[j["type"].get<std::string>()];
    if (j["type"] == "n2k_raw") ++raw_pgns[j["pgn"].get<int>()];
    EXPECT_TRUE(j["t_s"].is_null());  // screen print without timestamps
  }
  const std::map<std::string, std::size_t> want = {
      {"n2k_vessel_heading", 46}, {"n2k_rate_of_turn", 46},  {"n2k_attitude", 5},
      {"n2k_position_rapid", 46}, {"n2k_cog_sog_rapid", 46}, {"n2k_gnss_position", 5},
      {"n2k_raw", 73}};
  EXPECT_EQ(types, want);
  const std::map<int, std::size_t> want_raw = {
      {126992, 5}, {127258, 13}, {129539, 5}, {129540, 5}, {130306, 45}};
  EXPECT_EQ(raw_pgns, want_raw);
  // 129540 reassembled: 147 bytes.
  for (const auto& j : out) {
    if (j["type"] == "n2k_raw" && j["pgn"] == 129540) {
      EXPECT_EQ(j["data"].get<std::string>().size(), 2u * 147u);
    }
  }
  EXPECT_EQ(out[2]["type"], "n2k_vessel_heading");
  EXPECT_EQ(out[2]["line"], 9);
  EXPECT_EQ(out[2]["src"], 128);
  EXPECT_NEAR(out[2]["heading_rad"].get<double>(), 3.9324, 1e-9);
  EXPECT_NEAR(out[2]["variation_rad"].get<double>(), -0.2570, 1e-9);
}

// Random bytes fail at almost every offset, each for a reason of its own (a Keller frame's
// CRC): a run of bad bytes is one error record, not one per byte (64 KiB of noise used to give
// the Keller decoder about 64 000 records).
TEST(Decode, EveryRunOfBadBytesIsOneErrorRecord) {
  std::mt19937_64 rng(12345);
  protocols::Bytes noise(64 * 1024);
  for (auto& b : noise) b = static_cast<std::uint8_t>(rng());
  for (const auto& d : protocol_decoders()) {
    if (d.name == "nmea2000") continue;  // line-based candump text: its own test
    DecodeCounts c;
    const auto out = decode(d.name, noise, &c);
    // Runs of bad bytes alternate with messages (noise may hold a valid short frame); the
    // end may add a truncated message.
    EXPECT_LE(c.errors, c.messages + 2) << d.name;
    for (std::size_t i = 1; i < out.size(); ++i) {
      EXPECT_FALSE(out[i]["type"] == "error" && out[i - 1]["type"] == "error" &&
                   out[i - 1]["error"] != "truncated message at end of input" &&
                   out[i]["error"] != "truncated message at end of input")
          << d.name << ": two error records in a row at " << out[i]["offset"];
    }
  }
}

TEST(Decode, BytesOfOnePortFromACapture) {
  const std::string cap = "(0.000100000) ahrs CB00\n(0.001000000) gps 2447\n(0.002000000) ahrs FF\n";
  const auto b = bytes_from_capture(cap, "ahrs", "cap.log");
  ASSERT_TRUE(b);
  EXPECT_EQ(*b, (protocols::Bytes{0xCB, 0x00, 0xFF}));
  EXPECT_FALSE(bytes_from_capture("(0.1) ahrs ABC\n", "ahrs", "cap.log"));
  const auto bad = bytes_from_capture("ahrs CB\n", "ahrs", "cap.log");
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error().detail.rfind("cap.log:1: expected", 0), 0u) << bad.error().detail;
}

// A port the capture does not have used to decode nothing and exit 0: it is named, with the
// ports the capture has.
TEST(Decode, APortTheCaptureDoesNotHaveIsAnErrorListingItsPorts) {
  const std::string cap = "(0.000100000) ahrs CB00\n(0.001000000) gps 2447\n(0.002000000) ahrs FF\n";
  const auto none = bytes_from_capture(cap, "nosuch", "cap.log");
  ASSERT_FALSE(none);
  EXPECT_EQ(none.error().code, ErrorCode::kNotFound);
  EXPECT_EQ(none.error().detail, "cap.log: no port 'nosuch' in this capture (its ports: ahrs, gps)");
  const auto empty = bytes_from_capture("", "ahrs", "cap.log");
  ASSERT_FALSE(empty);
  EXPECT_EQ(empty.error().detail, "cap.log: no port 'ahrs' in this capture (it has no lines)");
}

}  // namespace
}  // namespace nav::bench

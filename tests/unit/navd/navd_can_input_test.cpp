// SPDX-License-Identifier: MIT
// navd's CAN front end (dut/navd/can_input.hpp), pure: frames built with the nmea2000 encoders
// and the wheel encoder codec, plus frames transcribed by hand from the bit layouts
// (protocols.md section 5, fixtures/crawler.dbc) so that a bug shared by encoder and decoder
// does not pass unseen. Fast packets interleaved from two sources, lost and repeated frames,
// garbage identifiers, RTR and error frames, frames that disagree with the DBC, a DBC that
// disagrees with the code, and the summary text.
#include "can_input.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "nav/protocols/dbc.hpp"
#include "nav/protocols/nmea2000.hpp"
#include "nav/protocols/wheel_encoder.hpp"
#include "source_paths.hpp"

namespace nav::dut {
namespace {

namespace can = protocols::can;
namespace dbc = protocols::dbc;
namespace n2k = protocols::n2k;
namespace wheel = protocols::wheel_encoder;

std::string crawler_path() { return nav::test_paths::source_dir() + "/fixtures/crawler.dbc"; }

std::string crawler_text() {
  std::ifstream f(crawler_path());
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

dbc::Database crawler_db() {
  auto db = dbc::load(crawler_path());
  EXPECT_TRUE(db.has_value()) << (db ? "" : db.error().detail);
  return db ? *db : dbc::Database{};
}

CanInput crawler_input() {
  auto in = CanInput::with_dbc(crawler_db());
  EXPECT_TRUE(in.has_value()) << (in ? "" : in.error().detail);
  return in ? std::move(*in) : CanInput{};
}

/// A frame from an identifier and bytes as a candump line would show them.
can::Frame raw_frame(std::uint32_t id, bool extended, const std::vector<std::uint8_t>& bytes) {
  can::Frame f;
  f.id = id;
  f.extended = extended;
  f.dlc = static_cast<std::uint8_t>(bytes.size());
  std::copy(bytes.begin(), bytes.end(), f.data.begin());
  return f;
}

can::Frame to_can(const dbc::Frame& f) {
  return raw_frame(f.id, f.extended, std::vector<std::uint8_t>(f.data.begin(), f.data.end()));
}

void feed_all(CanInput& in, const std::vector<can::Frame>& frames) {
  for (const auto& f : frames) in.feed(f);
}

n2k::GnssPositionData gnss(double lat_deg, double lon_deg) {
  n2k::GnssPositionData g;
  g.sid = 1;
  g.date_days = 20000;
  g.time_s = 43200.0;
  g.lat_deg = lat_deg;
  g.lon_deg = lon_deg;
  g.altitude_m = 12.5;
  g.method = 1;
  g.satellites = 9;
  g.hdop = 0.8;
  g.pdop = 1.4;
  g.geoid_separation_m = 0.0;
  return g;
}

TEST(NavdCanInput, SingleFramePgnsAreCountedAndTheLastKept) {
  CanInput in;
  n2k::VesselHeading h;
  h.heading_rad = 1.0;
  h.reference = n2k::DirectionReference::kTrue;
  n2k::RateOfTurn r;
  r.rate_radps = 0.01;
  n2k::Attitude a;
  a.yaw_rad = 1.0;
  a.pitch_rad = 0.05;
  a.roll_rad = -0.02;
  n2k::SpeedWaterReferenced sw;
  sw.water_speed_mps = 1.25;
  n2k::WaterDepth d;
  d.depth_m = 42.5;
  d.offset_m = 0.3;
  n2k::PositionRapidUpdate p;
  p.lat_deg = 36.3833;
  p.lon_deg = 127.36;
  n2k::CogSogRapidUpdate cs;
  cs.reference = n2k::DirectionReference::kTrue;
  cs.cog_rad = 0.5;
  cs.sog_mps = 0.96;
  const n2k::Header src{2, 0, 0x23};
  for (const n2k::Message& m : std::vector<n2k::Message>{h, r, a, sw, d, p, cs}) {
    feed_all(in, n2k::encode_frames(src, m));
  }
  d.depth_m = 43.0;
  feed_all(in, n2k::encode_frames(n2k::Header{3, 0, 0x24}, d));

  EXPECT_EQ(in.frames(), 8u);
  for (const std::uint32_t pgn : CanInput::kPgns) {
    const std::uint64_t expected = pgn == n2k::kPgnWaterDepth      ? 2u
                                   : pgn == n2k::kPgnGnssPosition ? 0u
                                                                  : 1u;
    EXPECT_EQ(in.n2k_count(pgn), expected) << pgn;
  }
  ASSERT_NE(in.last<n2k::VesselHeading>(), nullptr);
  EXPECT_NEAR(*in.last<n2k::VesselHeading>()->heading_rad, 1.0, 1e-4);
  ASSERT_NE(in.last<n2k::Attitude>(), nullptr);
  EXPECT_NEAR(*in.last<n2k::Attitude>()->pitch_rad, 0.05, 1e-4);
  ASSERT_NE(in.last<n2k::WaterDepth>(), nullptr);
  EXPECT_NEAR(*in.last<n2k::WaterDepth>()->depth_m, 43.0, 0.01);
  EXPECT_EQ(in.last_source(n2k::kPgnWaterDepth), 0x24);
  ASSERT_NE(in.last<n2k::PositionRapidUpdate>(), nullptr);
  EXPECT_NEAR(*in.last<n2k::PositionRapidUpdate>()->lat_deg, 36.3833, 1e-6);
  ASSERT_NE(in.last<n2k::CogSogRapidUpdate>(), nullptr);
  EXPECT_NEAR(*in.last<n2k::CogSogRapidUpdate>()->sog_mps, 0.96, 0.01);
  ASSERT_NE(in.last<n2k::SpeedWaterReferenced>(), nullptr);
  EXPECT_NEAR(*in.last<n2k::SpeedWaterReferenced>()->water_speed_mps, 1.25, 0.01);
  EXPECT_EQ(in.last<n2k::GnssPositionData>(), nullptr);
  const CanRejects& rej = in.rejects();
  EXPECT_EQ(rej.unknown_id + rej.rtr + rej.error_frames + rej.fields + rej.fast_packet +
                rej.fast_packet_dup + rej.dbc,
            0u);
}

TEST(NavdCanInput, HandTranscribedHeadingFrame) {
  // Priority 2, PGN 127250 (0x1F112), source 0x01: 2<<26 | 0x1F112<<8 | 0x01 = 0x09F11201.
  // SID 0; heading 15708 x 1e-4 rad = 5C 3D; deviation and variation n/a (7FFF); reference
  // true (0) with the six reserved bits 1 = FC.
  CanInput in;
  in.feed(raw_frame(0x09F11201, true, {0x00, 0x5C, 0x3D, 0xFF, 0x7F, 0xFF, 0x7F, 0xFC}));
  EXPECT_EQ(in.n2k_count(n2k::kPgnVesselHeading), 1u);
  const auto* h = in.last<n2k::VesselHeading>();
  ASSERT_NE(h, nullptr);
  ASSERT_TRUE(h->heading_rad.has_value());
  EXPECT_NEAR(*h->heading_rad, 1.5708, 1e-9);
  EXPECT_FALSE(h->deviation_rad.has_value());
  EXPECT_EQ(h->reference, n2k::DirectionReference::kTrue);
  EXPECT_EQ(in.last_source(n2k::kPgnVesselHeading), 0x01);
}

TEST(NavdCanInput, FastPacketsInterleavedFromTwoSourcesBothAssemble) {
  CanInput in;
  const auto a = n2k::encode_frames(n2k::Header{3, 0, 10}, gnss(36.5, 127.25), 2);
  const auto b = n2k::encode_frames(n2k::Header{3, 0, 20}, gnss(-12.75, -45.5), 5);
  ASSERT_EQ(a.size(), 7u);
  ASSERT_EQ(b.size(), 7u);
  // a0 b0 a1 b1 ... a6 b6: a completes at a6, b at b6.
  for (std::size_t i = 0; i < a.size(); ++i) {
    in.feed(a[i]);
    EXPECT_EQ(in.n2k_count(n2k::kPgnGnssPosition), i + 1 == a.size() ? 1u : 0u) << i;
    in.feed(b[i]);
  }
  EXPECT_EQ(in.n2k_count(n2k::kPgnGnssPosition), 2u);
  const auto* g = in.last<n2k::GnssPositionData>();
  ASSERT_NE(g, nullptr);
  EXPECT_NEAR(*g->lat_deg, -12.75, 1e-9);
  EXPECT_NEAR(*g->lon_deg, -45.5, 1e-9);
  EXPECT_NEAR(*g->altitude_m, 12.5, 1e-6);
  EXPECT_EQ(in.last_source(n2k::kPgnGnssPosition), 20);
  EXPECT_EQ(in.rejects().fast_packet, 0u);
  EXPECT_EQ(in.frames(), 14u);
}

TEST(NavdCanInput, FastPacketLostAndRepeatedFramesAreCountedNeverMisassembled) {
  CanInput in;
  const auto a = n2k::encode_frames(n2k::Header{3, 0, 10}, gnss(36.5, 127.25), 1);
  // Frame 2 lost: frame 3 discards the message and is an orphan itself, like 4..6.
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (i != 2) in.feed(a[i]);
  }
  EXPECT_EQ(in.n2k_count(n2k::kPgnGnssPosition), 0u);
  EXPECT_EQ(in.last<n2k::GnssPositionData>(), nullptr);
  EXPECT_EQ(in.rejects().fast_packet, 1u + 4u);
  // The next message, with frame 1 repeated (ignored), assembles.
  const auto b = n2k::encode_frames(n2k::Header{3, 0, 10}, gnss(36.75, 127.5), 2);
  for (std::size_t i = 0; i < b.size(); ++i) {
    in.feed(b[i]);
    if (i == 1) in.feed(b[i]);
  }
  EXPECT_EQ(in.n2k_count(n2k::kPgnGnssPosition), 1u);
  EXPECT_EQ(in.rejects().fast_packet_dup, 1u);
  ASSERT_NE(in.last<n2k::GnssPositionData>(), nullptr);
  EXPECT_NEAR(*in.last<n2k::GnssPositionData>()->lat_deg, 36.75, 1e-9);
}

TEST(NavdCanInput, GarbageIdentifiersAndFramesAreRejectedByReason) {
  for (const bool with_dbc : {false, true}) {
    SCOPED_TRACE(with_dbc ? "with the crawler DBC" : "without a DBC");
    CanInput in = with_dbc ? crawler_input() : CanInput{};
    in.feed(raw_frame(0x555, false, {1, 2, 3}));                       // 11-bit, no message
    in.feed(raw_frame(0x000, false, {}));                              // 11-bit, id 0, DLC 0
    in.feed(raw_frame(0x02000000u | 0x09F11201u, true, {0, 0, 0, 0, 0, 0, 0, 0}));  // EDP set
    can::Frame rtr = raw_frame(0x09F11201, true, {});
    rtr.rtr = true;
    rtr.dlc = 8;
    in.feed(rtr);
    can::Frame err;
    err.error = true;
    err.id = 0x004;
    in.feed(err);
    // A well-formed N2K frame of a PGN navd does not decode (ISO address claim 60928).
    in.feed(n2k::single_frame(n2k::Header{6, 60928, 0x23}, protocols::Bytes(8, 0x11)));
    // 127250 with only 3 bytes: too short for its fields.
    in.feed(raw_frame(0x09F11201, true, {0x00, 0x5C, 0x3D}));
    // 11-bit wheel ids as 29-bit frames are not the DBC's messages: N2K PGN 0 (other).
    in.feed(raw_frame(288, true, {0, 0, 0, 0, 0, 0, 0, 0}));

    EXPECT_EQ(in.frames(), 8u);
    EXPECT_EQ(in.rejects().unknown_id, 3u);
    EXPECT_EQ(in.rejects().rtr, 1u);
    EXPECT_EQ(in.rejects().error_frames, 1u);
    EXPECT_EQ(in.rejects().fields, 1u);
    EXPECT_EQ(in.n2k_other(), 2u);
    for (const std::uint32_t pgn : CanInput::kPgns) EXPECT_EQ(in.n2k_count(pgn), 0u) << pgn;
    EXPECT_EQ(in.dbc_count(std::string(wheel::kLeftMessage)), 0u);
  }
}

TEST(NavdCanInput, WheelFramesThroughTheDbc) {
  const auto codec = wheel::WheelEncoderCodec::from_database(crawler_db());
  ASSERT_TRUE(codec.has_value()) << codec.error().detail;
  CanInput in = crawler_input();
  ASSERT_TRUE(in.has_dbc());
  for (std::uint32_t k = 0; k < 3; ++k) {
    const auto counter = static_cast<std::uint8_t>(k);
    const wheel::WheelEncoderSample left{wheel::Wheel::kLeft, 1000 + 10 * k, 1.5, counter, true};
    const wheel::WheelEncoderSample right{wheel::Wheel::kRight, 4294967290u + 3 * k, -0.25,
                                          counter, k != 2};
    const auto fl = codec->encode(left);
    const auto fr = codec->encode(right);
    ASSERT_TRUE(fl && fr);
    in.feed(to_can(*fl));
    in.feed(to_can(*fr));
  }
  EXPECT_EQ(in.dbc_count("WheelEncoderLeft"), 3u);
  EXPECT_EQ(in.dbc_count("WheelEncoderRight"), 3u);
  const auto& l = in.last_wheel(wheel::Wheel::kLeft);
  const auto& r = in.last_wheel(wheel::Wheel::kRight);
  ASSERT_TRUE(l && r);
  EXPECT_EQ(l->ticks, 1020u);
  EXPECT_NEAR(l->omega, 1.5, 1e-9);
  EXPECT_EQ(r->ticks, 0u);  // 4294967290 + 6 wrapped modulo 2^32
  EXPECT_NEAR(r->omega, -0.25, 1e-9);
  EXPECT_EQ(r->counter, 2);
  EXPECT_FALSE(r->valid);  // an invalid reading is decoded and kept, flagged
  EXPECT_EQ(in.rejects().dbc + in.rejects().unknown_id, 0u);
}

TEST(NavdCanInput, HandTranscribedWheelFrame) {
  // crawler.dbc BO_ 288: TickCount 0|32 = 1000 (E8 03 00 00), WheelSpeed 32|16 signed x0.001
  // = 1.5 rad/s (1500 = DC 05), MsgCounter 48|4 = 3 and Valid 52|1 = 1 (byte 6 = 0x13).
  CanInput in = crawler_input();
  in.feed(raw_frame(0x120, false, {0xE8, 0x03, 0x00, 0x00, 0xDC, 0x05, 0x13, 0x00}));
  EXPECT_EQ(in.dbc_count("WheelEncoderLeft"), 1u);
  const auto& l = in.last_wheel(wheel::Wheel::kLeft);
  ASSERT_TRUE(l.has_value());
  EXPECT_EQ(l->ticks, 1000u);
  EXPECT_NEAR(l->omega, 1.5, 1e-9);
  EXPECT_EQ(l->counter, 3);
  EXPECT_TRUE(l->valid);
  EXPECT_FALSE(in.last_wheel(wheel::Wheel::kRight).has_value());
}

TEST(NavdCanInput, WheelFrameShorterThanTheDbcIsRejected) {
  CanInput in = crawler_input();
  in.feed(raw_frame(0x121, false, {0xE8, 0x03, 0x00}));  // DBC says 8 bytes
  can::Frame empty = raw_frame(0x120, false, {});
  in.feed(empty);
  EXPECT_EQ(in.rejects().dbc, 2u);
  EXPECT_EQ(in.dbc_count("WheelEncoderLeft") + in.dbc_count("WheelEncoderRight"), 0u);
  EXPECT_FALSE(in.last_wheel(wheel::Wheel::kRight).has_value());
}

TEST(NavdCanInput, DbcThatDisagreesWithTheCodeIsRefused) {
  std::string text = crawler_text();
  const std::string from = "SG_ TickCount : 0|32@1+";
  const auto at = text.find(from);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, from.size(), "SG_ TickCount : 0|16@1+");
  auto db = dbc::parse(text, "crawler-16bit.dbc");
  ASSERT_TRUE(db.has_value()) << db.error().detail;
  const auto in = CanInput::with_dbc(std::move(*db));
  ASSERT_FALSE(in.has_value());
  EXPECT_NE(in.error().detail.find("TickCount"), std::string::npos) << in.error().detail;
  EXPECT_NE(in.error().detail.find("WheelEncoderLeft"), std::string::npos) << in.error().detail;
}

TEST(NavdCanInput, DbcWithoutWheelEncodersDecodesItsOwnMessages) {
  const std::string text =
      "VERSION \"\"\n\nBS_:\n\nBU_: BMS NAVD\n\n"
      "BO_ 512 Battery: 2 BMS\n"
      " SG_ Voltage : 0|16@1+ (0.01,0) [0|655.35] \"V\" NAVD\n\n"
      "BO_ 2147484160 BatteryExt: 1 BMS\n"
      " SG_ Soc : 0|8@1+ (1,0) [0|100] \"%\" NAVD\n";
  auto db = dbc::parse(text, "battery.dbc");
  ASSERT_TRUE(db.has_value()) << db.error().detail;
  auto in = CanInput::with_dbc(std::move(*db));
  ASSERT_TRUE(in.has_value()) << in.error().detail;
  in->feed(raw_frame(512, false, {0x10, 0x27}));
  in->feed(raw_frame(512, false, {0x10}));  // shorter than its DLC
  in->feed(raw_frame(512, true, {0x55}));   // 29-bit id 512: BatteryExt, not Battery
  in->feed(raw_frame(512, true, {0x42, 0x01}));  // longer than its DLC: decoded
  in->feed(raw_frame(0x120, false, {0, 0, 0, 0, 0, 0, 0, 0}));  // no wheel in this DBC
  EXPECT_EQ(in->dbc_count("Battery"), 1u);
  EXPECT_EQ(in->dbc_count("BatteryExt"), 2u);
  EXPECT_EQ(in->rejects().dbc, 1u);
  EXPECT_EQ(in->rejects().unknown_id, 1u);
  EXPECT_FALSE(in->last_wheel(wheel::Wheel::kLeft).has_value());
  EXPECT_NE(in->counters_text().find("dbc{Battery=1,BatteryExt=2}"), std::string::npos)
      << in->counters_text();
}

TEST(NavdCanInput, CountersText) {
  CanInput none;
  EXPECT_EQ(none.counters_text(),
            "frames=0 n2k{127250=0,127251=0,127257=0,128259=0,128267=0,129025=0,129026=0,"
            "129029=0,other=0} dbc{} rejects{unknown_id=0,rtr=0,error_frames=0,fields=0,"
            "fast_packet=0,fast_packet_dup=0,dbc=0} errors{bus_off=0,restarted=0,protocol=0,"
            "controller=0,rx_errors=0}");
  CanInput in = crawler_input();
  in.feed(raw_frame(0x09F11201, true, {0x00, 0x5C, 0x3D, 0xFF, 0x7F, 0xFF, 0x7F, 0xFC}));
  in.feed(raw_frame(0x120, false, {0xE8, 0x03, 0x00, 0x00, 0xDC, 0x05, 0x13, 0x00}));
  in.feed(raw_frame(0x7FF, false, {}));
  EXPECT_EQ(in.counters_text(),
            "frames=3 n2k{127250=1,127251=0,127257=0,128259=0,128267=0,129025=0,129026=0,"
            "129029=0,other=0} dbc{WheelEncoderLeft=1,WheelEncoderRight=0} "
            "rejects{unknown_id=1,rtr=0,error_frames=0,fields=0,fast_packet=0,"
            "fast_packet_dup=0,dbc=0} errors{bus_off=0,restarted=0,protocol=0,controller=0,"
            "rx_errors=0}");
}

// What a Linux controller driver reports (linux/can/error.h), as the bench plays it on a
// virtual bus: a corrupted frame, error-passive, bus-off and the restart; counted, survived.
TEST(NavdCanInput, ErrorFramesAreCountedByClassAndBusOffUntilTheRestart) {
  namespace can = protocols::can;
  CanInput in;
  can::ErrorReport corrupted{can::kErrProtocol | can::kErrCounters, 0, can::kProtForm,
                             can::kProtLocCrcSequence, 0, 1};
  in.feed(can::error_frame(corrupted));
  can::ErrorReport passive{can::kErrController | can::kErrCounters, can::kCtrlRxPassive, 0, 0, 0,
                           128};
  in.feed(can::error_frame(passive));
  in.feed(can::error_frame({can::kErrBusOff | can::kErrController, 0, 0, 0, 0, 0}));
  EXPECT_TRUE(in.errors().bus_is_off);
  in.feed(can::error_frame({can::kErrRestarted | can::kErrController, can::kCtrlActive, 0, 0, 0,
                            0}));
  EXPECT_FALSE(in.errors().bus_is_off);
  EXPECT_EQ(in.errors().protocol, 1u);
  EXPECT_EQ(in.errors().controller, 3u);
  EXPECT_EQ(in.errors().bus_off, 1u);
  EXPECT_EQ(in.errors().restarted, 1u);
  EXPECT_EQ(in.errors().rx_errors, 128u);
  EXPECT_EQ(in.rejects().error_frames, 4u);
  EXPECT_EQ(in.frames(), 4u);
  // Data frames after the restart decode as before.
  in.feed(raw_frame(0x09F11201, true, {0x00, 0x5C, 0x3D, 0xFF, 0x7F, 0xFF, 0x7F, 0xFC}));
  EXPECT_EQ(in.n2k_count(protocols::n2k::kPgnVesselHeading), 1u);
  EXPECT_NE(in.counters_text().find(
                "errors{bus_off=1,restarted=1,protocol=1,controller=3,rx_errors=128}"),
            std::string::npos)
      << in.counters_text();
}

}  // namespace
}  // namespace nav::dut

// SPDX-License-Identifier: MIT
#include "nav/bench/decode.hpp"

#include <gtest/gtest.h>

#include "nav/protocols/microstrain_gx3.hpp"

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

TEST(Decode, BytesOfOnePortFromACapture) {
  const std::string cap = "(0.000100000) ahrs CB00\n(0.001000000) gps 2447\n(0.002000000) ahrs FF\n";
  const auto b = bytes_from_capture(cap, "ahrs");
  ASSERT_TRUE(b);
  EXPECT_EQ(*b, (protocols::Bytes{0xCB, 0x00, 0xFF}));
  EXPECT_FALSE(bytes_from_capture("(0.1) ahrs ABC\n", "ahrs"));
  const auto bad = bytes_from_capture("ahrs CB\n", "ahrs");
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().detail.find("line 1"), std::string::npos);
}

}  // namespace
}  // namespace nav::bench

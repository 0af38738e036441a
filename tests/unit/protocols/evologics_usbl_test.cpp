// SPDX-License-Identifier: MIT
// EvoLogics USBLLONG / USBLANGLES: the real data-mode line of protocols.md 6c, command-mode
// lines, a constructed USBLANGLES, malformed input, round trips and random bytes.
#include "nav/protocols/evologics_usbl.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <string_view>

#include "stream_drain.hpp"

namespace nav::protocols::evologics {
namespace {

using test_support::bytes_of;
using test_support::drain;
using test_support::random_rounds_missing_frame;

/// protocols.md 6c real example (a device capture quoted in public clients), with the CR LF
/// that ends every notification.
constexpr std::string_view kRealPayload =
    "USBLLONG,10446.991981,10446.534643,3,-0.0604,-1.0888,-0.5851,-0.4233,-1.0020,-0.5901,"
    "0.0063,0.0269,-0.3295,825,-36,77,1.2375";
const std::string kRealLine = "+++AT:124:" + std::string(kRealPayload) + "\r\n";

/// Constructed: accuracy -1 marks an invalid fix (evins special-cases -1.0).
constexpr std::string_view kAnglesPayload =
    "USBLANGLES,1234.567890,1234.123456,2,0.1000,-0.2000,1.5708,-0.3000,0.0100,-0.0200,"
    "3.1416,-40,120,-1.0000";

ParseResult<Notification> parse_text(std::string_view s) { return parse(bytes_of(s)); }

TEST(EvologicsUsbl, RealDataModeLineDecodes) {
  EXPECT_EQ(kRealPayload.size(), 124u);  // the <len> of the wrapper
  const auto r = parse_text(kRealLine);
  ASSERT_EQ(r.status, ParseStatus::kComplete) << r.error;
  EXPECT_EQ(r.consumed, kRealLine.size());
  EXPECT_EQ(r.message->framing, Framing::kDataMode);
  const auto* l = std::get_if<UsblLong>(&r.message->fix);
  ASSERT_NE(l, nullptr);
  EXPECT_DOUBLE_EQ(l->current_time_s, 10446.991981);
  EXPECT_DOUBLE_EQ(l->measurement_time_s, 10446.534643);
  EXPECT_EQ(l->remote_address, 3);
  EXPECT_DOUBLE_EQ(l->x_m, -0.0604);
  EXPECT_DOUBLE_EQ(l->y_m, -1.0888);
  EXPECT_DOUBLE_EQ(l->z_m, -0.5851);
  EXPECT_DOUBLE_EQ(l->e_m, -0.4233);
  EXPECT_DOUBLE_EQ(l->n_m, -1.0020);
  EXPECT_DOUBLE_EQ(l->u_m, -0.5901);
  EXPECT_DOUBLE_EQ(l->roll_rad, 0.0063);
  EXPECT_DOUBLE_EQ(l->pitch_rad, 0.0269);
  EXPECT_DOUBLE_EQ(l->yaw_rad, -0.3295);
  EXPECT_EQ(l->propagation_time_us, 825);
  EXPECT_EQ(l->rssi_db, -36);
  EXPECT_EQ(l->integrity, 77);
  EXPECT_DOUBLE_EQ(l->accuracy_m, 1.2375);
  // Consistency of the sample: |XYZ| and |ENU| agree (motion compensation rotates only),
  // and the slant range from the propagation time at c = 1500 m/s is of the same order.
  const double r_xyz = std::sqrt(l->x_m * l->x_m + l->y_m * l->y_m + l->z_m * l->z_m);
  const double r_enu = std::sqrt(l->e_m * l->e_m + l->n_m * l->n_m + l->u_m * l->u_m);
  EXPECT_NEAR(r_xyz, r_enu, 1e-3);
  EXPECT_NEAR(l->propagation_time_us * 1500.0 * 1e-6, r_xyz, 0.1);
}

TEST(EvologicsUsbl, EncodeReproducesRealLine) {
  const auto r = parse_text(kRealLine);
  ASSERT_EQ(r.status, ParseStatus::kComplete) << r.error;
  EXPECT_EQ(encode(*r.message), kRealLine);
  EXPECT_EQ(to_payload(r.message->fix), kRealPayload);
}

TEST(EvologicsUsbl, CommandModeLineDecodes) {
  const std::string line = std::string(kRealPayload) + "\r\n";
  const auto r = parse_text(line);
  ASSERT_EQ(r.status, ParseStatus::kComplete) << r.error;
  EXPECT_EQ(r.consumed, line.size());
  EXPECT_EQ(r.message->framing, Framing::kCommandMode);
  EXPECT_EQ(encode(*r.message), line);
  // Bare LF too.
  EXPECT_EQ(parse_text(std::string(kRealPayload) + "\n").status, ParseStatus::kComplete);
}

TEST(EvologicsUsbl, AnglesDecodeAndRoundTrip) {
  const auto fix = decode_payload(kAnglesPayload);
  ASSERT_TRUE(fix.has_value()) << fix.error().detail;
  const auto& a = std::get<UsblAngles>(*fix);
  EXPECT_DOUBLE_EQ(a.current_time_s, 1234.56789);
  EXPECT_EQ(a.remote_address, 2);
  EXPECT_DOUBLE_EQ(a.local_bearing_rad, 0.1);
  EXPECT_DOUBLE_EQ(a.local_elevation_rad, -0.2);
  EXPECT_DOUBLE_EQ(a.bearing_rad, 1.5708);
  EXPECT_DOUBLE_EQ(a.elevation_rad, -0.3);
  EXPECT_DOUBLE_EQ(a.yaw_rad, 3.1416);
  EXPECT_EQ(a.rssi_db, -40);
  EXPECT_EQ(a.integrity, 120);
  EXPECT_DOUBLE_EQ(a.accuracy_m, -1.0);
  EXPECT_EQ(to_payload(*fix), kAnglesPayload);
  const std::string line = encode(Notification{*fix, Framing::kDataMode});
  EXPECT_EQ(line, "+++AT:" + std::to_string(kAnglesPayload.size()) + ":" +
                      std::string(kAnglesPayload) + "\r\n");
  const auto r = parse_text(line);
  ASSERT_EQ(r.status, ParseStatus::kComplete) << r.error;
  EXPECT_EQ(encode(*r.message), line);
}

TEST(EvologicsUsbl, EveryPrefixNeedsMore) {
  EXPECT_EQ(parse({}).status, ParseStatus::kNeedMore);
  for (const std::string& text : {kRealLine, std::string(kRealPayload) + "\r\n"}) {
    for (std::size_t n = 1; n < text.size(); ++n) {
      const auto r = parse_text(std::string_view(text).substr(0, n));
      EXPECT_EQ(r.status, ParseStatus::kNeedMore) << n << " of " << text;
      EXPECT_EQ(r.consumed, 0u);
    }
  }
}

TEST(EvologicsUsbl, MalformedInputIsSkippedWithAReason) {
  struct Case {
    std::string text;
    std::size_t consumed;
    std::string error;
  };
  const std::string p(kRealPayload);
  const std::string short_payload = p.substr(0, p.rfind(','));  // 15 values
  const Case cases[] = {
      {"xx\r\n" + p + "\r\n", 4, "4 byte(s) that cannot start a notification"},
      {"+++AX:124:" + p + "\r\n", 1, "'+' does not start \"+++AT:\""},
      {"+++AT:12a:" + p + "\r\nUSBL", 136, "bad data-mode length field"},
      {"+++AT:0:\r\n", 10, "data-mode length 0 out of range"},
      {"+++AT:123:" + p + "\r\n", 136,
       "data-mode payload of 123 byte(s) is not followed by CR LF"},
      {"+++AT:" + std::to_string(short_payload.size()) + ":" + short_payload + "\r\n",
       short_payload.size() + 12, "USBLLONG has 15 values, needs 16"},
      {"RECVIM,5,1,2,ack,1234,-40,120,0.5,hello\r\n", 41, "unsupported notification 'RECVIM'"},
      {"USBLANGLES,1,2,3,4,5,6,7,8,9,10,x,12,13\r\n", 41,
       "USBLANGLES field rssi 'x' is not a number"},
      {"USBLANGLES,1,2,3.5,4,5,6,7,8,9,10,11,12,13\r\n", 44,
       "USBLANGLES field remote address '3.5' is not a number"},
      {"USBLLONG,1,2+++AT:1:X\r\n", 12, "line cut short by '+'"},
      {"USBL\rLONG\r\n", 5, "CR inside a line"},
      {"USBL\x01\r\n", 5, "non-printable byte at offset 4"},
  };
  for (const Case& c : cases) {
    const auto r = parse_text(c.text);
    EXPECT_EQ(r.status, ParseStatus::kMalformed) << c.text;
    EXPECT_EQ(r.consumed, c.consumed) << c.text;
    EXPECT_EQ(r.error, c.error) << c.text;
  }
  EXPECT_EQ(parse_text("+++AT:99999:").error, "bad data-mode length field");
  EXPECT_EQ(parse_text(std::string(kMaxPayload + 5, 'A')).error,
            "line longer than 512 characters");
}

TEST(EvologicsUsbl, StreamOfMixedNotifications) {
  const std::string stream = "OK\r\n" + kRealLine + "+++AT:5:RECVI\r\n" +
                             std::string(kAnglesPayload) + "\r\n" + kRealLine.substr(0, 40);
  const auto d = drain<Notification>(&parse, bytes_of(stream));
  ASSERT_EQ(d.messages.size(), 2u);
  EXPECT_EQ(d.offsets[0], 4u);
  EXPECT_TRUE(std::holds_alternative<UsblLong>(d.messages[0].fix));
  EXPECT_TRUE(std::holds_alternative<UsblAngles>(d.messages[1].fix));
  EXPECT_EQ(d.messages[1].framing, Framing::kCommandMode);
  EXPECT_EQ(d.errors, (std::vector<std::string>{"unsupported notification 'OK'",
                                                "unsupported notification 'RECVI'"}));
  EXPECT_EQ(d.leftover, 40u);
}

TEST(EvologicsUsbl, RoundTripOfQuantisedFixes) {
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<int> q(-40000, 40000);
  for (int k = 0; k < 300; ++k) {
    UsblLong l;
    l.current_time_s = 1e4 + k * 1.000001;
    l.measurement_time_s = l.current_time_s - 0.25;
    l.remote_address = k % 255;
    l.x_m = q(rng) / 1e4;
    l.n_m = q(rng) / 1e2;
    l.yaw_rad = q(rng) / 1e4;
    l.propagation_time_us = k * 1000;
    l.rssi_db = -(k % 90);
    l.integrity = k;
    l.accuracy_m = k / 16.0;
    const Framing f = k % 2 == 0 ? Framing::kDataMode : Framing::kCommandMode;
    const std::string line = encode(Notification{l, f});
    const auto r = parse_text(line);
    ASSERT_EQ(r.status, ParseStatus::kComplete) << line << r.error;
    EXPECT_EQ(r.message->framing, f);
    EXPECT_EQ(encode(*r.message), line);
    const auto& back = std::get<UsblLong>(r.message->fix);
    EXPECT_NEAR(back.current_time_s, l.current_time_s, 5e-7);
    EXPECT_DOUBLE_EQ(back.n_m, l.n_m);
    EXPECT_EQ(back.propagation_time_us, l.propagation_time_us);
  }
}

TEST(EvologicsUsbl, RelativeAttitudeExtension) {
  // navbench's NVBRELATT (an iUSBL's relative heading and pitch of the same ping).
  RelativeAttitude a;
  a.current_time_s = 12.6;
  a.measurement_time_s = 12.433;
  a.remote_address = 3;
  a.relative_heading_rad = -3.1;
  a.relative_pitch_rad = 0.0523;
  const std::string payload = "NVBRELATT,12.600000,12.433000,3,-3.1000,0.0523";
  EXPECT_EQ(to_payload(a), payload);
  EXPECT_EQ(header_of(UsblFix{a}), "NVBRELATT");
  const auto r = parse_text("+++AT:" + std::to_string(payload.size()) + ":" + payload + "\r\n");
  ASSERT_EQ(r.status, ParseStatus::kComplete) << r.error;
  const auto* back = std::get_if<RelativeAttitude>(&r.message->fix);
  ASSERT_NE(back, nullptr);
  EXPECT_EQ(back->remote_address, 3);
  EXPECT_DOUBLE_EQ(back->relative_heading_rad, -3.1);
  EXPECT_DOUBLE_EQ(back->measurement_time_s, 12.433);
  // Five values or nothing.
  EXPECT_FALSE(decode_payload("NVBRELATT,12.6,12.433,3,-3.1").has_value());
  EXPECT_FALSE(decode_payload("NVBRELATT,12.6,12.433,3,x,0.05").has_value());
}

TEST(EvologicsUsbl, RandomBytesKeepTheTriStateContract) {
  // '+' cuts a command-mode line short; a noise "+++AT:<len>:" that swallows the frame is
  // possible but rare, so a couple of misses are allowed.
  EXPECT_LE(random_rounds_missing_frame<Notification>(&parse, bytes_of(kRealLine),
                                                      bytes_of("+AT:\r\n,U0123456789"), 41),
            2);
}

}  // namespace
}  // namespace nav::protocols::evologics

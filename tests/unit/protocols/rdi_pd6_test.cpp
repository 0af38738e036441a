// SPDX-License-Identifier: MIT
// Teledyne RDI PD6 codec: the illustrative block of protocols.md 3c byte for byte, the bad
// velocity markers (-32768, V), zero-padded fields, round trips, malformed input, random bytes.
#include "nav/protocols/rdi_pd6.hpp"

#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "dvl_test_support.hpp"

namespace nav::protocols::rdi_pd6 {
namespace {

using test_support::drain;
using test_support::to_bytes;

/// protocols.md 3c illustrative block (spacing not verified against a capture).
const std::vector<std::string> kDocBlock = {
    ":SA, -1.23, +0.45,123.45",
    ":TS,24011512304512,35.0,+12.5,  10.0,1500.0,  0",
    ":BI,   +12,   -34,    +5,    +1,A",
    ":BS,   -34,   +12,    -5,A",
    ":BE,  +100,  -200,    +3,A",
    ":BD,      +12.34,      -56.78,       +0.12,  10.50,  0.20",
};

Line parse_line(const std::string& text) {
  const auto r = parse(to_bytes(text));
  EXPECT_EQ(r.status, ParseStatus::kComplete) << text << ": " << r.error;
  EXPECT_EQ(r.consumed, text.size()) << text;
  return r.message.value_or(Line{});
}

TEST(RdiPd6, DocBlockDecodes) {
  const auto sa = std::get<Attitude>(parse_line(kDocBlock[0] + "\r\n"));
  EXPECT_DOUBLE_EQ(sa.pitch_deg, -1.23);
  EXPECT_DOUBLE_EQ(sa.roll_deg, 0.45);
  EXPECT_DOUBLE_EQ(sa.heading_deg, 123.45);

  const auto ts = std::get<TimeAndScaling>(parse_line(kDocBlock[1] + "\r\n"));
  EXPECT_EQ(ts.year, 2024);
  EXPECT_EQ(ts.month, 1);
  EXPECT_EQ(ts.day, 15);
  EXPECT_EQ(ts.hour, 12);
  EXPECT_EQ(ts.minute, 30);
  EXPECT_EQ(ts.second, 45);
  EXPECT_EQ(ts.hundredths, 12);
  EXPECT_DOUBLE_EQ(ts.salinity_ppt, 35.0);
  EXPECT_DOUBLE_EQ(ts.temperature_degc, 12.5);
  EXPECT_DOUBLE_EQ(ts.depth_m, 10.0);
  EXPECT_DOUBLE_EQ(ts.sound_speed_mps, 1500.0);
  EXPECT_EQ(ts.bit_result, 0);
  EXPECT_FALSE(ts.leak.has_value());

  const auto bi = std::get<InstrumentVelocity>(parse_line(kDocBlock[2] + "\r\n"));
  EXPECT_EQ(bi.track, Track::kBottom);
  EXPECT_EQ(bi.xyze_mmps, (std::array<int, 4>{12, -34, 5, 1}));
  EXPECT_TRUE(bi.valid);
  const auto bs = std::get<ShipVelocity>(parse_line(kDocBlock[3] + "\r\n"));
  EXPECT_EQ(bs.transverse_mmps, -34);
  EXPECT_EQ(bs.longitudinal_mmps, 12);
  EXPECT_EQ(bs.normal_mmps, -5);
  const auto be = std::get<EarthVelocity>(parse_line(kDocBlock[4] + "\r\n"));
  EXPECT_EQ(be.east_mmps, 100);
  EXPECT_EQ(be.north_mmps, -200);
  EXPECT_EQ(be.up_mmps, 3);
  EXPECT_TRUE(be.valid);
  const auto bd = std::get<Distance>(parse_line(kDocBlock[5] + "\n"));
  EXPECT_EQ(bd.track, Track::kBottom);
  EXPECT_DOUBLE_EQ(bd.east_m, 12.34);
  EXPECT_DOUBLE_EQ(bd.north_m, -56.78);
  EXPECT_DOUBLE_EQ(bd.up_m, 0.12);
  EXPECT_DOUBLE_EQ(bd.range_m, 10.5);
  EXPECT_DOUBLE_EQ(bd.time_since_good_s, 0.2);
}

TEST(RdiPd6, EncodeReproducesTheDocBlockByteForByte) {
  for (const std::string& line : kDocBlock) {
    EXPECT_EQ(encode(parse_line(line + "\r\n")), line + "\r\n");
  }
}

TEST(RdiPd6, BadVelocitiesAreMinus32768AndV) {
  const std::string wi = ":WI,-32768,-32768,-32768,-32768,V";
  const auto v = std::get<InstrumentVelocity>(parse_line(wi + "\r\n"));
  EXPECT_EQ(v.track, Track::kWater);
  EXPECT_FALSE(v.valid);
  for (const int x : v.xyze_mmps) EXPECT_FALSE(to_mps(x).has_value());
  EXPECT_EQ(encode(v), wi + "\r\n");
  EXPECT_EQ(encode(EarthVelocity{Track::kBottom, kBadVelocity, kBadVelocity, kBadVelocity, false}),
            ":BE,-32768,-32768,-32768,V\r\n");
  ASSERT_TRUE(to_mps(-1234).has_value());
  EXPECT_DOUBLE_EQ(*to_mps(-1234), -1.234);
}

TEST(RdiPd6, WaterTrackLinesAndLeakFlagRoundTrip) {
  const std::vector<Line> lines = {
      InstrumentVelocity{Track::kWater, {250, -13, 0, 7}, true},
      ShipVelocity{Track::kWater, -13, 250, 0, true},
      EarthVelocity{Track::kWater, 99999, -99999, 0, false},
      Distance{Track::kWater, -123456.78, 0.0, 99999999.99, 12.34, 999.99},
      Attitude{-89.99, 179.5, 359.99},
      TimeAndScaling{1999, 12, 31, 23, 59, 60, 99, 0.0, -2.5, 6000.0, 1412.3, 123, 'W'},
  };
  const std::vector<std::string> expected = {
      ":WI,  +250,   -13,    +0,    +7,A\r\n",
      ":WS,   -13,  +250,    +0,A\r\n",
      ":WE,+99999,-99999,    +0,V\r\n",
      ":WD,  -123456.78,       +0.00,+99999999.99,  12.34,999.99\r\n",
      ":SA,-89.99,+179.50,359.99\r\n",
      ":TS,99123123596099, 0.0, -2.5,6000.0,1412.3,123,W\r\n",
  };
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string text = encode(lines[i]);
    EXPECT_EQ(text, expected[i]);
    EXPECT_EQ(encode(parse_line(text)), text);
  }
  const auto ts = std::get<TimeAndScaling>(parse_line(expected[5]));
  EXPECT_EQ(ts.year, 1999);
  EXPECT_EQ(ts.leak, 'W');
}

TEST(RdiPd6, ZeroPaddedFieldsParse) {
  // Zero padding, as some DVLs emulating PD6 print it; the parser trims and reads the value.
  const auto bi = std::get<InstrumentVelocity>(parse_line(":BI,+00000,-02345,-00439,+00000,A\r\n"));
  EXPECT_EQ(bi.xyze_mmps, (std::array<int, 4>{0, -2345, -439, 0}));
  const auto bd = std::get<Distance>(
      parse_line(":BD,+00000000.00,+00000000.00,+00000000.00,0000.40,000.00\r\n"));
  EXPECT_DOUBLE_EQ(bd.range_m, 0.4);
}

TEST(RdiPd6, MalformedLinesSayWhy) {
  const auto check = [](const std::string& text, std::size_t consumed, const std::string& why) {
    const auto r = parse(to_bytes(text));
    EXPECT_EQ(r.status, ParseStatus::kMalformed) << text;
    EXPECT_EQ(r.consumed, consumed) << text;
    EXPECT_EQ(r.error, why) << text;
  };
  // Whole lines: consumed through the LF.
  const auto line = [&check](const std::string& text, const std::string& why) {
    check(text, text.size(), why);
  };
  line(":HM,G,G,1234,5678,12.345,1.234,12.345\r\n", "unsupported line ':HM'");
  line(":BI,   +12,   -34,    +5,A\r\n", ":BI has 4 fields, needs 5");
  line(":BI,   +12,   -34,    +5,    +1,X\r\n", ":BI field 5 'X' is not status A or V");
  line(":BE,  +1.5,  -200,    +3,A\n", ":BE field 1 '1.5' is not an integer in range");
  line(":SA, -1.23,+-0.45,123.45\r\n", ":SA field 2 '+-0.45' is not a number");
  line(":TS,24011532304512,35.0,+12.5,  10.0,1500.0,  0\r\n",
       ":TS field 1 '24011532304512' is not a time YYMMDDHHmmsshh");
  check("xx:BI", 2, "2 byte(s) before ':'");
  check(":BI,   +12:BS", 10, "line cut short by a new ':' after 10 byte(s)");
  check(":BS,\x7f", 5, "non-printable byte at offset 4");
}

TEST(RdiPd6, EveryPrefixNeedsMore) {
  const Bytes line = to_bytes(kDocBlock[5] + "\r\n");
  for (std::size_t n = 0; n < line.size(); ++n) {
    EXPECT_EQ(parse(ByteSpan(line).first(n)).status, ParseStatus::kNeedMore) << n;
  }
}

TEST(RdiPd6, RandomBytesNeverStallAndSplicedBlocksAreFound) {
  std::mt19937_64 rng(6);
  std::string block;
  for (const std::string& line : kDocBlock) block += line + "\r\n";
  const char alphabet[] = ":BSIETD,+-0123456789. AV\r\n\x03\xfe";
  for (int round = 0; round < 2000; ++round) {
    Bytes buf(rng() % 200);
    for (auto& b : buf) b = static_cast<std::uint8_t>(alphabet[rng() % (sizeof alphabet - 1)]);
    const std::size_t at = rng() % (buf.size() + 1);
    buf.insert(buf.begin() + static_cast<std::ptrdiff_t>(at), block.begin(), block.end());
    const auto d = drain<Line>(buf, parse);
    // A ':' ends any line, so the block's six lines always decode, at their own offsets.
    std::size_t found = 0;
    std::size_t expect_at = at;
    for (const std::size_t off : d.offsets) {
      if (off == expect_at && found < kDocBlock.size()) expect_at += kDocBlock[found++].size() + 2;
    }
    EXPECT_EQ(found, kDocBlock.size()) << "round " << round;
    EXPECT_LE(d.leftover, kMaxLine);
  }
}

}  // namespace
}  // namespace nav::protocols::rdi_pd6

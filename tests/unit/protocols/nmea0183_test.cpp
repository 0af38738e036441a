// SPDX-License-Identifier: MIT
// NMEA 0183 framing, GGA/RMC and UtcTime: the verified examples of protocols.md section 4,
// round trips and malformed input. Real receiver logs are in nmea0183_logs_test.cpp.
#include "nav/protocols/nmea0183.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <ctime>
#include <limits>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "nav/common/ensure.hpp"

namespace nav::protocols::nmea {
namespace {

Bytes to_bytes(std::string_view s) { return Bytes(s.begin(), s.end()); }

ParseResult<Sentence> parse_text(std::string_view s) { return parse(to_bytes(s)); }

Sentence parse_ok(std::string_view s) {
  const auto r = parse_text(s);
  EXPECT_EQ(r.status, ParseStatus::kComplete) << s << ": " << r.error;
  EXPECT_EQ(r.consumed, s.size()) << s;
  return r.message.value_or(Sentence{});
}

// protocols.md section 4, "Example (verified)" lines.
constexpr std::string_view kGga =
    "$GNGGA,001043.00,4404.14036,N,12118.85961,W,1,12,0.98,1113.0,M,-21.3,M*47\r\n";
constexpr std::string_view kRmc =
    "$GNRMC,001031.00,A,4404.13993,N,12118.86023,W,0.146,,100117,,,A*7B\r\n";

TEST(NmeaChecksum, MatchesEveryVerifiedExample) {
  const std::vector<std::pair<std::string_view, std::uint8_t>> cases = {
      {"GNGGA,001043.00,4404.14036,N,12118.85961,W,1,12,0.98,1113.0,M,-21.3,M", 0x47},
      {"GNRMC,001031.00,A,4404.13993,N,12118.86023,W,0.146,,100117,,,A", 0x7B},
      {"GPHDT,274.07,T", 0x03},
      {"HEHDT,341.8,T", 0x21},
      {"INHDT,161.98,T", 0x12},
      {"GPVTG,220.86,T,,M,2.550,N,4.724,K,A", 0x34},
      {"GPZDA,160012.71,11,03,2004,-1,00", 0x7D},
  };
  for (const auto& [body, expected] : cases) EXPECT_EQ(checksum(body), expected) << body;
}

TEST(NmeaParse, SplitsAddressAndFields) {
  const Sentence s = parse_ok(kGga);
  EXPECT_EQ(s.talker, "GN");
  EXPECT_EQ(s.type, "GGA");
  const std::vector<std::string> fields = {"001043.00", "4404.14036", "N",     "12118.85961",
                                           "W",         "1",          "12",    "0.98",
                                           "1113.0",    "M",          "-21.3", "M"};
  EXPECT_EQ(s.fields, fields);

  const Sentence hdt = parse_ok("$INHDT,161.98,T*12\r\n");
  EXPECT_EQ(hdt.talker, "IN");
  EXPECT_EQ(hdt.type, "HDT");
  EXPECT_EQ(hdt.fields, (std::vector<std::string>{"161.98", "T"}));
}

TEST(NmeaParse, ProprietaryTalkerIsP) {
  const Sentence s = parse_ok("$PGRME,7.6,M,41.7,M,42.4,M*2F\r\n");  // Garmin, from garmin15x.log
  EXPECT_EQ(s.talker, "P");
  EXPECT_EQ(s.type, "GRME");
  EXPECT_EQ(s.fields.size(), 6u);
}

TEST(NmeaParse, EmptyFieldsAreKept) {
  const Sentence s = parse_ok(kRmc);
  ASSERT_EQ(s.fields.size(), 12u);
  EXPECT_EQ(s.fields[7], "");
  EXPECT_EQ(s.fields[9], "");
  EXPECT_EQ(s.fields[10], "");
  EXPECT_EQ(s.fields[11], "A");
}

TEST(NmeaParse, AcceptsBareLfLowerCaseHexAndCrCrLf) {
  EXPECT_EQ(parse_ok("$GPHDT,274.07,T*03\n").fields[0], "274.07");
  EXPECT_EQ(parse_ok("$GPZDA,160012.71,11,03,2004,-1,00*7d\r\n").type, "ZDA");  // gpsd: any case
  EXPECT_EQ(parse_ok("$GPHDT,274.07,T*03\r\r\n").type, "HDT");
}

TEST(NmeaParse, NeedsMoreUntilLineEnd) {
  EXPECT_EQ(parse({}).status, ParseStatus::kNeedMore);
  const std::string line(kGga);
  for (std::size_t n = 1; n < line.size(); ++n) {
    const auto r = parse_text(std::string_view(line).substr(0, n));
    EXPECT_EQ(r.status, ParseStatus::kNeedMore) << n;
    EXPECT_EQ(r.consumed, 0u);
  }
}

TEST(NmeaParse, ConsumesExactlyOneSentence) {
  const std::string two = std::string(kGga) + std::string(kRmc);
  const auto r = parse_text(two);
  ASSERT_EQ(r.status, ParseStatus::kComplete);
  EXPECT_EQ(r.consumed, kGga.size());
  const auto r2 = parse_text(std::string_view(two).substr(r.consumed));
  ASSERT_EQ(r2.status, ParseStatus::kComplete);
  EXPECT_EQ(r2.message->type, "RMC");
}

TEST(NmeaParse, BadChecksumIsMalformedConsumingTheLine) {
  const auto r = parse_text("$GPHDT,274.07,T*04\r\n$GPHDT,274.07,T*03\r\n");
  EXPECT_EQ(r.status, ParseStatus::kMalformed);
  EXPECT_EQ(r.consumed, 20u);
  EXPECT_EQ(r.error, "checksum 0x04 != computed 0x03");
  // A corrupted field is caught the same way.
  EXPECT_EQ(parse_text("$GPHDT,275.07,T*03\r\n").status, ParseStatus::kMalformed);
}

TEST(NmeaParse, MissingChecksumIsMalformed) {
  for (const std::string_view s : {"$GPHDT,274.07,T\r\n", "$GPHDT,274.07,T*\r\n",
                                   "$GPHDT,274.07,T*0\r\n", "$GPHDT,274.07,T*0G\r\n"}) {
    const auto r = parse_text(s);
    EXPECT_EQ(r.status, ParseStatus::kMalformed) << s;
    EXPECT_EQ(r.consumed, s.size()) << s;
    EXPECT_EQ(r.error, "missing checksum '*hh'") << s;
  }
}

TEST(NmeaParse, GarbagePrefixIsSkippedToDollar) {
  using namespace std::string_view_literals;
  const auto r = parse_text("\xFF\x00noise$GPHDT,274.07,T*03\r\n"sv);
  EXPECT_EQ(r.status, ParseStatus::kMalformed);
  EXPECT_EQ(r.consumed, 7u);
  const auto all = parse_text("no dollar at all\r\n");
  EXPECT_EQ(all.status, ParseStatus::kMalformed);
  EXPECT_EQ(all.consumed, 18u);
}

TEST(NmeaParse, SentenceCutShortByNewDollarIsDroppedUpToIt) {
  const std::string s = "$GPGGA,1234" + std::string(kRmc);
  const auto r = parse_text(s);
  EXPECT_EQ(r.status, ParseStatus::kMalformed);
  EXPECT_EQ(r.consumed, 11u);
  EXPECT_EQ(parse_text(std::string_view(s).substr(r.consumed)).status, ParseStatus::kComplete);
}

TEST(NmeaParse, LengthLimitIsKMaxSentence) {
  // '$' through the checksum: kMaxSentence characters pass, one more does not.
  const auto make = [](std::size_t total) {
    std::string body = "PXYZ,";
    body.append(total - 4 - body.size(), 'A');  // '$' + body + "*hh" = total
    const std::uint8_t c = checksum(body);
    static constexpr char kHex[] = "0123456789ABCDEF";
    return "$" + body + "*" + kHex[c >> 4] + kHex[c & 0xF] + "\r\n";
  };
  EXPECT_EQ(parse_text(make(kMaxSentence)).status, ParseStatus::kComplete);
  const std::string too_long = make(kMaxSentence + 1);
  const auto r = parse_text(too_long);
  EXPECT_EQ(r.status, ParseStatus::kMalformed);
  EXPECT_NE(r.error.find("longer"), std::string::npos);
  // Without a line end it is rejected as soon as the limit is passed, not kept waiting.
  const auto open = parse_text(std::string_view(too_long).substr(0, kMaxSentence + 1));
  EXPECT_EQ(open.status, ParseStatus::kMalformed);
  EXPECT_EQ(open.consumed, kMaxSentence + 1);
}

TEST(NmeaParse, ControlBytesAndBadAddressesAreMalformed) {
  EXPECT_EQ(parse_text("$GPHDT,27\x01"
                       "4.07,T*03\r\n")
                .status,
            ParseStatus::kMalformed);
  EXPECT_EQ(parse_text("$GPHDT,274.07,T\r*03\r\n").status, ParseStatus::kMalformed);
  for (const std::string_view body : {"GPHD,1", "gphdt,1", "P,1", ",1", "GPHDTX,1"}) {
    const std::uint8_t c = checksum(body);
    static constexpr char kHex[] = "0123456789ABCDEF";
    const std::string s = "$" + std::string(body) + "*" + kHex[c >> 4] + kHex[c & 0xF] + "\r\n";
    const auto r = parse_text(s);
    EXPECT_EQ(r.status, ParseStatus::kMalformed) << s;
    EXPECT_EQ(r.consumed, s.size()) << s;
  }
}

TEST(NmeaParse, RandomInputKeepsTheTriStateContract) {
  // Random bytes mixed with pieces of valid sentences (fixed seed): every result is one of
  // the three states with a consistent `consumed`, and a reader loop always progresses.
  std::mt19937_64 rng(20240601);
  const std::string pieces = std::string(kGga) + std::string(kRmc) + "$PNVBSOL,*,\r\n";
  std::size_t complete = 0, malformed_count = 0;
  for (int round = 0; round < 3000; ++round) {
    Bytes buf(rng() % 200);
    for (auto& b : buf) {
      b = rng() % 3 == 0 ? static_cast<std::uint8_t>(rng())
                         : static_cast<std::uint8_t>(pieces[rng() % pieces.size()]);
    }
    if (rng() % 2 == 0) {  // splice in a whole valid sentence
      const std::size_t at = buf.empty() ? 0 : rng() % buf.size();
      buf.insert(buf.begin() + static_cast<std::ptrdiff_t>(at), kRmc.begin(), kRmc.end());
    }
    std::size_t pos = 0;
    while (pos < buf.size()) {
      const auto r = parse(ByteSpan(buf).subspan(pos));
      if (r.status == ParseStatus::kNeedMore) {
        EXPECT_EQ(r.consumed, 0u);
        EXPECT_EQ(buf[pos], '$');
        break;
      }
      ASSERT_GT(r.consumed, 0u);
      ASSERT_LE(r.consumed, buf.size() - pos);
      if (r.status == ParseStatus::kComplete) {
        ++complete;
        EXPECT_TRUE(r.message.has_value());
      } else {
        ++malformed_count;
        EXPECT_FALSE(r.error.empty());
      }
      pos += r.consumed;
    }
  }
  EXPECT_GT(complete, 1000u);  // the spliced sentences are found again
  EXPECT_GT(malformed_count, 1000u);
}

TEST(NmeaFrame, UpperCaseHexAndCrlf) {
  EXPECT_EQ(frame({"GP", "HDT", {"274.07", "T"}}), "$GPHDT,274.07,T*03\r\n");
  EXPECT_EQ(frame({"GP", "ZDA", {"160012.71", "11", "03", "2004", "-1", "00"}}),
            "$GPZDA,160012.71,11,03,2004,-1,00*7D\r\n");
  EXPECT_EQ(frame({"P", "GRME", {"7.6", "M", "41.7", "M", "42.4", "M"}}),
            "$PGRME,7.6,M,41.7,M,42.4,M*2F\r\n");
  // frame(parse(x)) reproduces x.
  EXPECT_EQ(frame(parse_ok(kRmc)), kRmc);
}

TEST(NmeaFrame, DelimiterInsideAFieldIsAContractViolation) {
  struct Violation {};
  const auto previous = set_ensure_handler(
      [](const char*, int, const char*, const std::string&) { throw Violation{}; });
  EXPECT_THROW(frame({"GP", "TXT", {"a,b"}}), Violation);
  EXPECT_THROW(frame({"GP", "TXT", {"a*b"}}), Violation);
  EXPECT_THROW(frame({"GP", "TXT", {"ok", "$b"}}), Violation);
  EXPECT_THROW(frame({"GP", "TXT", {"a\r"}}), Violation);
  EXPECT_THROW(frame({"GP", "TXT", {"\n"}}), Violation);
  EXPECT_EQ(frame({"GP", "TXT", {"a b-c.d_e"}}).substr(0, 16), "$GPTXT,a b-c.d_e");
  set_ensure_handler(previous);
}

TEST(NmeaGga, DecodesVerifiedExample) {
  const auto g = decode_gga(parse_ok(kGga));
  ASSERT_TRUE(g) << g.error().detail;
  EXPECT_EQ(g->time.hour, 0);
  EXPECT_EQ(g->time.minute, 10);
  EXPECT_DOUBLE_EQ(g->time.second, 43.0);
  EXPECT_NEAR(*g->lat_deg, 44.0 + 4.14036 / 60.0, 1e-12);
  EXPECT_NEAR(*g->lon_deg, -(121.0 + 18.85961 / 60.0), 1e-12);
  EXPECT_EQ(g->quality, 1);
  EXPECT_EQ(g->satellites, 12);
  EXPECT_DOUBLE_EQ(*g->hdop, 0.98);
  EXPECT_DOUBLE_EQ(*g->alt_msl_m, 1113.0);
  EXPECT_DOUBLE_EQ(*g->geoid_sep_m, -21.3);
}

TEST(NmeaGga, ReencodesVerifiedExample) {
  // Our GGA always carries the last two fields (DGPS age, station), empty; the example
  // stops after the geoid unit. The first twelve fields match text for text, and the
  // checksum is unchanged because two extra commas XOR to zero.
  const Sentence original = parse_ok(kGga);
  const Sentence ours = to_sentence(*decode_gga(original), "GN");
  ASSERT_EQ(ours.fields.size(), 14u);
  EXPECT_EQ(std::vector<std::string>(ours.fields.begin(), ours.fields.begin() + 12),
            original.fields);
  EXPECT_EQ(frame(ours),
            "$GNGGA,001043.00,4404.14036,N,12118.85961,W,1,12,0.98,1113.0,M,-21.3,M,,*47\r\n");
}

TEST(NmeaGga, NoFixLooksLikeAReceiverWithoutFix) {
  Gga g;
  g.time = {0, 0, 0, 23, 59, 59.99};
  g.quality = 0;
  g.lat_deg = 10.0;  // ignored without a fix
  g.lon_deg = 20.0;
  g.hdop = 1.0;
  g.alt_msl_m = 5.0;
  EXPECT_EQ(frame(to_sentence(g)), "$GPGGA,235959.99,,,,,0,00,,,,,,,*49\r\n");
  const auto d = decode_gga(to_sentence(g));
  ASSERT_TRUE(d) << d.error().detail;
  EXPECT_EQ(d->quality, 0);
  EXPECT_FALSE(d->lat_deg || d->lon_deg || d->hdop || d->alt_msl_m || d->geoid_sep_m);
}

TEST(NmeaGga, RoundTripKeepsFiveDecimalsOfMinutes) {
  // Resolution 1e-5 arcmin = 1.67e-7 deg; rounding error at most half of that.
  const double kHalfStep = 0.5e-5 / 60.0 + 1e-12;
  for (const double lat : {0.0, 44.0690060, -33.8688197, 89.9999999, -0.00000001, 10.99999999}) {
    for (const double lon : {0.0, -121.3143268, 151.2092955, -179.9999999, 0.000001}) {
      Gga g;
      g.time = {0, 0, 0, 12, 34, 56.78};
      g.lat_deg = lat;
      g.lon_deg = lon;
      g.quality = 4;
      g.satellites = 7;
      g.hdop = 0.7;
      g.alt_msl_m = -12.3;
      g.geoid_sep_m = 17.0;
      const std::string text = frame(to_sentence(g));
      const auto d = decode_gga(parse_ok(text));
      ASSERT_TRUE(d) << text << ": " << d.error().detail;
      EXPECT_NEAR(*d->lat_deg, lat, kHalfStep) << text;
      EXPECT_NEAR(*d->lon_deg, lon, kHalfStep) << text;
      EXPECT_EQ(d->time.hour, 12);
      EXPECT_EQ(d->time.minute, 34);
      EXPECT_NEAR(d->time.second, 56.78, 1e-9);
      EXPECT_EQ(d->quality, 4);
      EXPECT_EQ(d->satellites, 7);
      EXPECT_NEAR(*d->alt_msl_m, -12.3, 1e-9);
    }
  }
  // 10.99999999 deg rounds up to 11 deg 00.00000', not "1060.00000".
  Gga carry;
  carry.lat_deg = 10.99999999;
  carry.lon_deg = -0.99999999;
  carry.quality = 1;
  const Sentence s = to_sentence(carry);
  EXPECT_EQ(s.fields[1], "1100.00000");
  EXPECT_EQ(s.fields[3], "00100.00000");
  EXPECT_EQ(s.fields[4], "W");
}

TEST(NmeaGga, BadFieldsAreNamed) {
  const auto with_field = [](std::size_t i, std::string v) {
    Sentence s = parse_ok(kGga);
    s.fields[i] = std::move(v);
    return decode_gga(s);
  };
  const auto expect_error = [](const Result<Gga>& r, std::string_view word) {
    ASSERT_FALSE(r);
    EXPECT_NE(r.error().detail.find(word), std::string::npos) << r.error().detail;
  };
  expect_error(with_field(0, "1x1043.00"), "time");
  expect_error(with_field(0, "251043.00"), "time");
  expect_error(with_field(1, "44O4.14036"), "latitude");
  expect_error(with_field(1, "4460.00000"), "latitude");
  expect_error(with_field(2, "E"), "latitude");
  expect_error(with_field(3, "18118.85961"), "longitude");
  expect_error(with_field(5, "x"), "quality");
  // Found by tests/fuzz (nmea0183): quality and satellites beyond their one and two digits
  // decoded, though to_sentence() refuses them by contract.
  expect_error(with_field(5, "92"), "quality");
  expect_error(with_field(5, "-1"), "quality");
  expect_error(with_field(6, "100"), "satellites");
  expect_error(with_field(6, "-3"), "satellites");
  expect_error(with_field(7, "0,98"), "hdop");
  expect_error(with_field(8, "nan"), "altitude");
  Sentence short_gga = parse_ok(kGga);
  short_gga.fields.resize(9);
  expect_error(decode_gga(short_gga), "fields");
  expect_error(decode_gga(parse_ok(kRmc)), "GGA");
}

TEST(NmeaRmc, DecodesAndReencodesVerifiedExampleByteExact) {
  const auto r = decode_rmc(parse_ok(kRmc));
  ASSERT_TRUE(r) << r.error().detail;
  EXPECT_TRUE(r->valid);
  EXPECT_NEAR(*r->lat_deg, 44.0 + 4.13993 / 60.0, 1e-12);
  EXPECT_NEAR(*r->lon_deg, -(121.0 + 18.86023 / 60.0), 1e-12);
  EXPECT_DOUBLE_EQ(*r->sog_kn, 0.146);
  EXPECT_FALSE(r->cog_deg.has_value());
  EXPECT_EQ(r->time.year, 2017);
  EXPECT_EQ(r->time.month, 1);
  EXPECT_EQ(r->time.day, 10);
  EXPECT_EQ(r->mode, 'A');
  EXPECT_DOUBLE_EQ(r->time.unix_seconds(), 1484007031.0);  // 2017-01-10T00:10:31Z
  EXPECT_EQ(frame(to_sentence(*r, "GN")), kRmc);
}

TEST(NmeaRmc, RoundTripAndInvalidStatus) {
  Rmc r;
  r.time = UtcTime::from_unix_seconds(1709208000.25);  // 2024-02-29T12:00:00.25Z
  r.valid = true;
  r.lat_deg = -45.5;
  r.lon_deg = 170.25;
  r.sog_kn = 12.3456;
  r.cog_deg = 359.994;
  r.mode = 'D';
  const Sentence s = to_sentence(r);
  // Checksum 0x40 computed independently (Python XOR over the body).
  EXPECT_EQ(frame(s),
            "$GPRMC,120000.25,A,4530.00000,S,17015.00000,E,12.346,359.99,290224,,,D*40\r\n");
  const auto d = decode_rmc(parse_ok(frame(s)));
  ASSERT_TRUE(d) << d.error().detail;
  EXPECT_DOUBLE_EQ(d->time.unix_seconds(), 1709208000.25);
  EXPECT_EQ(d->mode, 'D');

  Rmc none;
  none.valid = false;
  none.lat_deg = 1.0;  // a receiver without a fix sends no position
  none.mode = 'N';
  none.time = UtcTime::from_unix_seconds(946684800.0);  // 2000-01-01T00:00:00Z
  EXPECT_EQ(to_sentence(none).fields, (std::vector<std::string>{"000000.00", "V", "", "", "", "",
                                                                "", "", "010100", "", "", "N"}));
  const auto dn = decode_rmc(to_sentence(none));
  ASSERT_TRUE(dn);
  EXPECT_FALSE(dn->valid);
  EXPECT_FALSE(dn->lat_deg.has_value());
  EXPECT_EQ(dn->time.year, 2000);
}

TEST(NmeaRmc, OldRmcWithoutModeAndBadFields) {
  // NMEA 2.2 (Garmin 15x): no mode field, whole seconds, magnetic variation present.
  const auto r = decode_rmc(
      parse_ok("$GPRMC,113258,A,3238.9148,N,10822.4466,W,005.3,247.1,181022,009.3,E*6B\r\n"));
  ASSERT_TRUE(r) << r.error().detail;
  EXPECT_EQ(r->mode, 'A');
  EXPECT_DOUBLE_EQ(r->time.second, 58.0);
  EXPECT_DOUBLE_EQ(*r->sog_kn, 5.3);
  EXPECT_DOUBLE_EQ(r->time.unix_seconds(), 1666092778.0);  // 2022-10-18T11:32:58Z

  Sentence s = parse_ok(kRmc);
  s.fields[1] = "X";
  ASSERT_FALSE(decode_rmc(s));
  EXPECT_NE(decode_rmc(s).error().detail.find("status"), std::string::npos);
  s = parse_ok(kRmc);
  s.fields[8] = "320117";
  ASSERT_FALSE(decode_rmc(s));
  EXPECT_NE(decode_rmc(s).error().detail.find("date"), std::string::npos);
  s = parse_ok(kRmc);
  s.fields[6] = "fast";
  ASSERT_FALSE(decode_rmc(s));
  EXPECT_NE(decode_rmc(s).error().detail.find("speed"), std::string::npos);
}

TEST(UtcTime, UnixSecondsOfKnownDates) {
  EXPECT_DOUBLE_EQ((UtcTime{1970, 1, 1, 0, 0, 0.0}).unix_seconds(), 0.0);
  EXPECT_DOUBLE_EQ((UtcTime{2000, 3, 1, 0, 0, 0.0}).unix_seconds(), 951868800.0);
  EXPECT_DOUBLE_EQ((UtcTime{2024, 2, 29, 12, 0, 0.0}).unix_seconds(), 1709208000.0);
  EXPECT_DOUBLE_EQ((UtcTime{1969, 12, 31, 23, 59, 59.0}).unix_seconds(), -1.0);
  EXPECT_DOUBLE_EQ((UtcTime{2038, 1, 19, 3, 14, 8.5}).unix_seconds(), 2147483648.5);
}

TEST(UtcTime, FromUnixSecondsRoundTripsAndRoundsToCentiseconds) {
  for (double s = -86400.0 * 800; s < 86400.0 * 30000; s += 86400.0 * 97.3 + 0.37) {
    const double cs = std::round(s * 100.0) / 100.0;
    const UtcTime t = UtcTime::from_unix_seconds(s);
    EXPECT_NEAR(t.unix_seconds(), cs, 1e-6) << s;
    EXPECT_GE(t.month, 1);
    EXPECT_LE(t.day, 31);
  }
  const UtcTime t = UtcTime::from_unix_seconds(59.996);  // rounds into the next minute
  EXPECT_EQ(t.minute, 1);
  EXPECT_DOUBLE_EQ(t.second, 0.0);
  const UtcTime leap = UtcTime::from_unix_seconds(951782400.0);  // 2000-02-29
  EXPECT_EQ(leap.month, 2);
  EXPECT_EQ(leap.day, 29);
}

TEST(UtcTime, IndependentOfTimeZone) {
  const char* old = std::getenv("TZ");
  const std::string saved = old ? old : "";
  ::setenv("TZ", "America/New_York", 1);
  ::tzset();
  const double s = (UtcTime{2017, 1, 10, 0, 10, 31.0}).unix_seconds();
  const UtcTime t = UtcTime::from_unix_seconds(s);
  if (old)
    ::setenv("TZ", saved.c_str(), 1);
  else
    ::unsetenv("TZ");
  ::tzset();
  EXPECT_DOUBLE_EQ(s, 1484007031.0);
  EXPECT_EQ(t.hour, 0);
  EXPECT_EQ(t.day, 10);
}

TEST(NmeaText, FormatAndParseNumbers) {
  EXPECT_EQ(format_fixed(-0.00001, 4), "0.0000");
  EXPECT_EQ(format_fixed(-1.25, 1), "-1.2");  // round-half-even of the exact binary value
  EXPECT_EQ(format_fixed(1113.0, 1), "1113.0");
  EXPECT_EQ(parse_number("-21.3"), -21.3);
  EXPECT_FALSE(parse_number(""));
  EXPECT_FALSE(parse_number("1.5x"));
  EXPECT_FALSE(parse_number("0,98"));
  EXPECT_FALSE(parse_number("inf"));
  EXPECT_FALSE(parse_number("nan"));
}

// Found by tests/fuzz (ebimu, evologics_usbl): format_fixed aborted ("value too large for the
// buffer") on finite values from about 1e46 up, which parse_number accepts ("1e300"); navd's
// $PNVBSOL goes through it too, so a diverging filter would have aborted navd.
TEST(NmeaText, FormatFixedOfTheLargestFiniteValues) {
  const std::string big = format_fixed(1e300, 2);
  EXPECT_EQ(big.size(), 301u + 3u);
  EXPECT_EQ(big.substr(0, 2), "10");
  EXPECT_EQ(big.substr(big.size() - 3), ".00");
  const std::string lowest = format_fixed(-std::numeric_limits<double>::max(), 17);
  EXPECT_EQ(lowest.size(), 1u + 309u + 1u + 17u);
  EXPECT_EQ(parse_number(lowest), -std::numeric_limits<double>::max());
}

}  // namespace
}  // namespace nav::protocols::nmea

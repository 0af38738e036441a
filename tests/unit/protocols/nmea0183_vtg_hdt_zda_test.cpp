// SPDX-License-Identifier: MIT
// NMEA 0183 VTG, HDT and ZDA: the verified examples of protocols.md section 4 (exact sentences
// and checksums), the old VTG form, malformed fields, round trips and random bytes.
// Checksums of the sentences that are not in protocols.md were computed outside this code
// (Python XOR over the body).
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <string_view>

#include "nav/common/ensure.hpp"
#include "nav/protocols/nmea0183.hpp"
#include "stream_drain.hpp"

namespace nav::protocols::nmea {
namespace {

using test_support::bytes_of;
using test_support::random_rounds_missing_frame;

Sentence parse_ok(std::string_view s) {
  const auto r = parse(bytes_of(s));
  EXPECT_EQ(r.status, ParseStatus::kComplete) << s << ": " << r.error;
  EXPECT_EQ(r.consumed, s.size()) << s;
  return r.message.value_or(Sentence{});
}

// protocols.md section 4, "Example (verified)".
constexpr std::string_view kVtg = "$GPVTG,220.86,T,,M,2.550,N,4.724,K,A*34\r\n";
constexpr std::string_view kZda = "$GPZDA,160012.71,11,03,2004,-1,00*7D\r\n";

TEST(NmeaVtg, DecodesVerifiedExample) {
  const auto v = decode_vtg(parse_ok(kVtg));
  ASSERT_TRUE(v.has_value()) << v.error().detail;
  EXPECT_DOUBLE_EQ(*v->cog_true_deg, 220.86);
  EXPECT_FALSE(v->cog_mag_deg.has_value());
  EXPECT_DOUBLE_EQ(*v->sog_kn, 2.55);
  EXPECT_DOUBLE_EQ(*v->sog_kmh, 4.724);
  EXPECT_EQ(v->mode, 'A');
}

TEST(NmeaVtg, ReencodesVerifiedExampleByteExact) {
  Vtg v;
  v.cog_true_deg = 220.86;
  v.sog_kn = 2.55;
  v.sog_kmh = 4.724;
  v.mode = 'A';
  EXPECT_EQ(frame(to_sentence(v)), kVtg);
  v.mode.reset();  // NMEA 2.0-2.2: unit letters, no mode field
  EXPECT_EQ(frame(to_sentence(v)), "$GPVTG,220.86,T,,M,2.550,N,4.724,K*59\r\n");
}

TEST(NmeaVtg, DecodesOldFormWithoutUnitLetters) {
  const auto v = decode_vtg(parse_ok("$GPVTG,054.7,034.4,005.5,010.2*54\r\n"));
  ASSERT_TRUE(v.has_value()) << v.error().detail;
  EXPECT_DOUBLE_EQ(*v->cog_true_deg, 54.7);
  EXPECT_DOUBLE_EQ(*v->cog_mag_deg, 34.4);
  EXPECT_DOUBLE_EQ(*v->sog_kn, 5.5);
  EXPECT_DOUBLE_EQ(*v->sog_kmh, 10.2);
  EXPECT_FALSE(v->mode.has_value());
}

TEST(NmeaVtg, ReceiverWithoutFix) {
  for (const std::string_view text :
       {"$GPVTG,,,,,,,,,N*30\r\n", "$GPVTG,,T,,M,0.000,N,0.000,K,N*2C\r\n"}) {
    const auto v = decode_vtg(parse_ok(text));
    ASSERT_TRUE(v.has_value()) << text << v.error().detail;
    EXPECT_FALSE(v->cog_true_deg.has_value()) << text;
    EXPECT_EQ(v->mode, 'N') << text;
  }
}

TEST(NmeaVtg, BadFieldsAreNamed) {
  const auto err = [](std::vector<std::string> fields) {
    const auto v = decode_vtg(Sentence{"GP", "VTG", std::move(fields)});
    EXPECT_FALSE(v.has_value());
    return v ? std::string{} : v.error().detail;
  };
  EXPECT_EQ(err({"1", "T", "2", "X", "3", "N", "4", "K", "A"}),
            "VTG field 4 'X' is not the unit letter 'M'");
  EXPECT_EQ(err({"1", "T", "2", "M", "3"}), "VTG with unit letters has 5 fields, needs 8");
  EXPECT_EQ(err({"1", "2", "3"}), "VTG has 3 fields, needs 4");
  EXPECT_EQ(err({"1", "2", "3", "4", "5"}), "old-form VTG has 5 fields, needs 4");
  EXPECT_EQ(err({"1", "2", "3", "x"}), "field speed km/h 'x' is not a number");
  EXPECT_EQ(err({"1", "T", "", "M", "fast", "N", "", "K"}),
            "field speed knots 'fast' is not a number");
  EXPECT_EQ(err({"1", "T", "", "M", "", "N", "", "K", "ab"}), "field mode 'ab'");
  EXPECT_FALSE(decode_vtg(Sentence{"GP", "HDT", {"1", "T"}}).has_value());
}

TEST(NmeaHdt, DecodesEveryVerifiedExample) {
  const std::pair<std::string_view, double> cases[] = {
      {"$GPHDT,274.07,T*03\r\n", 274.07},
      {"$HEHDT,341.8,T*21\r\n", 341.8},
      {"$INHDT,161.98,T*12\r\n", 161.98},
  };
  for (const auto& [text, deg] : cases) {
    const auto h = decode_hdt(parse_ok(text));
    ASSERT_TRUE(h.has_value()) << text << h.error().detail;
    EXPECT_DOUBLE_EQ(*h->heading_deg, deg) << text;
  }
}

TEST(NmeaHdt, ReencodesVerifiedExamplesByteExact) {
  EXPECT_EQ(frame(to_sentence(Hdt{274.07})), "$GPHDT,274.07,T*03\r\n");
  EXPECT_EQ(frame(to_sentence(Hdt{161.98}, "IN")), "$INHDT,161.98,T*12\r\n");
  // Two decimals always: the gyro's "341.8" is written "341.80".
  EXPECT_EQ(to_sentence(Hdt{341.8}, "HE").fields[0], "341.80");
}

TEST(NmeaHdt, WrapsIntoOneTurnAndKeepsEmptyHeading) {
  EXPECT_EQ(to_sentence(Hdt{-90.0}).fields[0], "270.00");
  EXPECT_EQ(to_sentence(Hdt{720.5}).fields[0], "0.50");
  EXPECT_EQ(to_sentence(Hdt{359.999}).fields[0], "0.00");
  EXPECT_EQ(to_sentence(Hdt{-0.001}).fields[0], "0.00");
  EXPECT_EQ(to_sentence(Hdt{}).fields, (std::vector<std::string>{"", "T"}));
  const auto empty = decode_hdt(Sentence{"HE", "HDT", {"", "T"}});
  ASSERT_TRUE(empty.has_value());
  EXPECT_FALSE(empty->heading_deg.has_value());
  const auto full_turn = decode_hdt(Sentence{"HE", "HDT", {"360.0", "T"}});
  ASSERT_TRUE(full_turn.has_value());
  EXPECT_EQ(*full_turn->heading_deg, 0.0);
}

TEST(NmeaHdt, BadFieldsAreNamed) {
  const auto err = [](std::vector<std::string> fields) {
    const auto h = decode_hdt(Sentence{"HE", "HDT", std::move(fields)});
    EXPECT_FALSE(h.has_value());
    return h ? std::string{} : h.error().detail;
  };
  EXPECT_EQ(err({"10.0", "M"}), "HDT reference 'M' is not 'T'");
  EXPECT_EQ(err({"361.0", "T"}), "HDT heading '361.0' is outside 0..360");
  EXPECT_EQ(err({"-1", "T"}), "HDT heading '-1' is outside 0..360");
  EXPECT_EQ(err({"north", "T"}), "field heading 'north' is not a number");
  EXPECT_EQ(err({}), "HDT has 0 fields, needs 1");
}

TEST(NmeaZda, DecodesVerifiedExample) {
  const auto z = decode_zda(parse_ok(kZda));
  ASSERT_TRUE(z.has_value()) << z.error().detail;
  EXPECT_EQ(z->time.hour, 16);
  EXPECT_EQ(z->time.minute, 0);
  EXPECT_DOUBLE_EQ(z->time.second, 12.71);
  EXPECT_EQ(z->time.day, 11);
  EXPECT_EQ(z->time.month, 3);
  EXPECT_EQ(z->time.year, 2004);
  EXPECT_EQ(z->zone_hours, -1);
  EXPECT_EQ(z->zone_minutes, 0);
  EXPECT_NEAR(z->time.unix_seconds(), 1079020812.71, 1e-6);  // 2004-03-11T16:00:12.71Z
}

TEST(NmeaZda, ReencodesVerifiedExampleByteExact) {
  Zda z;
  z.time = UtcTime::from_unix_seconds(1079020812.71);
  z.zone_hours = -1;
  z.zone_minutes = 0;
  EXPECT_EQ(frame(to_sentence(z)), kZda);
}

TEST(NmeaZda, RoundingCarriesIntoTheNextDayAndYear) {
  Zda z;
  z.time = UtcTime{2004, 12, 31, 23, 59, 59.999};
  z.zone_hours = 0;
  z.zone_minutes = 0;
  EXPECT_EQ(frame(to_sentence(z)), "$GPZDA,000000.00,01,01,2005,00,00*61\r\n");
}

TEST(NmeaZda, EmptyZoneFields) {
  Zda z;
  z.time = UtcTime{2024, 2, 29, 12, 0, 0.0};
  EXPECT_EQ(frame(to_sentence(z)), "$GPZDA,120000.00,29,02,2024,,*68\r\n");
  const auto d = decode_zda(parse_ok("$GPZDA,120000.00,29,02,2024,,*68\r\n"));
  ASSERT_TRUE(d.has_value()) << d.error().detail;
  EXPECT_FALSE(d->zone_hours.has_value());
  EXPECT_FALSE(d->zone_minutes.has_value());
  // Only the four required fields.
  EXPECT_TRUE(decode_zda(Sentence{"GP", "ZDA", {"120000.00", "29", "02", "2024"}}).has_value());
}

TEST(NmeaZda, BadFieldsAreNamed) {
  const auto err = [](std::vector<std::string> fields) {
    const auto z = decode_zda(Sentence{"GP", "ZDA", std::move(fields)});
    EXPECT_FALSE(z.has_value());
    return z ? std::string{} : z.error().detail;
  };
  EXPECT_EQ(err({"", "", "", "", "", ""}), "field time ''");
  EXPECT_EQ(err({"250000.00", "11", "03", "2004"}), "field time '250000.00'");
  EXPECT_EQ(err({"160012.71", "32", "03", "2004"}), "field day '32'");
  EXPECT_EQ(err({"160012.71", "11", "13", "2004"}), "field month '13'");
  EXPECT_EQ(err({"160012.71", "11", "03", "04"}), "field year '04'");
  EXPECT_EQ(err({"160012.71", "11", "03", "2004", "14", "00"}), "field zone hours '14'");
  EXPECT_EQ(err({"160012.71", "11", "03", "2004", "-1", "60"}), "field zone minutes '60'");
  EXPECT_EQ(err({"160012.71", "11", "03"}), "ZDA has 3 fields, needs 4");
}

TEST(NmeaZda, EncodeNeedsADate) {
  const auto previous = set_ensure_handler(
      [](const char*, int, const char*, const std::string& m) { throw std::logic_error(m); });
  EXPECT_THROW(to_sentence(Zda{}), std::logic_error);
  set_ensure_handler(previous);
}

TEST(NmeaVtgHdtZda, RoundTripThroughFraming) {
  for (int k = 0; k < 360; ++k) {
    Vtg v;
    v.cog_true_deg = k + 0.25;
    v.cog_mag_deg = (k + 180) % 360 + 0.5;
    v.sog_kn = k * 0.125;
    v.sog_kmh = *v.sog_kn * 1.852;
    v.mode = k % 2 == 0 ? std::optional<char>('D') : std::nullopt;
    const auto dv = decode_vtg(parse_ok(frame(to_sentence(v, "GN"))));
    ASSERT_TRUE(dv.has_value()) << dv.error().detail;
    EXPECT_DOUBLE_EQ(*dv->cog_true_deg, *v.cog_true_deg);
    EXPECT_DOUBLE_EQ(*dv->cog_mag_deg, *v.cog_mag_deg);
    EXPECT_DOUBLE_EQ(*dv->sog_kn, *v.sog_kn);
    EXPECT_NEAR(*dv->sog_kmh, *v.sog_kmh, 5.01e-4);  // 3 decimals
    EXPECT_EQ(dv->mode, v.mode);

    const auto dh = decode_hdt(parse_ok(frame(to_sentence(Hdt{k + 0.75}, "HE"))));
    ASSERT_TRUE(dh.has_value()) << dh.error().detail;
    EXPECT_DOUBLE_EQ(*dh->heading_deg, k + 0.75);

    Zda z;
    z.time = UtcTime::from_unix_seconds(1.7e9 + k * 86399.37);
    z.zone_hours = k % 27 - 13;
    z.zone_minutes = k % 60;
    const auto dz = decode_zda(parse_ok(frame(to_sentence(z))));
    ASSERT_TRUE(dz.has_value()) << dz.error().detail;
    EXPECT_NEAR(dz->time.unix_seconds(), z.time.unix_seconds(), 1e-6);
    EXPECT_EQ(dz->zone_hours, z.zone_hours);
    EXPECT_EQ(dz->zone_minutes, z.zone_minutes);
  }
}

TEST(NmeaVtgHdtZda, RandomBytesAroundAZdaKeepTheTriStateContract) {
  EXPECT_EQ(random_rounds_missing_frame<Sentence>(&parse, bytes_of(kZda),
                                                  bytes_of("$*\r\n,GPZDA0123456789"), 21),
            0);
}

}  // namespace
}  // namespace nav::protocols::nmea

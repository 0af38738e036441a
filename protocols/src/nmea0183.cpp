// SPDX-License-Identifier: MIT
// NMEA 0183 framing, GGA and RMC (protocols.md section 4; acceptance rules follow gpsd's
// packet.c lexer and driver_nmea0183.c).
//
// Framing:  '$' address { ',' field } '*' hh [CR] LF
//   address  = talker (2 chars) + type (3 chars), or 'P' + proprietary type
//   hh       = XOR of the characters between '$' and '*', two hex digits (any case on input,
//              upper case on output)
// Length:    '$' through hh at most kMaxSentence characters (gpsd's NMEA_MAX) unless the
//            caller gives another limit; gpsd's tolerance of CR CR LF and of trailing bytes
//            after hh is kept.
#include "nav/protocols/nmea0183.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>

#include "nav/common/ensure.hpp"

namespace nav::protocols::nmea {
namespace {

constexpr char kHexDigits[] = "0123456789ABCDEF";
constexpr std::int64_t kCentisecondsPerDay = 86400LL * 100;

ParseResult<Sentence> malformed(std::size_t consumed, std::string error) {
  ParseResult<Sentence> r;
  r.status = ParseStatus::kMalformed;
  r.consumed = consumed;
  r.error = std::move(error);
  return r;
}

std::string hex8(std::uint8_t v) {
  return std::string{"0x"} + kHexDigits[v >> 4] + kHexDigits[v & 0xF];
}

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

bool is_address_char(char c) { return (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9'); }

/// Parses a whole field of decimal digits.
std::optional<int> parse_int(std::string_view field) {
  if (field.empty()) return std::nullopt;
  int v = 0;
  const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), v);
  if (ec != std::errc{} || end != field.data() + field.size() || v < 0) return std::nullopt;
  return v;
}

std::string two_digits(int v) {
  return std::string{static_cast<char>('0' + v / 10 % 10), static_cast<char>('0' + v % 10)};
}

/// Days since 1970-01-01 of a proleptic Gregorian date (H. Hinnant's days_from_civil).
std::int64_t days_from_civil(std::int64_t y, unsigned m, unsigned d) {
  y -= m <= 2 ? 1 : 0;
  const std::int64_t era = (y >= 0 ? y : y - 399) / 400;
  const auto yoe = static_cast<unsigned>(y - era * 400);                 // [0, 399]
  const unsigned doy = (153 * (m > 2 ? m - 3 : m + 9) + 2) / 5 + d - 1;  // [0, 365]
  const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;            // [0, 146096]
  return era * 146097 + static_cast<std::int64_t>(doe) - 719468;
}

/// Inverse of days_from_civil: {year, month, day}.
void civil_from_days(std::int64_t z, int& year, int& month, int& day) {
  z += 719468;
  const std::int64_t era = (z >= 0 ? z : z - 146096) / 146097;
  const auto doe = static_cast<unsigned>(z - era * 146097);                    // [0, 146096]
  const unsigned yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;  // [0, 399]
  const unsigned doy = doe - (365 * yoe + yoe / 4 - yoe / 100);                // [0, 365]
  const unsigned mp = (5 * doy + 2) / 153;                                     // [0, 11]
  day = static_cast<int>(doy - (153 * mp + 2) / 5 + 1);
  month = static_cast<int>(mp < 10 ? mp + 3 : mp - 9);
  year = static_cast<int>(static_cast<std::int64_t>(yoe) + era * 400 + (month <= 2 ? 1 : 0));
}

/// "hhmmss.ss" of a time of day, rounded to the centisecond and wrapped into one day.
std::string format_time(const UtcTime& t) {
  const double s = t.hour * 3600.0 + t.minute * 60.0 + t.second;
  std::int64_t cs = std::llround(s * 100.0) % kCentisecondsPerDay;
  if (cs < 0) cs += kCentisecondsPerDay;
  const auto hour = static_cast<int>(cs / 360000);
  const auto minute = static_cast<int>(cs / 6000 % 60);
  const auto second = static_cast<int>(cs / 100 % 60);
  const auto centi = static_cast<int>(cs % 100);
  return two_digits(hour) + two_digits(minute) + two_digits(second) + "." + two_digits(centi);
}

/// Parses "hhmmss[.sss]" into the time-of-day part of t; empty leaves t unchanged.
bool parse_time(std::string_view f, UtcTime& t) {
  if (f.empty()) return true;
  if (f.size() < 6) return false;
  const auto hour = parse_int(f.substr(0, 2));
  const auto minute = parse_int(f.substr(2, 2));
  const auto second = parse_number(f.substr(4));
  if (!hour || !minute || !second || *hour > 23 || *minute > 59 || *second < 0.0 ||
      *second >= 61.0) {
    return false;
  }
  t.hour = *hour;
  t.minute = *minute;
  t.second = *second;
  return true;
}

/// Parses "ddmmyy" into the date part of t; empty leaves t unchanged. Two-digit years pivot
/// at 80: 80..99 are 1980..1999, 00..79 are 2000..2079.
bool parse_date(std::string_view f, UtcTime& t) {
  if (f.empty()) return true;
  if (f.size() != 6) return false;
  const auto day = parse_int(f.substr(0, 2));
  const auto month = parse_int(f.substr(2, 2));
  const auto yy = parse_int(f.substr(4, 2));
  if (!day || !month || !yy || *day < 1 || *day > 31 || *month < 1 || *month > 12) return false;
  t.day = *day;
  t.month = *month;
  t.year = *yy >= 80 ? 1900 + *yy : 2000 + *yy;
  return true;
}

/// "ddmm.mmmmm" (lat, 2 degree digits) or "dddmm.mmmmm" (lon, 3) with 5 decimals of minutes.
std::string format_angle(double deg, int degree_digits) {
  const std::int64_t total = std::llround(std::fabs(deg) * 60.0 * 1e5);  // [1e-5 arcmin]
  const std::int64_t whole_deg = total / 6'000'000;
  const std::int64_t rem = total % 6'000'000;
  char buf[32];
  std::snprintf(buf, sizeof buf, "%0*lld%02lld.%05lld", degree_digits,
                static_cast<long long>(whole_deg), static_cast<long long>(rem / 100'000),
                static_cast<long long>(rem % 100'000));
  return buf;
}

/// Decodes a ddmm.mmmm / dddmm.mmmm field and its hemisphere letter; both empty is nullopt.
Result<std::optional<double>> parse_angle(std::string_view value, std::string_view hemi,
                                          char positive, char negative, double max_deg,
                                          const std::string& name) {
  if (value.empty() && hemi.empty()) return std::optional<double>{};
  const auto bad = [&] {
    return fail(ErrorCode::kParse, "field " + name + " '" + std::string(value) + "," +
                                       std::string(hemi) + "' is not a coordinate");
  };
  if (value.empty() || hemi.size() != 1 || (hemi[0] != positive && hemi[0] != negative)) {
    return bad();
  }
  // Split at the text level (degrees = all but the two digits left of the point), so no
  // floating-point division can move a digit between degrees and minutes.
  const std::size_t dot = std::min(value.find('.'), value.size());
  if (dot < 3) return bad();
  const auto degrees = parse_int(value.substr(0, dot - 2));
  const auto minutes = parse_number(value.substr(dot - 2));
  if (!degrees || !minutes || *minutes < 0.0 || *minutes >= 60.0) return bad();
  const double deg = *degrees + *minutes / 60.0;
  if (deg > max_deg) return bad();
  return std::optional<double>{hemi[0] == negative ? -deg : deg};
}

Result<std::optional<double>> optional_number(const Sentence& s, std::size_t i,
                                              const std::string& name) {
  const std::string& f = s.fields[i];
  if (f.empty()) return std::optional<double>{};
  const auto v = parse_number(f);
  if (!v) return fail(ErrorCode::kParse, "field " + name + " '" + f + "' is not a number");
  return std::optional<double>{*v};
}

Result<void> check_address(const Sentence& s, std::string_view type, std::size_t min_fields) {
  if (s.type != type) {
    return fail(ErrorCode::kParse,
                "sentence $" + s.talker + s.type + " is not " + std::string(type));
  }
  if (s.fields.size() < min_fields) {
    return fail(ErrorCode::kParse, std::string(type) + " has " + std::to_string(s.fields.size()) +
                                       " fields, needs " + std::to_string(min_fields));
  }
  return {};
}

}  // namespace

std::string format_fixed(double value, int decimals) {
  NAV_ENSURE(std::isfinite(value), "format_fixed of a non-finite value");
  NAV_ENSURE(decimals >= 0 && decimals <= 17, "format_fixed decimals out of range");
  // The widest finite value: '-', 309 integer digits, '.', 17 decimals.
  char buf[1 + 309 + 1 + 17];
  const auto [end, ec] =
      std::to_chars(buf, buf + sizeof buf, value, std::chars_format::fixed, decimals);
  NAV_ENSURE(ec == std::errc{}, "format_fixed: value too large for the buffer");
  std::string s(buf, end);
  if (s.front() == '-' && s.find_first_not_of("0.", 1) == std::string::npos) s.erase(0, 1);
  return s;
}

std::string format_significant(double value, int digits) {
  NAV_ENSURE(std::isfinite(value), "format_significant of a non-finite value");
  NAV_ENSURE(digits >= 1 && digits <= 17, "format_significant digits out of range");
  if (value == 0.0) return "0";
  const int magnitude = static_cast<int>(std::floor(std::log10(std::fabs(value))));
  return format_fixed(value, std::clamp(digits - 1 - magnitude, 0, 12));
}

std::optional<double> parse_number(std::string_view field) {
  if (field.empty()) return std::nullopt;
  double v = 0.0;
  const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), v);
  if (ec != std::errc{} || end != field.data() + field.size() || !std::isfinite(v)) {
    return std::nullopt;
  }
  return v;
}

std::string format_time_of_day(const UtcTime& t) { return format_time(t); }

bool parse_time_of_day(std::string_view field, UtcTime& t) { return parse_time(field, t); }

std::uint8_t checksum(std::string_view body) {
  std::uint8_t sum = 0;
  for (const char c : body) sum = static_cast<std::uint8_t>(sum ^ static_cast<std::uint8_t>(c));
  return sum;
}

std::string frame(const Sentence& s) {
  // One test per character (find_first_of searches its set with a memchr per character:
  // navd's largest cost in user space over a P0 campaign).
  const auto delimiter = [](char c) {
    return c == ',' || c == '*' || c == '$' || c == '\r' || c == '\n';
  };
  std::string body = s.talker + s.type;
  for (const std::string& f : s.fields) {
    NAV_ENSURE(std::none_of(f.begin(), f.end(), delimiter),
               "NMEA field contains a delimiter: '" + f + "'");
    body += ',';
    body += f;
  }
  const std::uint8_t sum = checksum(body);
  return "$" + body + "*" + kHexDigits[sum >> 4] + kHexDigits[sum & 0xF] + "\r\n";
}

ParseResult<Sentence> parse(ByteSpan buffer) { return parse_with_limit(buffer, kMaxSentence); }

ParseResult<Sentence> parse_with_limit(ByteSpan buffer, std::size_t max_sentence) {
  if (buffer.empty()) return {};  // kNeedMore
  const auto begin = buffer.begin();
  if (buffer[0] != '$') {
    const auto next = std::find(begin, buffer.end(), std::uint8_t{'$'});
    const auto n = static_cast<std::size_t>(next - begin);
    return malformed(n, std::to_string(n) + " byte(s) before '$'");
  }

  // Find the line end; a new '$', a control byte or an over-long line ends the attempt.
  std::size_t lf = 0;
  for (std::size_t i = 1; i < buffer.size() && lf == 0; ++i) {
    const std::uint8_t c = buffer[i];
    if (c == '\n') {
      lf = i;
    } else if (c == '$') {
      return malformed(i,
                       "sentence cut short by a new '$' after " + std::to_string(i) + " byte(s)");
    } else if (c == '\r') {
      if (i + 1 < buffer.size() && buffer[i + 1] != '\r' && buffer[i + 1] != '\n') {
        return malformed(i + 1, "CR inside a sentence");
      }
    } else if (c < 0x20 || c > 0x7E) {
      return malformed(i + 1, "non-printable byte " + hex8(c) + " at offset " + std::to_string(i));
    } else if (i >= max_sentence) {
      const auto next =
          std::find(begin + static_cast<std::ptrdiff_t>(i), buffer.end(), std::uint8_t{'$'});
      return malformed(static_cast<std::size_t>(next - begin),
                       "sentence longer than " + std::to_string(max_sentence) + " characters");
    }
  }
  if (lf == 0) return {};  // kNeedMore: start of a sentence, no line end yet

  const std::size_t consumed = lf + 1;
  std::size_t end = lf;
  while (end > 1 && buffer[end - 1] == '\r') --end;
  const std::string line(begin + 1, begin + static_cast<std::ptrdiff_t>(end));  // without '$'

  const std::size_t star = line.find('*');
  if (star == std::string::npos || star + 3 > line.size() || hex_value(line[star + 1]) < 0 ||
      hex_value(line[star + 2]) < 0) {
    return malformed(consumed, "missing checksum '*hh'");
  }
  const std::string_view body = std::string_view(line).substr(0, star);
  const auto received =
      static_cast<std::uint8_t>(hex_value(line[star + 1]) * 16 + hex_value(line[star + 2]));
  const std::uint8_t computed = checksum(body);
  if (received != computed) {
    return malformed(consumed, "checksum " + hex8(received) + " != computed " + hex8(computed));
  }

  const std::size_t comma = std::min(body.find(','), body.size());
  const std::string_view address = body.substr(0, comma);
  const bool address_ok = !address.empty() &&
                          std::all_of(address.begin(), address.end(), is_address_char) &&
                          (address[0] == 'P' ? address.size() >= 2 : address.size() == 5);
  if (!address_ok) {
    return malformed(consumed, "address '" + std::string(address) +
                                   "' is neither talker+type nor P+proprietary");
  }

  Sentence s;
  const std::size_t talker_len = address[0] == 'P' ? 1 : 2;
  s.talker = std::string(address.substr(0, talker_len));
  s.type = std::string(address.substr(talker_len));
  if (comma < body.size()) {
    s.fields.reserve(static_cast<std::size_t>(
        std::count(body.begin() + static_cast<std::ptrdiff_t>(comma), body.end(), ',')));
    std::size_t pos = comma + 1;
    while (true) {
      const std::size_t next = std::min(body.find(',', pos), body.size());
      s.fields.emplace_back(body.substr(pos, next - pos));
      if (next == body.size()) break;
      pos = next + 1;
    }
  }

  ParseResult<Sentence> r;
  r.status = ParseStatus::kComplete;
  r.consumed = consumed;
  r.message = std::move(s);
  return r;
}

double UtcTime::unix_seconds() const {
  NAV_ENSURE(month >= 1 && month <= 12 && day >= 1 && day <= 31,
             "UtcTime::unix_seconds needs a date");
  const std::int64_t days =
      days_from_civil(year, static_cast<unsigned>(month), static_cast<unsigned>(day));
  return static_cast<double>(days * 86400 + hour * 3600 + minute * 60) + second;
}

UtcTime UtcTime::from_unix_seconds(double s) {
  NAV_ENSURE(std::isfinite(s), "UtcTime::from_unix_seconds of a non-finite time");
  const std::int64_t cs = std::llround(s * 100.0);
  std::int64_t days = cs / kCentisecondsPerDay;
  std::int64_t rem = cs % kCentisecondsPerDay;
  if (rem < 0) {  // floor division for times before 1970
    rem += kCentisecondsPerDay;
    --days;
  }
  UtcTime t;
  civil_from_days(days, t.year, t.month, t.day);
  t.hour = static_cast<int>(rem / 360000);
  t.minute = static_cast<int>(rem / 6000 % 60);
  t.second = static_cast<double>(rem % 6000) / 100.0;
  return t;
}

Sentence to_sentence(const Gga& g, std::string talker) {
  // A receiver without a fix sends quality 0 and leaves position, HDOP and heights empty.
  const bool fix = g.quality != 0;
  const bool has_pos = fix && g.lat_deg && g.lon_deg;
  const bool has_alt = fix && g.alt_msl_m.has_value();
  const bool has_sep = fix && g.geoid_sep_m.has_value();
  if (has_pos) {
    NAV_ENSURE(std::fabs(*g.lat_deg) <= 90.0, "GGA latitude out of range");
    NAV_ENSURE(std::fabs(*g.lon_deg) <= 180.0, "GGA longitude out of range");
  }
  NAV_ENSURE(g.quality >= 0 && g.quality <= 9, "GGA quality is one digit");
  NAV_ENSURE(g.satellites >= 0 && g.satellites <= 99, "GGA satellites is two digits");
  Sentence s{std::move(talker), "GGA", {}};
  s.fields = {format_time(g.time),
              has_pos ? format_angle(*g.lat_deg, 2) : "",
              has_pos ? (*g.lat_deg < 0.0 ? "S" : "N") : "",
              has_pos ? format_angle(*g.lon_deg, 3) : "",
              has_pos ? (*g.lon_deg < 0.0 ? "W" : "E") : "",
              std::to_string(g.quality),
              two_digits(g.satellites),
              fix && g.hdop ? format_fixed(*g.hdop, 2) : "",
              has_alt ? format_fixed(*g.alt_msl_m, 1) : "",
              has_alt ? "M" : "",
              has_sep ? format_fixed(*g.geoid_sep_m, 1) : "",
              has_sep ? "M" : "",
              "",   // age of differential corrections [s]
              ""};  // differential reference station ID
  return s;
}

Sentence to_sentence(const Rmc& r, std::string talker) {
  // Status V: like a receiver without a fix, no position and no motion.
  const bool has_pos = r.valid && r.lat_deg && r.lon_deg;
  if (has_pos) {
    NAV_ENSURE(std::fabs(*r.lat_deg) <= 90.0, "RMC latitude out of range");
    NAV_ENSURE(std::fabs(*r.lon_deg) <= 180.0, "RMC longitude out of range");
  }
  const bool has_date = r.time.month >= 1;
  if (has_date) NAV_ENSURE(r.time.year >= 1980 && r.time.year <= 2079, "RMC year out of range");
  NAV_ENSURE(r.mode >= 'A' && r.mode <= 'Z', "RMC mode is an upper-case letter");
  Sentence s{std::move(talker), "RMC", {}};
  s.fields = {
      format_time(r.time),
      r.valid ? "A" : "V",
      has_pos ? format_angle(*r.lat_deg, 2) : "",
      has_pos ? (*r.lat_deg < 0.0 ? "S" : "N") : "",
      has_pos ? format_angle(*r.lon_deg, 3) : "",
      has_pos ? (*r.lon_deg < 0.0 ? "W" : "E") : "",
      r.valid && r.sog_kn ? format_fixed(*r.sog_kn, 3) : "",
      r.valid && r.cog_deg ? format_fixed(*r.cog_deg, 2) : "",
      has_date ? two_digits(r.time.day) + two_digits(r.time.month) + two_digits(r.time.year % 100)
               : "",
      "",  // magnetic variation [deg]
      "",  // its direction E/W
      std::string(1, r.mode)};
  return s;
}

Result<Gga> decode_gga(const Sentence& s) {
  // gpsd needs 13 fields counting the address: up to the geoid separation's unit.
  if (auto ok = check_address(s, "GGA", 12); !ok) return tl::unexpected(ok.error());
  const auto& f = s.fields;
  Gga g;
  if (!parse_time(f[0], g.time)) return fail(ErrorCode::kParse, "field time '" + f[0] + "'");
  auto lat = parse_angle(f[1], f[2], 'N', 'S', 90.0, "latitude");
  if (!lat) return tl::unexpected(lat.error());
  auto lon = parse_angle(f[3], f[4], 'E', 'W', 180.0, "longitude");
  if (!lon) return tl::unexpected(lon.error());
  g.lat_deg = *lat;
  g.lon_deg = *lon;
  if (g.lat_deg.has_value() != g.lon_deg.has_value()) {
    return fail(ErrorCode::kParse, "GGA has only one of latitude and longitude");
  }
  const auto quality = f[5].empty() ? std::optional<int>{0} : parse_int(f[5]);
  // One digit and two digits on the wire (protocols.md 4).
  if (!quality || *quality < 0 || *quality > 9) {
    return fail(ErrorCode::kParse, "field quality '" + f[5] + "'");
  }
  g.quality = *quality;
  const auto sats = f[6].empty() ? std::optional<int>{0} : parse_int(f[6]);
  if (!sats || *sats < 0 || *sats > 99) {
    return fail(ErrorCode::kParse, "field satellites '" + f[6] + "'");
  }
  g.satellites = *sats;
  auto hdop = optional_number(s, 7, "hdop");
  if (!hdop) return tl::unexpected(hdop.error());
  auto alt = optional_number(s, 8, "altitude");
  if (!alt) return tl::unexpected(alt.error());
  auto sep = optional_number(s, 10, "geoid separation");
  if (!sep) return tl::unexpected(sep.error());
  if ((*alt && f[9] != "M") || (*sep && f[11] != "M")) {
    return fail(ErrorCode::kParse, "GGA height unit is not 'M'");
  }
  g.hdop = *hdop;
  g.alt_msl_m = *alt;
  g.geoid_sep_m = *sep;
  return g;
}

Result<Rmc> decode_rmc(const Sentence& s) {
  // Up to the date; magnetic variation (9, 10) and mode (11, NMEA >= 2.3) are optional.
  if (auto ok = check_address(s, "RMC", 9); !ok) return tl::unexpected(ok.error());
  const auto& f = s.fields;
  Rmc r;
  if (!parse_time(f[0], r.time)) return fail(ErrorCode::kParse, "field time '" + f[0] + "'");
  if (f[1] != "A" && f[1] != "V") return fail(ErrorCode::kParse, "field status '" + f[1] + "'");
  r.valid = f[1] == "A";
  auto lat = parse_angle(f[2], f[3], 'N', 'S', 90.0, "latitude");
  if (!lat) return tl::unexpected(lat.error());
  auto lon = parse_angle(f[4], f[5], 'E', 'W', 180.0, "longitude");
  if (!lon) return tl::unexpected(lon.error());
  r.lat_deg = *lat;
  r.lon_deg = *lon;
  if (r.lat_deg.has_value() != r.lon_deg.has_value()) {
    return fail(ErrorCode::kParse, "RMC has only one of latitude and longitude");
  }
  auto sog = optional_number(s, 6, "speed over ground");
  if (!sog) return tl::unexpected(sog.error());
  auto cog = optional_number(s, 7, "course over ground");
  if (!cog) return tl::unexpected(cog.error());
  r.sog_kn = *sog;
  r.cog_deg = *cog;
  if (!parse_date(f[8], r.time)) return fail(ErrorCode::kParse, "field date '" + f[8] + "'");
  if (f.size() > 11 && !f[11].empty()) {
    if (f[11].size() != 1 || f[11][0] < 'A' || f[11][0] > 'Z') {
      return fail(ErrorCode::kParse, "field mode '" + f[11] + "'");
    }
    r.mode = f[11][0];
  } else {
    r.mode = r.valid ? 'A' : 'N';  // NMEA < 2.3 has no mode: infer it from the status
  }
  return r;
}

}  // namespace nav::protocols::nmea

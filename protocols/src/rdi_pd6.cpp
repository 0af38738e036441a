// SPDX-License-Identifier: MIT
// Teledyne RDI PD6 ASCII codec (protocols.md section 3c; Pathfinder DVL Guide Apr 2018
// Table 50, WorkHorse H-ADCP manual May 2015 Table 49).
//
// Line:  ':' ID { ',' field } CR LF, no checksum. Manual notation and our output widths:
//   :SA,±PP.PP,±RR.RR,HHH.HH                                   6, 6, 6
//   :TS,YYMMDDHHmmsshh,SS.S,+TT.T,DDDD.D,CCCC.C,BBB             14, 4, 5, 6, 6, 3
//   :WI|:BI,±XXXXX,±YYYYY,±ZZZZZ,±EEEEE,S                        6 x 4, 1
//   :WS|:BS,±TTTTT,±LLLLL,±NNNNN,S   :WE|:BE,±EEEEE,±NNNNN,±UUUUU,S   6 x 3, 1
//   :WD|:BD,±EEEEEEEE.EE,±NNNNNNNN.NN,±UUUUUUUU.UU,DDDD.DD,TTT.TT    12 x 3, 7, 6
// Fields are right-justified with spaces (UNCONFIRMED against a capture); the parser trims
// them, so zero padding ("+00012") parses too.
#include "nav/protocols/rdi_pd6.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <string_view>
#include <vector>

#include "nav/common/ensure.hpp"
#include "nav/protocols/nmea0183.hpp"

namespace nav::protocols::rdi_pd6 {
namespace {

ParseResult<Line> malformed(std::size_t consumed, std::string error) {
  ParseResult<Line> r;
  r.status = ParseStatus::kMalformed;
  r.consumed = consumed;
  r.error = std::move(error);
  return r;
}

std::string pad(std::string s, std::size_t width) {
  return s.size() >= width ? s : std::string(width - s.size(), ' ') + s;
}

/// Fixed decimals with an explicit sign ("+0.45", "-1.23"), right-justified.
std::string signed_fixed(double v, int decimals, std::size_t width) {
  std::string s = nmea::format_fixed(v, decimals);
  if (s.front() != '-') s.insert(0, 1, '+');
  return pad(s, width);
}

std::string signed_int(int v, std::size_t width) {
  return pad((v < 0 ? "" : "+") + std::to_string(v), width);
}

std::string two_digits(int v) {
  NAV_ENSURE(v >= 0 && v <= 99, "PD6 :TS time field out of 00..99");
  return std::string{static_cast<char>('0' + v / 10), static_cast<char>('0' + v % 10)};
}

std::string velocity(int mmps) {
  NAV_ENSURE(mmps >= -99999 && mmps <= 99999, "PD6 velocity wider than +-XXXXX");
  return signed_int(mmps, 6);
}

char id_letter(Track t) { return t == Track::kWater ? 'W' : 'B'; }

std::string_view trim(std::string_view f) {
  while (!f.empty() && f.front() == ' ') f.remove_prefix(1);
  while (!f.empty() && f.back() == ' ') f.remove_suffix(1);
  return f;
}

/// Drops one leading '+' that precedes a digit or '.'; leaves anything else for from_chars
/// to reject.
std::string_view unplus(std::string_view f) {
  if (f.size() > 1 && f[0] == '+' &&
      (std::isdigit(static_cast<unsigned char>(f[1])) || f[1] == '.')) {
    f.remove_prefix(1);
  }
  return f;
}

/// Reads the fields of one line, naming the first one that does not parse.
class FieldReader {
 public:
  FieldReader(std::string id, std::vector<std::string_view> fields)
      : id_(std::move(id)), fields_(std::move(fields)) {}
  std::size_t size() const { return fields_.size(); }
  double number() {
    const std::string_view f = next();
    const auto v = nmea::parse_number(unplus(f));
    if (!v) fail(f, "a number");
    return v.value_or(0.0);
  }
  int integer(int lo, int hi) {
    const std::string_view f = unplus(next());
    int v = 0;
    const auto [end, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
    if (f.empty() || ec != std::errc{} || end != f.data() + f.size() || v < lo || v > hi) {
      fail(f, "an integer in range");
    }
    return v;
  }
  bool status() {
    const std::string_view f = next();
    if (f != "A" && f != "V") fail(f, "status A or V");
    return f == "A";
  }
  std::string_view text() { return next(); }
  void fail(std::string_view field, const char* what) {
    if (error_.empty()) {
      error_ = ":" + id_ + " field " + std::to_string(index_) + " '" + std::string(field) +
               "' is not " + what;
    }
  }
  const std::string& error() const { return error_; }

 private:
  std::string_view next() { return trim(fields_[index_++]); }
  std::string id_;
  std::vector<std::string_view> fields_;
  std::size_t index_ = 0;
  std::string error_;
};

/// Two decimal digits at pos of a 14-digit :TS time, within [lo, hi].
int time_part(FieldReader& in, std::string_view t, std::size_t pos, int lo, int hi) {
  const int v = (t[pos] - '0') * 10 + (t[pos + 1] - '0');
  if (v < lo || v > hi) in.fail(t, "a time YYMMDDHHmmsshh");
  return v;
}

std::string encode_line(const Attitude& a) {
  return ":SA," + signed_fixed(a.pitch_deg, 2, 6) + "," + signed_fixed(a.roll_deg, 2, 6) + "," +
         pad(nmea::format_fixed(a.heading_deg, 2), 6);
}

std::string encode_line(const TimeAndScaling& t) {
  NAV_ENSURE(t.year >= 1980 && t.year <= 2079, "PD6 :TS year outside 1980..2079");
  NAV_ENSURE(t.bit_result >= 0 && t.bit_result <= 999, "PD6 :TS BIT result is 3 digits");
  std::string s = ":TS," + two_digits(t.year % 100) + two_digits(t.month) + two_digits(t.day) +
                  two_digits(t.hour) + two_digits(t.minute) + two_digits(t.second) +
                  two_digits(t.hundredths) + "," + pad(nmea::format_fixed(t.salinity_ppt, 1), 4) +
                  "," + signed_fixed(t.temperature_degc, 1, 5) + "," +
                  pad(nmea::format_fixed(t.depth_m, 1), 6) + "," +
                  pad(nmea::format_fixed(t.sound_speed_mps, 1), 6) + "," +
                  pad(std::to_string(t.bit_result), 3);
  if (t.leak) s += std::string(",") + *t.leak;
  return s;
}

std::string encode_line(const InstrumentVelocity& v) {
  std::string s = std::string(":") + id_letter(v.track) + "I";
  for (const int x : v.xyze_mmps) s += "," + velocity(x);
  return s + "," + (v.valid ? "A" : "V");
}

std::string encode_line(const ShipVelocity& v) {
  return std::string(":") + id_letter(v.track) + "S," + velocity(v.transverse_mmps) + "," +
         velocity(v.longitudinal_mmps) + "," + velocity(v.normal_mmps) + "," +
         (v.valid ? "A" : "V");
}

std::string encode_line(const EarthVelocity& v) {
  return std::string(":") + id_letter(v.track) + "E," + velocity(v.east_mmps) + "," +
         velocity(v.north_mmps) + "," + velocity(v.up_mmps) + "," + (v.valid ? "A" : "V");
}

std::string encode_line(const Distance& d) {
  return std::string(":") + id_letter(d.track) + "D," + signed_fixed(d.east_m, 2, 12) + "," +
         signed_fixed(d.north_m, 2, 12) + "," + signed_fixed(d.up_m, 2, 12) + "," +
         pad(nmea::format_fixed(d.range_m, 2), 7) + "," +
         pad(nmea::format_fixed(d.time_since_good_s, 2), 6);
}

/// Decodes the fields after ":ID,"; the error names the first bad field.
Line decode_fields(const std::string& id, FieldReader& in, std::size_t& expected) {
  const Track track = id[0] == 'W' ? Track::kWater : Track::kBottom;
  const char kind = id[1];
  if (id == "SA") {
    expected = 3;
    if (in.size() != expected) return Attitude{};
    Attitude a;
    a.pitch_deg = in.number();
    a.roll_deg = in.number();
    a.heading_deg = in.number();
    return a;
  }
  if (id == "TS") {
    expected = in.size() == 7 ? 7 : 6;
    if (in.size() != expected) return TimeAndScaling{};
    TimeAndScaling t;
    const std::string_view time = in.text();
    if (time.size() != 14 ||
        !std::all_of(time.begin(), time.end(), [](char c) { return c >= '0' && c <= '9'; })) {
      in.fail(time, "a time YYMMDDHHmmsshh");
      return t;
    }
    const int yy = time_part(in, time, 0, 0, 99);
    t.year = yy >= 80 ? 1900 + yy : 2000 + yy;
    t.month = time_part(in, time, 2, 1, 12);
    t.day = time_part(in, time, 4, 1, 31);
    t.hour = time_part(in, time, 6, 0, 23);
    t.minute = time_part(in, time, 8, 0, 59);
    t.second = time_part(in, time, 10, 0, 60);
    t.hundredths = time_part(in, time, 12, 0, 99);
    t.salinity_ppt = in.number();
    t.temperature_degc = in.number();
    t.depth_m = in.number();
    t.sound_speed_mps = in.number();
    t.bit_result = in.integer(0, 999);
    if (expected == 7) {
      const std::string_view leak = in.text();
      if (leak.size() != 1) in.fail(leak, "a one-letter leak flag");
      t.leak = leak.empty() ? ' ' : leak[0];
    }
    return t;
  }
  if (kind == 'I') {
    expected = 5;
    if (in.size() != expected) return InstrumentVelocity{};
    InstrumentVelocity v{track, {}, false};
    for (int& x : v.xyze_mmps) x = in.integer(-99999, 99999);
    v.valid = in.status();
    return v;
  }
  if (kind == 'S' || kind == 'E') {
    expected = 4;
    if (in.size() != expected) return ShipVelocity{};
    const int a = in.integer(-99999, 99999);
    const int b = in.integer(-99999, 99999);
    const int c = in.integer(-99999, 99999);
    const bool valid = in.status();
    if (kind == 'S') return ShipVelocity{track, a, b, c, valid};
    return EarthVelocity{track, a, b, c, valid};
  }
  expected = 5;  // kind == 'D'
  if (in.size() != expected) return Distance{};
  Distance d;
  d.track = track;
  d.east_m = in.number();
  d.north_m = in.number();
  d.up_m = in.number();
  d.range_m = in.number();
  d.time_since_good_s = in.number();
  return d;
}

}  // namespace

std::string encode(const Line& line) {
  return std::visit([](const auto& l) { return encode_line(l); }, line) + "\r\n";
}

ParseResult<Line> parse(ByteSpan buffer) {
  if (buffer.empty()) return {};  // kNeedMore
  if (buffer[0] != ':') {
    const auto next = std::find(buffer.begin(), buffer.end(), std::uint8_t{':'});
    const auto n = static_cast<std::size_t>(next - buffer.begin());
    return malformed(n, std::to_string(n) + " byte(s) before ':'");
  }
  std::size_t lf = 0;
  for (std::size_t i = 1; i < buffer.size() && lf == 0; ++i) {
    const std::uint8_t c = buffer[i];
    if (c == '\n') {
      lf = i;
    } else if (c == ':') {
      return malformed(i, "line cut short by a new ':' after " + std::to_string(i) + " byte(s)");
    } else if (c == '\r') {
      if (i + 1 < buffer.size() && buffer[i + 1] != '\n') return malformed(i + 1, "CR in a line");
    } else if (c < 0x20 || c > 0x7E) {
      return malformed(i + 1, "non-printable byte at offset " + std::to_string(i));
    } else if (i >= kMaxLine) {
      const auto next = std::find(buffer.begin() + static_cast<std::ptrdiff_t>(i), buffer.end(),
                                  std::uint8_t{':'});
      return malformed(static_cast<std::size_t>(next - buffer.begin()),
                       "line longer than " + std::to_string(kMaxLine) + " characters");
    }
  }
  if (lf == 0) return {};  // kNeedMore

  const std::size_t consumed = lf + 1;
  const std::size_t end = buffer[lf - 1] == '\r' ? lf - 1 : lf;
  const std::string text(buffer.begin() + 1, buffer.begin() + static_cast<std::ptrdiff_t>(end));
  const std::string id = text.substr(0, 2);
  static constexpr std::string_view kIds[] = {"SA", "TS", "WI", "WS", "WE",
                                              "WD", "BI", "BS", "BE", "BD"};
  if (text.size() < 3 || text[2] != ',' ||
      std::find(std::begin(kIds), std::end(kIds), id) == std::end(kIds)) {
    return malformed(consumed, "unsupported line ':" + text.substr(0, text.find(',')) + "'");
  }
  std::vector<std::string_view> fields;
  for (std::size_t pos = 3;;) {
    const std::size_t next = std::min(text.find(',', pos), text.size());
    fields.emplace_back(std::string_view(text).substr(pos, next - pos));
    if (next == text.size()) break;
    pos = next + 1;
  }
  FieldReader in(id, fields);
  std::size_t expected = 0;
  Line line = decode_fields(id, in, expected);
  if (fields.size() != expected) {
    return malformed(consumed, ":" + id + " has " + std::to_string(fields.size()) +
                                   " fields, needs " + std::to_string(expected));
  }
  if (!in.error().empty()) return malformed(consumed, in.error());

  ParseResult<Line> r;
  r.status = ParseStatus::kComplete;
  r.consumed = consumed;
  r.message = std::move(line);
  return r;
}

std::optional<double> to_mps(int mmps) {
  if (mmps == kBadVelocity) return std::nullopt;
  return mmps / 1000.0;
}

}  // namespace nav::protocols::rdi_pd6

// SPDX-License-Identifier: MIT
// LinkQuest NavQuest 600 NQ1 line codec (protocols.md section 3a).
//
// Line:   "$#NQ.RES" { ' ' token } CR LF, 47 tokens in all:
//   1 error code (hex "0X0000"), 2-5 beam good, 6-9 beam altitude [m], 10-13 bottom radial
//   velocity [mm/s], 14-17 water radial velocity [mm/s], 18-21 water credit, 22-24 + 25
//   instrument velocity [mm/s] + flag, 26-28 + 29 earth velocity + flag, 30-32 + 33 water
//   instrument velocity + flag, 34-36 + 37 water earth velocity + flag, 38-40 roll, pitch,
//   yaw [deg], 41 altitude [m], 42 temperature [°C], 43 pressure, 44 salinity [ppt],
//   45 sound speed [m/s], 46 checksum (decimal).
// Checksum: XOR of the characters from the first space (inclusive) to the last space
// (exclusive), i.e. DUNE's XORChecksum::compute(strchr(bfr,' '), strrchr(bfr,' ') - sptr).
#include "nav/protocols/navquest_nq1.hpp"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <vector>

#include "nav/common/ensure.hpp"
#include "nav/protocols/nmea0183.hpp"

namespace nav::protocols::navquest_nq1 {
namespace {

ParseResult<Nq1> malformed(std::size_t consumed, std::string error) {
  ParseResult<Nq1> r;
  r.status = ParseStatus::kMalformed;
  r.consumed = consumed;
  r.error = std::move(error);
  return r;
}

std::size_t skip_to_next_dollar(ByteSpan buffer, std::size_t from) {
  const auto next = std::find(buffer.begin() + static_cast<std::ptrdiff_t>(from), buffer.end(),
                              std::uint8_t{'$'});
  return static_cast<std::size_t>(next - buffer.begin());
}

/// "0" for an exact zero (as the device prints unmeasured fields), else fixed decimals.
std::string number(double v, int decimals) {
  return v == 0.0 ? std::string("0") : nmea::format_fixed(v, decimals);
}

std::optional<int> parse_int(std::string_view f) {
  int v = 0;
  const auto [end, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
  if (f.empty() || ec != std::errc{} || end != f.data() + f.size()) return std::nullopt;
  return v;
}

/// Walks the 46 tokens after the header, remembering the first one that does not parse.
class TokenReader {
 public:
  explicit TokenReader(const std::vector<std::string_view>& tokens) : tokens_(tokens) {}
  double number() {
    const auto v = nmea::parse_number(next());
    if (!v) fail("a number");
    return v.value_or(0.0);
  }
  int integer(int lo, int hi) {
    const auto v = parse_int(next());
    if (!v || *v < lo || *v > hi) fail(("an integer " + range(lo, hi)).c_str());
    return v.value_or(lo);
  }
  template <std::size_t N>
  void numbers(std::array<double, N>& out) {
    for (double& v : out) v = number();
  }
  VelocityFlag flag() { return static_cast<VelocityFlag>(integer(0, 2)); }
  std::uint16_t error_code() {
    const std::string_view t = next();
    unsigned v = 0;
    const bool prefix = t.size() > 2 && t[0] == '0' && (t[1] == 'X' || t[1] == 'x');
    const char* first = t.data() + (prefix ? 2 : 0);
    const auto [end, ec] = std::from_chars(first, t.data() + t.size(), v, 16);
    if (!prefix || t.size() > 6 || ec != std::errc{} || end != t.data() + t.size()) {
      fail("a hex error code 0Xhhhh");
    }
    return static_cast<std::uint16_t>(v);
  }
  const std::string& error() const { return error_; }

 private:
  static std::string range(int lo, int hi) {
    return std::to_string(lo) + ".." + std::to_string(hi);
  }
  std::string_view next() { return tokens_[index_++]; }
  void fail(const char* what) {
    if (error_.empty()) {
      error_ = "token " + std::to_string(index_ - 1) + " '" + std::string(tokens_[index_ - 1]) +
               "' is not " + what;
    }
  }
  const std::vector<std::string_view>& tokens_;
  std::size_t index_ = 1;  // token 0 is the header
  std::string error_;
};

}  // namespace

std::uint8_t checksum(std::string_view between) {
  std::uint8_t sum = 0;
  for (const char c : between) sum = static_cast<std::uint8_t>(sum ^ static_cast<std::uint8_t>(c));
  return sum;
}

std::string encode(const Nq1& m) {
  NAV_ENSURE(m.sound_speed_mps >= 0, "NQ1 sound speed is a non-negative integer");
  char code[8];
  std::snprintf(code, sizeof code, "0X%04X", static_cast<unsigned>(m.error_code));
  std::string body = std::string(" ") + code;
  const auto add = [&body](const std::string& token) { body += ' ' + token; };
  for (const bool g : m.beam_good) add(g ? "1" : "0");
  for (const double v : m.beam_altitude_m) add(number(v, 1));
  for (const double v : m.bottom_radial_mmps) add(number(v, 1));
  for (const double v : m.water_radial_mmps) add(number(v, 1));
  for (const int c : m.water_credit) add(std::to_string(c));
  const auto add_velocity = [&](const std::array<double, 3>& v, VelocityFlag flag) {
    for (const double x : v) add(number(x, 1));
    add(std::to_string(static_cast<int>(flag)));
  };
  add_velocity(m.velocity_instrument_mmps, m.velocity_instrument_flag);
  add_velocity(m.velocity_earth_mmps, m.velocity_earth_flag);
  add_velocity(m.water_velocity_instrument_mmps, m.water_velocity_instrument_flag);
  add_velocity(m.water_velocity_earth_mmps, m.water_velocity_earth_flag);
  for (const double v : {m.roll_deg, m.pitch_deg, m.yaw_deg, m.altitude_m, m.temperature_degc}) {
    add(number(v, 1));
  }
  add(number(m.pressure, 3));
  add(number(m.salinity_ppt, 1));
  add(std::to_string(m.sound_speed_mps));
  return std::string(kHeader) + body + ' ' + std::to_string(checksum(body)) + "\r\n";
}

ParseResult<Nq1> parse(ByteSpan buffer) {
  if (buffer.empty()) return {};  // kNeedMore
  if (buffer[0] != '$') {
    const std::size_t n = skip_to_next_dollar(buffer, 0);
    return malformed(n, std::to_string(n) + " byte(s) before '$'");
  }
  // "$#NQ.RES " must open the line; decide as soon as the bytes differ.
  const std::string header = std::string(kHeader) + ' ';
  const std::size_t have = std::min(buffer.size(), header.size());
  if (!std::equal(buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>(have),
                  header.begin())) {
    return malformed(skip_to_next_dollar(buffer, 1), "line does not start with \"$#NQ.RES \"");
  }

  std::size_t lf = 0;
  for (std::size_t i = 1; i < buffer.size() && lf == 0; ++i) {
    const std::uint8_t c = buffer[i];
    if (c == '\n') {
      lf = i;
    } else if (c == '$') {
      return malformed(i, "line cut short by a new '$' after " + std::to_string(i) + " byte(s)");
    } else if (c == '\r') {
      if (i + 1 < buffer.size() && buffer[i + 1] != '\n') return malformed(i + 1, "CR in a line");
    } else if (c < 0x20 || c > 0x7E) {
      return malformed(i + 1, "non-printable byte at offset " + std::to_string(i));
    } else if (i >= kMaxLine) {
      return malformed(skip_to_next_dollar(buffer, i),
                       "line longer than " + std::to_string(kMaxLine) + " characters");
    }
  }
  if (lf == 0) return {};  // kNeedMore

  const std::size_t consumed = lf + 1;
  const std::size_t end = buffer[lf - 1] == '\r' ? lf - 1 : lf;
  const std::string line(buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>(end));

  std::vector<std::string_view> tokens;
  for (std::size_t pos = 0; pos < line.size();) {
    const std::size_t next = std::min(line.find(' ', pos), line.size());
    if (next > pos) tokens.emplace_back(std::string_view(line).substr(pos, next - pos));
    pos = next + 1;
  }
  if (tokens.size() != kTokenCount) {
    return malformed(consumed, "NQ1 line has " + std::to_string(tokens.size()) + " tokens, needs " +
                                   std::to_string(kTokenCount));
  }
  const std::size_t first_space = line.find(' ');
  const std::size_t last_space = line.rfind(' ');
  const auto received = parse_int(tokens.back());
  const std::uint8_t computed =
      checksum(std::string_view(line).substr(first_space, last_space - first_space));
  if (!received || *received < 0 || *received > 255) {
    return malformed(consumed,
                     "checksum token '" + std::string(tokens.back()) + "' is not a decimal 0..255");
  }
  if (*received != computed) {
    return malformed(consumed, "checksum " + std::to_string(*received) + " != computed " +
                                   std::to_string(computed));
  }

  TokenReader in(tokens);
  Nq1 m;
  m.error_code = in.error_code();
  for (bool& g : m.beam_good) g = in.integer(0, 1) == 1;
  in.numbers(m.beam_altitude_m);
  in.numbers(m.bottom_radial_mmps);
  in.numbers(m.water_radial_mmps);
  for (int& c : m.water_credit) c = in.integer(0, 50);
  in.numbers(m.velocity_instrument_mmps);
  m.velocity_instrument_flag = in.flag();
  in.numbers(m.velocity_earth_mmps);
  m.velocity_earth_flag = in.flag();
  in.numbers(m.water_velocity_instrument_mmps);
  m.water_velocity_instrument_flag = in.flag();
  in.numbers(m.water_velocity_earth_mmps);
  m.water_velocity_earth_flag = in.flag();
  m.roll_deg = in.number();
  m.pitch_deg = in.number();
  m.yaw_deg = in.number();
  m.altitude_m = in.number();
  m.temperature_degc = in.number();
  m.pressure = in.number();
  m.salinity_ppt = in.number();
  m.sound_speed_mps = in.integer(0, 99999);
  if (!in.error().empty()) return malformed(consumed, in.error());

  ParseResult<Nq1> r;
  r.status = ParseStatus::kComplete;
  r.consumed = consumed;
  r.message = m;
  return r;
}

std::optional<std::array<double, 3>> vehicle_velocity_mps(const Nq1& m) {
  if (m.velocity_instrument_flag != VelocityFlag::kBottom) return std::nullopt;
  std::array<double, 3> v{};
  for (std::size_t i = 0; i < 3; ++i) v[i] = -m.velocity_instrument_mmps[i] / 1000.0;
  return v;
}

}  // namespace nav::protocols::navquest_nq1

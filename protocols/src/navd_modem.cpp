// SPDX-License-Identifier: MIT
// `$PNVBPOS` position report sent over an acoustic modem (docs/dut-contract.md):
//
//   $PNVBPOS,<id>,<t_s>,<lat_deg>,<lon_deg>,<depth_m>,<std_m>*hh<CR><LF>
//
//   index  field     format  unit, range
//   0      id        uint    sender's vehicle id, 0..255
//   1      t_s       %.3f    sender's AHRS time of the solution [s], [0, 99999.999]
//   2      lat_deg   %.6f    [deg] + North, [-90, 90]
//   3      lon_deg   %.6f    [deg] + East, [-180, 180]
//   4      depth_m   %.2f    [m] + down, [-999.99, 9999.99]
//   5      std_m     %.1f    horizontal 1-sigma per axis [m], [0, 999.9], rounded up
//
// Length budget (one 64-byte modem packet): "$PNVBPOS," 9 + "255," 4 + "99999.999," 10 +
// "-90.000000," 11 + "-180.000000," 12 + "9999.99," 8 (or "-999.99,") + "999.9" 5 + "*hh" 3
// + CR LF 2 = 64.
//
// Numbers go through std::to_chars / std::from_chars: no locale can turn '.' into ','.
#include "nav/protocols/navd_modem.hpp"

#include <array>
#include <charconv>
#include <cmath>

#include "nav/common/ensure.hpp"

namespace nav::protocols::navd_modem {
namespace {

constexpr std::size_t kFieldCount = 6;
constexpr std::array<const char*, kFieldCount> kFieldNames = {
    "id", "t_s", "lat_deg", "lon_deg", "depth_m", "std_m"};

Error field_error(std::size_t index, const std::string& text, const char* why) {
  return Error{ErrorCode::kParse,
               std::string("PNVBPOS field ") + kFieldNames[index] + " '" + text + "' " + why};
}

/// [-]digits[.digits]: what encode() writes, without exponent, sign '+' or blanks.
bool is_plain_decimal(const std::string& f) {
  std::size_t i = (!f.empty() && f[0] == '-') ? 1 : 0;
  std::size_t digits = 0;
  bool dot = false;
  for (; i < f.size(); ++i) {
    if (f[i] >= '0' && f[i] <= '9') {
      ++digits;
    } else if (f[i] == '.' && !dot) {
      dot = true;
    } else {
      return false;
    }
  }
  return digits > 0;
}

bool in_range(double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; }

/// std rounded up to the printed resolution, so a receiver never sees less uncertainty than
/// the sender had; the 1e-6 keeps exact tenths (1.2 * 10 = 12.000000000000002) where they are.
double std_rounded_up(double std_m) {
  const double scale = std::pow(10.0, kStdDecimals);
  return std::min(kMaxStdM, std::ceil(std_m * scale - 1e-6) / scale);
}

}  // namespace

bool encodable(const Position& p) {
  return in_range(p.t_s, 0.0, kMaxTimeS) && in_range(p.lat_deg, -90.0, 90.0) &&
         in_range(p.lon_deg, -180.0, 180.0) && in_range(p.depth_m, kMinDepthM, kMaxDepthM) &&
         std::isfinite(p.horizontal_std_m) && p.horizontal_std_m >= 0.0;
}

std::string encode(const Position& p) {
  NAV_ENSURE(encodable(p), "PNVBPOS report out of range: t_s " + std::to_string(p.t_s) +
                               " lat " + std::to_string(p.lat_deg) + " lon " +
                               std::to_string(p.lon_deg) + " depth " +
                               std::to_string(p.depth_m) + " std " +
                               std::to_string(p.horizontal_std_m));
  nmea::Sentence sentence{"P", "NVBPOS", {}};
  auto& f = sentence.fields;
  f.reserve(kFieldCount);
  f.push_back(std::to_string(static_cast<unsigned>(p.vehicle_id)));
  f.push_back(nmea::format_fixed(p.t_s, kTimeDecimals));
  f.push_back(nmea::format_fixed(p.lat_deg, kLatLonDecimals));
  f.push_back(nmea::format_fixed(p.lon_deg, kLatLonDecimals));
  f.push_back(nmea::format_fixed(p.depth_m, kDepthDecimals));
  f.push_back(nmea::format_fixed(std_rounded_up(p.horizontal_std_m), kStdDecimals));
  std::string text = nmea::frame(sentence);
  NAV_ENSURE(text.size() <= kMaxPacketBytes, "PNVBPOS longer than one modem packet: " + text);
  return text;
}

Result<Position> decode(const nmea::Sentence& s) {
  if (s.talker != "P" || s.type != "NVBPOS") {
    return fail(ErrorCode::kParse, "sentence $" + s.talker + s.type + " is not " + kAddress);
  }
  const auto& f = s.fields;
  if (f.size() != kFieldCount) {
    return fail(ErrorCode::kParse, "PNVBPOS has " + std::to_string(f.size()) + " fields, needs " +
                                       std::to_string(kFieldCount));
  }
  Position out;
  unsigned id = 0;
  const auto [end, ec] = std::from_chars(f[0].data(), f[0].data() + f[0].size(), id);
  if (f[0].empty() || f[0].size() > 3 || ec != std::errc{} ||
      end != f[0].data() + f[0].size()) {
    return tl::unexpected(field_error(0, f[0], "is not an integer 0..255"));
  }
  if (id > 255) return tl::unexpected(field_error(0, f[0], "is outside 0..255"));
  out.vehicle_id = static_cast<std::uint8_t>(id);

  struct Rule {
    double* target;
    double lo, hi;
  };
  const std::array<Rule, kFieldCount> rules = {{{nullptr, 0.0, 0.0},
                                                {&out.t_s, 0.0, kMaxTimeS},
                                                {&out.lat_deg, -90.0, 90.0},
                                                {&out.lon_deg, -180.0, 180.0},
                                                {&out.depth_m, kMinDepthM, kMaxDepthM},
                                                {&out.horizontal_std_m, 0.0, kMaxStdM}}};
  for (std::size_t i = 1; i < kFieldCount; ++i) {
    const auto v = is_plain_decimal(f[i]) ? nmea::parse_number(f[i]) : std::nullopt;
    if (!v) return tl::unexpected(field_error(i, f[i], "is not a plain decimal number"));
    if (*v < rules[i].lo || *v > rules[i].hi) {
      return tl::unexpected(field_error(i, f[i], "is out of range"));
    }
    *rules[i].target = *v;
  }
  return out;
}

ParseResult<Position> parse(ByteSpan buffer) {
  auto framed = nmea::parse_with_limit(buffer, kMaxSentence);
  ParseResult<Position> r;
  r.status = framed.status;
  r.consumed = framed.consumed;
  r.error = std::move(framed.error);
  if (framed.status != ParseStatus::kComplete) return r;
  const nmea::Sentence& s = *framed.message;
  if (s.talker + s.type != kAddress) {
    r.status = ParseStatus::kMalformed;
    r.error = "address $" + s.talker + s.type + " is not " + kAddress;
    return r;
  }
  auto p = decode(s);
  if (!p) {
    r.status = ParseStatus::kMalformed;
    r.error = "fields: " + p.error().detail;
    return r;
  }
  r.message = *p;
  return r;
}

}  // namespace nav::protocols::navd_modem

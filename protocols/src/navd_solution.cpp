// SPDX-License-Identifier: MIT
// `$PNVBSOL` navigation solution sentence of the DUT (docs/dut-contract.md):
//
//   $PNVBSOL,<input>,<trigger_tag>,<seq>,<lat_deg>,<lon_deg>,<depth_m>,<vn>,<ve>,<vd>,
//            <roll_deg>,<pitch_deg>,<yaw_deg>,<status>*hh<CR><LF>
//
//   index  field       format   unit
//   0      input       text     trigger input role (no ',', '*', '$')
//   1      trigger_tag uint64   the trigger's own time tag (GX3 timer ticks)
//   2      seq         uint64   solution counter
//   3      lat_deg     %.9f     [deg] + North    (3..8 all empty when position_valid is false)
//   4      lon_deg     %.9f     [deg] + East
//   5      depth_m     %.3f     [m]   + down
//   6..8   vn, ve, vd  %.4f     [m/s] NED
//   9..11  roll, pitch, yaw  %.4f  [deg] ZYX Euler of q_nb
//   12     status      text     OK, ALIGNING, DEGRADED
//
// Numbers go through std::to_chars / std::from_chars: no locale can turn '.' into ','.
#include "nav/protocols/navd_solution.hpp"

#include <array>
#include <charconv>
#include <cmath>

#include "nav/common/ensure.hpp"

namespace nav::protocols::navd {
namespace {

constexpr std::size_t kFieldCount = 13;
constexpr std::size_t kFirstPositionField = 3;
constexpr std::size_t kLastPositionField = 8;

constexpr std::array<const char*, kFieldCount> kFieldNames = {
    "input",  "trigger_tag", "seq",      "lat_deg",   "lon_deg", "depth_m", "vn_mps",
    "ve_mps", "vd_mps",      "roll_deg", "pitch_deg", "yaw_deg", "status"};

bool is_plain_text(const std::string& s) {
  for (const char c : s) {
    if (c < 0x20 || c > 0x7E || c == ',' || c == '*' || c == '$') return false;
  }
  return true;
}

std::string format_u64(std::uint64_t v) {
  char buf[24];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  NAV_ENSURE(ec == std::errc{}, "uint64 formatting");
  return std::string(buf, end);
}

Error field_error(std::size_t index, const std::string& text, const char* why) {
  return Error{ErrorCode::kParse,
               std::string("PNVBSOL field ") + kFieldNames[index] + " '" + text + "' " + why};
}

}  // namespace

std::string encode(const Solution& s) {
  NAV_ENSURE(!s.input.empty() && is_plain_text(s.input),
             "PNVBSOL input must be non-empty text without ',', '*', '$': '" + s.input + "'");
  NAV_ENSURE(is_plain_text(s.status),
             "PNVBSOL status must be text without ',', '*', '$': '" + s.status + "'");

  nmea::Sentence sentence{"P", "NVBSOL", {}};
  auto& f = sentence.fields;
  f.reserve(kFieldCount);
  f.push_back(s.input);
  f.push_back(format_u64(s.trigger_tag));
  f.push_back(format_u64(s.seq));
  if (s.position_valid) {
    NAV_ENSURE(std::fabs(s.lat_deg) <= 90.0, "PNVBSOL latitude outside [-90, 90]");
    NAV_ENSURE(std::fabs(s.lon_deg) <= 180.0, "PNVBSOL longitude outside [-180, 180]");
    f.push_back(nmea::format_fixed(s.lat_deg, 9));
    f.push_back(nmea::format_fixed(s.lon_deg, 9));
    f.push_back(nmea::format_fixed(s.depth_m, 3));
    f.push_back(nmea::format_fixed(s.vn_mps, 4));
    f.push_back(nmea::format_fixed(s.ve_mps, 4));
    f.push_back(nmea::format_fixed(s.vd_mps, 4));
  } else {
    f.insert(f.end(), kLastPositionField - kFirstPositionField + 1, std::string{});
  }
  f.push_back(nmea::format_fixed(s.roll_deg, 4));
  f.push_back(nmea::format_fixed(s.pitch_deg, 4));
  f.push_back(nmea::format_fixed(s.yaw_deg, 4));
  f.push_back(s.status);
  return nmea::frame(sentence);
}

Result<Solution> decode(const nmea::Sentence& s) {
  if (s.talker != "P" || s.type != "NVBSOL") {
    return fail(ErrorCode::kParse, "sentence $" + s.talker + s.type + " is not " + kAddress);
  }
  const auto& f = s.fields;
  if (f.size() != kFieldCount) {
    return fail(ErrorCode::kParse, "PNVBSOL has " + std::to_string(f.size()) + " fields, needs " +
                                       std::to_string(kFieldCount));
  }

  Solution out;
  if (f[0].empty()) return tl::unexpected(field_error(0, f[0], "is empty"));
  out.input = f[0];
  for (std::size_t i : {std::size_t{1}, std::size_t{2}}) {
    std::uint64_t v = 0;
    const auto [end, ec] = std::from_chars(f[i].data(), f[i].data() + f[i].size(), v);
    if (f[i].empty() || ec != std::errc{} || end != f[i].data() + f[i].size()) {
      return tl::unexpected(field_error(i, f[i], "is not an unsigned integer"));
    }
    (i == 1 ? out.trigger_tag : out.seq) = v;
  }

  // Position and velocity: all six present, or all six empty.
  std::size_t empty_count = 0;
  for (std::size_t i = kFirstPositionField; i <= kLastPositionField; ++i) {
    empty_count += f[i].empty() ? 1 : 0;
  }
  out.position_valid = empty_count == 0;
  if (empty_count != 0 && empty_count != kLastPositionField - kFirstPositionField + 1) {
    for (std::size_t i = kFirstPositionField; i <= kLastPositionField; ++i) {
      if (f[i].empty()) {
        return tl::unexpected(field_error(i, f[i], "is empty while other position fields are not"));
      }
    }
  }
  const std::array<double*, kFieldCount> targets = {
      nullptr,        nullptr,      nullptr,     &out.lat_deg, &out.lon_deg,
      &out.depth_m,   &out.vn_mps,  &out.ve_mps, &out.vd_mps,  &out.roll_deg,
      &out.pitch_deg, &out.yaw_deg, nullptr};
  for (std::size_t i = kFirstPositionField; i < kFieldCount - 1; ++i) {
    if (i <= kLastPositionField && !out.position_valid) continue;
    const auto v = nmea::parse_number(f[i]);
    if (!v) return tl::unexpected(field_error(i, f[i], "is not a finite number"));
    *targets[i] = *v;
  }
  if (std::fabs(out.lat_deg) > 90.0) {
    return tl::unexpected(field_error(3, f[3], "is outside [-90, 90]"));
  }
  if (std::fabs(out.lon_deg) > 180.0) {
    return tl::unexpected(field_error(4, f[4], "is outside [-180, 180]"));
  }
  out.status = f[12];
  return out;
}

}  // namespace nav::protocols::navd

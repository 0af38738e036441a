// SPDX-License-Identifier: MIT
// The DUT output sentence `$PNVBSOL` (docs/dut-contract.md): one navigation solution that
// names the input it answers. NMEA 0183 framing (checksum, CRLF), proprietary address.
#pragma once

#include <cstdint>
#include <string>

#include "nav/common/result.hpp"
#include "nav/protocols/nmea0183.hpp"

namespace nav::protocols::navd {

inline constexpr const char* kAddress = "PNVBSOL";  ///< talker "P" + "NVBSOL"

/// Length limit for reading $PNVBSOL ('$' through the checksum) [chars]. A full-precision
/// solution can exceed gpsd's 130 (nmea::kMaxSentence), so read navd output with
/// nmea::parse_with_limit(buffer, navd::kMaxSentence). 256 holds a 20-digit tag and seq,
/// 16-char input and status, |depth| < 1e6 m and |v| < 1e4 m/s.
inline constexpr std::size_t kMaxSentence = 256;

/// One navigation solution.
struct Solution {
  std::string input;             ///< trigger input role, e.g. "AHRS"
  std::uint64_t trigger_tag = 0; ///< the trigger's own time tag as received (GX3 timer ticks)
  std::uint64_t seq = 0;         ///< solution counter, from 0
  bool position_valid = false;   ///< false: lat/lon/depth/velocity fields are empty
  double lat_deg = 0.0;          ///< [deg], + North
  double lon_deg = 0.0;          ///< [deg], + East
  double depth_m = 0.0;          ///< depth below mean sea level [m], + down (= -altitude)
  double vn_mps = 0.0, ve_mps = 0.0, vd_mps = 0.0;  ///< velocity, NED [m/s]
  double roll_deg = 0.0, pitch_deg = 0.0, yaw_deg = 0.0;  ///< ZYX Euler of q_nb [deg]
  std::string status = "OK";     ///< OK, ALIGNING, DEGRADED (free text without commas)
};

/// Frames a solution as a `$PNVBSOL` sentence with CRLF.
std::string encode(const Solution& s);

/// Decodes the fields of an already framed sentence whose address is PNVBSOL.
Result<Solution> decode(const nmea::Sentence& s);

}  // namespace nav::protocols::navd

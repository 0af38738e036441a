// SPDX-License-Identifier: MIT
// Teledyne RDI PD6 ASCII output (protocols.md section 3c): the :SA, :TS, :WI, :WS, :WE, :WD,
// :BI, :BS, :BE and :BD lines, each CRLF-terminated, without checksum. Values stay in wire
// units (mm/s, m, s, deg, °C). :BI/:BS/:BE/:BD are CONFIRMED (Pathfinder guide Table 50,
// H-ADCP manual Table 49); :SA and :TS are PARTIAL; :WI/:WS/:WE are PARTIAL (by analogy with
// :BI/:BS/:BE); exact padding is UNCONFIRMED (no capture). The Pathfinder-only :HM line is
// not supported. PD6 velocities assume a stationary bottom and a moving vehicle (Pathfinder
// guide p.206), the opposite sign of PD0 bottom track.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <variant>

#include "nav/protocols/parse.hpp"

namespace nav::protocols::rdi_pd6 {

inline constexpr int kBadVelocity = -32768;   ///< printed for a velocity that is not valid
inline constexpr std::size_t kMaxLine = 128;  ///< longest accepted line, ':' to LF [chars]

/// Which track a velocity or distance line belongs to: :W* water mass, :B* bottom.
enum class Track { kWater, kBottom };

/// :SA,±PP.PP,±RR.RR,HHH.HH — attitude (PARTIAL: pitch first, as two code sources read it).
struct Attitude {
  double pitch_deg = 0.0;    ///< [deg]
  double roll_deg = 0.0;     ///< [deg]
  double heading_deg = 0.0;  ///< [deg], 0..360
};

/// :TS,YYMMDDHHmmsshh,SS.S,+TT.T,DDDD.D,CCCC.C,BBB[,L] — time and scaling (PARTIAL).
struct TimeAndScaling {
  int year = 2000;         ///< full year; the wire has two digits (00..79 -> 20xx, 80..99 -> 19xx)
  int month = 1, day = 1;  ///< date
  int hour = 0, minute = 0, second = 0, hundredths = 0;  ///< time of day, [1/100 s] last
  double salinity_ppt = 0.0;                             ///< [ppt]
  double temperature_degc = 0.0;                         ///< [°C]
  double depth_m = 0.0;                                  ///< transducer depth [m]
  double sound_speed_mps = 1500.0;                       ///< [m/s]
  int bit_result = 0;                                    ///< built-in test result, 0 = ok
  std::optional<char> leak;                              ///< Rowe's optional leak flag O / W / X
};

/// :BI / :WI — velocity in instrument coordinates [mm/s]: x (+ Bm1 -> Bm2 transducer
/// movement), y (+ Bm4 -> Bm3), z (+ away from the bottom), error velocity.
struct InstrumentVelocity {
  Track track = Track::kBottom;    ///< :B* (bottom) or :W* (water mass)
  std::array<int, 4> xyze_mmps{};  ///< x, y, z, error [mm/s]; kBadVelocity when not valid
  bool valid = false;              ///< status A (true) / V (false)
};

/// :BS / :WS — velocity in ship coordinates [mm/s].
struct ShipVelocity {
  Track track = Track::kBottom;  ///< :B* (bottom) or :W* (water mass)
  int transverse_mmps = 0;       ///< + port -> starboard [mm/s]
  int longitudinal_mmps = 0;     ///< + aft -> forward [mm/s]
  int normal_mmps = 0;           ///< + away from the bottom [mm/s]
  bool valid = false;            ///< status A / V
};

/// :BE / :WE — velocity in earth coordinates [mm/s], + = DVL moving east / north / up.
struct EarthVelocity {
  Track track = Track::kBottom;                    ///< :B* (bottom) or :W* (water mass)
  int east_mmps = 0, north_mmps = 0, up_mmps = 0;  ///< [mm/s]
  bool valid = false;                              ///< status A / V
};

/// :BD / :WD — distance made good in earth coordinates since the first good velocity.
struct Distance {
  Track track = Track::kBottom;                    ///< :B* (bottom) or :W* (water mass)
  double east_m = 0.0, north_m = 0.0, up_m = 0.0;  ///< [m]
  double range_m = 0.0;            ///< range to the bottom (:BD) or water-mass centre (:WD) [m]
  double time_since_good_s = 0.0;  ///< time since the last good velocity [s]
};

/// One PD6 line.
using Line = std::variant<Attitude, TimeAndScaling, InstrumentVelocity, ShipVelocity, EarthVelocity,
                          Distance>;

/// Encodes a line with CRLF, fields right-justified with spaces to the manual's widths
/// (±XXXXX = 6, ±PP.PP = 6, ±EEEEEEEE.EE = 12, …) with explicit '+' on signed fields, as in
/// protocols.md's illustrative block; a value wider than its field widens the field.
std::string encode(const Line& line);

/// Parses a line at the start of the buffer. Fields are trimmed of spaces, so space- or
/// zero-padded fields both parse. Bytes before ':', an unknown line type, a wrong field count,
/// a field that does not parse or a status other than A / V are malformed; a ':' inside a line
/// ends it (malformed) so the next line is not lost.
ParseResult<Line> parse(ByteSpan buffer);

/// A wire velocity in m/s, or nullopt for kBadVelocity [m/s].
std::optional<double> to_mps(int mmps);

}  // namespace nav::protocols::rdi_pd6

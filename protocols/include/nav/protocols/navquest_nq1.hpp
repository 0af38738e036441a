// SPDX-License-Identifier: MIT
// LinkQuest NavQuest 600 (Micro) NQ1 output line (protocols.md section 3a):
//   "$#NQ.RES" then 46 single-space separated tokens, the last a decimal XOR checksum, CRLF.
// Field order and checksum CONFIRMED (DUNE, AVL, cola2 drivers and a real line); units and
// the velocity sign PARTIAL. Values stay in wire units (mm/s, m, deg, °C).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "nav/protocols/parse.hpp"

namespace nav::protocols::navquest_nq1 {

inline constexpr std::string_view kHeader = "$#NQ.RES";  ///< first token of every line
inline constexpr std::size_t kTokenCount = 47;           ///< header, 45 fields, checksum
inline constexpr std::size_t kMaxLine = 512;  ///< longest accepted line, '$' to LF [chars]

/// Source of a velocity solution (the *_flag tokens).
enum class VelocityFlag : int {
  kInvalid = 0,  ///< no solution
  kBottom = 1,   ///< bottom track
  kWater = 2,    ///< water track
};

/// One NQ1 line.
struct Nq1 {
  std::uint16_t error_code = 0;                      ///< device error bits, printed "0X%04X"
  std::array<bool, 4> beam_good{};                   ///< per beam: bottom detected (1) or not (0)
  std::array<double, 4> beam_altitude_m{};           ///< per-beam vertical range [m], < 0 invalid
  std::array<double, 4> bottom_radial_mmps{};        ///< bottom-track radial velocity [mm/s]
  std::array<double, 4> water_radial_mmps{};         ///< water-track radial velocity [mm/s]
  std::array<int, 4> water_credit{};                 ///< water-track quality, 0..50
  std::array<double, 3> velocity_instrument_mmps{};  ///< instrument x, y, z [mm/s] (sign: see
                                                     ///< vehicle_velocity_mps)
  VelocityFlag velocity_instrument_flag = VelocityFlag::kInvalid;  ///< its source
  std::array<double, 3> velocity_earth_mmps{};                     ///< earth x, y, z [mm/s]
  VelocityFlag velocity_earth_flag = VelocityFlag::kInvalid;       ///< its source
  std::array<double, 3> water_velocity_instrument_mmps{};  ///< water track, instrument [mm/s]
  VelocityFlag water_velocity_instrument_flag = VelocityFlag::kInvalid;  ///< 0 or 2
  std::array<double, 3> water_velocity_earth_mmps{};                ///< water track, earth [mm/s]
  VelocityFlag water_velocity_earth_flag = VelocityFlag::kInvalid;  ///< 0 or 2
  double roll_deg = 0.0;                                            ///< [deg]
  double pitch_deg = 0.0;                                           ///< [deg]
  double yaw_deg = 0.0;                                             ///< heading [deg]
  double altitude_m = 0.0;                                          ///< altitude estimate [m]
  double temperature_degc = 0.0;                                    ///< water temperature [°C]
  double pressure = 0.0;       ///< pressure, unit unknown; invalid on the Micro (doc)
  double salinity_ppt = 0.0;   ///< [ppt]
  int sound_speed_mps = 1500;  ///< speed of sound used [m/s], an integer on the wire
};

/// XOR of the characters from the first space after the header up to, excluding, the space
/// before the checksum token (DUNE's rule, protocols.md 3a).
std::uint8_t checksum(std::string_view between);

/// Encodes a line with CRLF. Number format follows the real line in protocols.md: exact zeros
/// as "0" (how the device prints fields it does not measure), otherwise one decimal; pressure
/// three decimals; flags, credits and sound speed as integers.
std::string encode(const Nq1& m);

/// Parses a line at the start of the buffer. Bytes before a '$', a line whose first token is
/// not "$#NQ.RES" (e.g. a command reply), a wrong token count, a token that does not parse or
/// a wrong checksum are malformed; a line without its LF yet needs more.
ParseResult<Nq1> parse(ByteSpan buffer);

/// Vehicle (DVL) velocity over the bottom in the instrument frame [m/s], when the instrument
/// velocity is a bottom-track solution. NQ1 reports the bottom's velocity relative to the DVL,
/// so this negates it (DUNE and AVL both do; PARTIAL: no manual confirms the sign).
std::optional<std::array<double, 3>> vehicle_velocity_mps(const Nq1& m);

}  // namespace nav::protocols::navquest_nq1

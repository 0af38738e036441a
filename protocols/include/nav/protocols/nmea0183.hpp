// SPDX-License-Identifier: MIT
// NMEA 0183 framing and the GGA / RMC sentences of a GPS receiver (protocols.md section 4).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "nav/common/result.hpp"
#include "nav/protocols/parse.hpp"

namespace nav::protocols::nmea {

inline constexpr std::size_t kMaxSentence = 130;  ///< gpsd's NMEA_MAX [chars]

/// One framed sentence: "$" talker type "," fields "*hh" CRLF.
struct Sentence {
  std::string talker;               ///< e.g. "GP", or "P" for proprietary
  std::string type;                 ///< e.g. "GGA"; for proprietary the rest of the address
  std::vector<std::string> fields;  ///< fields after the address, empty = no data
};

/// XOR of the characters between '$' and '*'.
std::uint8_t checksum(std::string_view body);

/// Frames a sentence: adds '$', the checksum as two upper-case hex digits, and CRLF.
std::string frame(const Sentence& s);

/// Parses a sentence at the start of the buffer; bytes before a '$' are malformed.
/// Accepts CRLF or bare LF; a missing or wrong checksum is malformed.
ParseResult<Sentence> parse(ByteSpan buffer);

/// As parse(), with another length limit ('$' through the checksum) [chars]: for
/// sentences not meant for gpsd that can be longer, e.g. navd::kMaxSentence for $PNVBSOL.
ParseResult<Sentence> parse_with_limit(ByteSpan buffer, std::size_t max_sentence);

/// UTC time of day and date as carried by NMEA sentences.
struct UtcTime {
  int year = 0, month = 0, day = 0;  ///< date (RMC/ZDA); 0 when absent
  int hour = 0, minute = 0;          ///< time of day
  double second = 0.0;               ///< [s], with fraction
  /// Seconds since 1970-01-01T00:00:00Z (date required) [s].
  double unix_seconds() const;
  /// From seconds since 1970-01-01T00:00:00Z, rounded to the centisecond NMEA carries.
  static UtcTime from_unix_seconds(double s);
};

/// GGA: fix data. Absent numeric fields are nullopt.
struct Gga {
  UtcTime time;                   ///< time of fix (time of day only)
  std::optional<double> lat_deg;  ///< latitude [deg], + North
  std::optional<double> lon_deg;  ///< longitude [deg], + East
  int quality = 0;                ///< 0 no fix, 1 GPS, 2 DGPS, ...
  int satellites = 0;             ///< satellites used
  std::optional<double> hdop;     ///< horizontal dilution of precision [-]
  std::optional<double> alt_msl_m;     ///< altitude above mean sea level [m]
  std::optional<double> geoid_sep_m;   ///< geoid separation [m]
};

/// RMC: recommended minimum data.
struct Rmc {
  UtcTime time;                   ///< time and date of fix
  bool valid = false;             ///< status A (true) or V (false)
  std::optional<double> lat_deg;  ///< [deg], + North
  std::optional<double> lon_deg;  ///< [deg], + East
  std::optional<double> sog_kn;   ///< speed over ground [knots]
  std::optional<double> cog_deg;  ///< course over ground, true [deg]
  char mode = 'A';                ///< FAA mode indicator (A autonomous, N no fix, ...)
};

/// Builds a GGA sentence (talker "GP" unless given); lat/lon with 5 decimals of minutes.
Sentence to_sentence(const Gga& g, std::string talker = "GP");
Sentence to_sentence(const Rmc& r, std::string talker = "GP");

/// Decodes GGA / RMC fields; a field that does not parse is an error naming it.
Result<Gga> decode_gga(const Sentence& s);
Result<Rmc> decode_rmc(const Sentence& s);

/// Field text helpers shared by every NMEA-framed codec; locale-independent
/// (std::to_chars / std::from_chars), so a process locale with ',' decimals cannot break them.

/// Formats a finite value with `decimals` digits after the point; "-0.00" becomes "0.00".
std::string format_fixed(double value, int decimals);

/// Parses a whole field as a finite decimal number; nullopt if empty, partial or not finite.
std::optional<double> parse_number(std::string_view field);

}  // namespace nav::protocols::nmea

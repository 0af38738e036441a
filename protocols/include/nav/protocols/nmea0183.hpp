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

/// VTG: course and speed over ground. Encoded in the NMEA >= 3.01 form with unit letters
/// (`cog_t,T,cog_m,M,sog_kn,N,sog_kmh,K[,mode]`); decode_vtg() also reads the old form
/// without unit letters (`cog_t,cog_m,sog_kn,sog_kmh`), told apart by field 2 == "T".
struct Vtg {
  std::optional<double> cog_true_deg;  ///< course over ground, true [deg]
  std::optional<double> cog_mag_deg;   ///< course over ground, magnetic [deg]
  std::optional<double> sog_kn;        ///< speed over ground [knots]
  std::optional<double> sog_kmh;       ///< speed over ground [km/h], sent as its own field
  std::optional<char> mode;            ///< FAA mode (NMEA >= 2.3); nullopt: no mode field
};

/// HDT: true heading (gyro compass, INS or GNSS compass).
struct Hdt {
  std::optional<double> heading_deg;  ///< true heading [deg] in [0, 360); nullopt: empty field
};

/// ZDA: UTC date and time with the local time zone.
struct Zda {
  UtcTime time;                     ///< UTC date and time of day (date required)
  std::optional<int> zone_hours;    ///< local zone hours [h], -13..13; nullopt: empty field
  std::optional<int> zone_minutes;  ///< local zone minutes [min], 0..59; nullopt: empty field
};

/// Builds VTG (courses with 2 decimals, speeds with 3), HDT (2 decimals) and ZDA sentences.
Sentence to_sentence(const Vtg& v, std::string talker = "GP");
Sentence to_sentence(const Hdt& h, std::string talker = "GP");
Sentence to_sentence(const Zda& z, std::string talker = "GP");

/// Decodes VTG (either form) / HDT / ZDA fields; a field that does not parse is an error
/// naming it.
Result<Vtg> decode_vtg(const Sentence& s);
Result<Hdt> decode_hdt(const Sentence& s);
Result<Zda> decode_zda(const Sentence& s);

/// "hhmmss.ss" of a time of day, rounded to the centisecond and wrapped into one day.
std::string format_time_of_day(const UtcTime& t);

/// Parses "hhmmss[.sss]" into the time-of-day part of t; an empty field leaves t unchanged.
/// False if the field is not a time of day.
bool parse_time_of_day(std::string_view field, UtcTime& t);

/// Field text helpers shared by every NMEA-framed codec; locale-independent
/// (std::to_chars / std::from_chars), so a process locale with ',' decimals cannot break them.

/// Formats a finite value with `decimals` digits after the point; "-0.00" becomes "0.00".
std::string format_fixed(double value, int decimals);

/// Formats a finite value with `digits` significant digits and no exponent (12.3457,
/// -0.000123457, 0), at most 12 decimals; "-0" becomes "0".
std::string format_significant(double value, int digits = 6);

/// Parses a whole field as a finite decimal number; nullopt if empty, partial or not finite.
std::optional<double> parse_number(std::string_view field);

}  // namespace nav::protocols::nmea

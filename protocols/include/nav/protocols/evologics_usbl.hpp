// SPDX-License-Identifier: MIT
// EvoLogics USBL modem position notifications USBLLONG and USBLANGLES (protocols.md 6c).
//
//   data mode     "+++AT:" <len> ":" <payload> CR LF    <len> = byte length of <payload>
//   command mode  <payload> CR LF                        (framing PARTIAL per protocols.md)
//   payload       "USBLLONG," 16 values | "USBLANGLES," 13 values, comma-separated, no checksum
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include "nav/common/result.hpp"
#include "nav/protocols/parse.hpp"

namespace nav::protocols::evologics {

inline constexpr std::string_view kDataModePrefix = "+++AT:";  ///< data-mode wrapper start
/// Bound on a payload and on a command-mode line [chars]. Chosen here: the real USBLLONG
/// sample is 124 characters.
inline constexpr std::size_t kMaxPayload = 512;

/// How a notification is wrapped on the wire.
enum class Framing {
  kDataMode,     ///< "+++AT:<len>:<payload>\r\n"
  kCommandMode,  ///< "<payload>\r\n"
};

/// USBLLONG: position of a remote modem. Times are the modem's system clock, not UTC.
struct UsblLong {
  double current_time_s = 0.0;      ///< modem time when the line was sent [s], µs resolution
  double measurement_time_s = 0.0;  ///< modem time of the measurement [s], µs resolution
  int remote_address = 0;           ///< acoustic address of the remote modem
  /// Position of the remote in the transceiver (local) frame [m]; axis convention not given
  /// by the sources (UNCONFIRMED).
  double x_m = 0.0, y_m = 0.0, z_m = 0.0;
  /// Motion-compensated position (internal AHRS), east/north/up [m].
  double e_m = 0.0, n_m = 0.0, u_m = 0.0;
  /// Transceiver attitude [rad]: radians by analogy with USBLANGLES (PARTIAL).
  double roll_rad = 0.0, pitch_rad = 0.0, yaw_rad = 0.0;
  int propagation_time_us = 0;        ///< one-way propagation time [µs]; range = t * c * 1e-6
  int rssi_db = 0;                    ///< received signal strength [dB]
  int integrity = 0;                  ///< signal integrity [-], link weak below 100
  double accuracy_m = 0.0;            ///< position accuracy estimate [m]
};

/// USBLANGLES: direction to a remote modem.
struct UsblAngles {
  double current_time_s = 0.0;      ///< modem time when the line was sent [s]
  double measurement_time_s = 0.0;  ///< modem time of the measurement [s]
  int remote_address = 0;           ///< acoustic address of the remote modem
  double local_bearing_rad = 0.0;     ///< bearing in the transceiver frame [rad]
  double local_elevation_rad = 0.0;   ///< elevation in the transceiver frame [rad]
  double bearing_rad = 0.0;           ///< motion-compensated bearing [rad]
  double elevation_rad = 0.0;         ///< motion-compensated elevation [rad]
  double roll_rad = 0.0, pitch_rad = 0.0, yaw_rad = 0.0;  ///< transceiver attitude [rad]
  int rssi_db = 0;                    ///< received signal strength [dB]
  int integrity = 0;                  ///< signal integrity [-], link weak below 100
  double accuracy_m = 0.0;            ///< accuracy estimate [m]; -1 = invalid
};

/// NVBRELATT, navbench's extension (not an EvoLogics notification): the remote vehicle's
/// heading and pitch relative to the receiving one, as an inverted USBL on a vehicle reports
/// them alongside its USBLLONG of the same ping (paper P2's heading and pitch observations;
/// docs/wire-formats.md, "iUSBL"). Same framing and time fields as the others:
///   NVBRELATT,<current_time>,<measurement_time>,<remote_addr>,<rel_heading>,<rel_pitch>
struct RelativeAttitude {
  double current_time_s = 0.0;      ///< modem time when the line was sent [s]
  double measurement_time_s = 0.0;  ///< modem time of the measurement [s]
  int remote_address = 0;           ///< acoustic address of the remote modem
  double relative_heading_rad = 0.0;  ///< ψ_remote − ψ_own, wrapped to (−π, π] [rad]
  double relative_pitch_rad = 0.0;    ///< θ_remote − θ_own [rad]
};

/// Any notification.
using UsblFix = std::variant<UsblLong, UsblAngles, RelativeAttitude>;

/// "USBLLONG", "USBLANGLES" or "NVBRELATT".
std::string_view header_of(const UsblFix& fix);

/// A notification as received: the fix and how it was wrapped.
struct Notification {
  UsblFix fix;                          ///< the decoded payload
  Framing framing = Framing::kDataMode;  ///< the wrapper it came in
};

/// Payload text without framing, e.g. "USBLLONG,10446.991981,...". Times with 6 decimals,
/// positions, angles and accuracy with 4 (as in the real sample). Values must be finite.
std::string to_payload(const UsblFix& fix);

/// Decodes a payload; an unknown notification, a wrong value count or a value that does not
/// parse is an error naming it.
Result<UsblFix> decode_payload(std::string_view payload);

/// Payload plus framing and CR LF.
std::string encode(const Notification& n);

/// Parses one notification at the start of the buffer. Bytes that cannot start a
/// notification are skipped up to the next '+' or upper-case letter; a data-mode frame whose
/// length or trailer is wrong is skipped through the next LF; a line or frame whose payload is
/// not USBLLONG/USBLANGLES/NVBRELATT is malformed as a whole. A '+' inside a command-mode line cuts it
/// short (a data-mode frame starts there).
ParseResult<Notification> parse(ByteSpan buffer);

}  // namespace nav::protocols::evologics

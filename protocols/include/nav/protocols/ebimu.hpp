// SPDX-License-Identifier: MIT
// E2BOX EBIMU-9DOF (V2/V3/V4) ASCII output lines (protocols.md section 2, PARTIAL).
//
//   '*' value { ',' value } CR LF        decimal ASCII values, no checksum
//
// The line carries no field names: which values it holds depends on the device's output
// configuration (<sof1>/<sof2>, <sog1>, <soa1>), so a line is parsed first into numbers
// (parse) and then interpreted with the configuration the host set (decode).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "nav/common/result.hpp"
#include "nav/protocols/parse.hpp"

namespace nav::protocols::ebimu {

inline constexpr char kStartOfLine = '*';  ///< every line starts with '*' (0x2A)
/// Bound on a line, '*' through LF [chars]. Chosen here (not from a vendor source): ten values
/// of the widest documented form take well under 100 characters.
inline constexpr std::size_t kMaxLine = 256;

/// Orientation output selected with <sof1> / <sof2>.
enum class Orientation {
  kEuler,       ///< <sof1>: roll, pitch, yaw [deg]
  kQuaternion,  ///< <sof2>: quaternion, sent in the order z, y, x, w
};

/// The output configuration a line is read with (the fields in their wire order).
/// Only the fields whose order is documented are modelled: orientation, gyro, then
/// accelerometer. Magnetometer, temperature, distance and battery outputs (relative order
/// UNCONFIRMED) and the <soa2..5> variants are not.
struct OutputConfig {
  Orientation orientation = Orientation::kEuler;  ///< <sof1> or <sof2>
  bool gyro = false;                              ///< <sog1>: angular rate follows
  bool accel = false;                             ///< <soa1>: acceleration follows
};

/// Number of values a line holds under `config`.
std::size_t value_count(const OutputConfig& config);

/// One line as numbers, in wire order.
struct Line {
  std::vector<double> values;  ///< the comma-separated values
};

/// One decoded sample. Exactly one of euler_deg / quat_wxyz is set. Frame and sign
/// convention of the EBIMU are not ROS ENU/FLU and are UNCONFIRMED; values are as sent.
struct Sample {
  std::optional<std::array<double, 3>> euler_deg;  ///< roll, pitch, yaw [deg]
  std::optional<std::array<double, 4>> quat_wxyz;  ///< quaternion (w, x, y, z) [-]
  std::optional<std::array<double, 3>> gyro_dps;   ///< angular rate x, y, z [deg/s]
  std::optional<std::array<double, 3>> accel_g;    ///< acceleration x, y, z [g] (unit UNCONFIRMED)
};

/// The output configuration that produces `s` (which optional fields are set).
OutputConfig config_of(const Sample& s);

/// Encodes a line: Euler angles and gyro with 2 decimals, quaternion with 4, acceleration
/// with 3 (as in the protocols.md example), CR LF at the end. Exactly one orientation form
/// must be set and every value must be finite (contract).
std::string encode(const Sample& s);

/// Parses one line at the start of the buffer. Bytes before a '*' are malformed (skipped up
/// to the next '*'); a new '*' before the line end cuts the line short (malformed up to it);
/// CR LF or a bare LF ends a line. A value that is not a decimal number is malformed.
ParseResult<Line> parse(ByteSpan buffer);

/// Interprets a parsed line under `config`; a value count that does not match is an error.
Result<Sample> decode(const Line& line, const OutputConfig& config);

/// parse() then decode(): a line that does not fit `config` is malformed (the whole line).
ParseResult<Sample> parse_sample(ByteSpan buffer, const OutputConfig& config);

}  // namespace nav::protocols::ebimu

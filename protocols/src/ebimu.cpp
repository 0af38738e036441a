// SPDX-License-Identifier: MIT
// E2BOX EBIMU-9DOF ASCII lines (protocols.md section 2, PARTIAL: layout from driver sources,
// not from a vendor manual).
//
//   '*' v1 ',' v2 ',' ... ',' vn CR LF
//   order: orientation (Euler roll,pitch,yaw [deg] | quaternion z,y,x,w), then gyro x,y,z
//          [deg/s] if enabled, then accel x,y,z [g, UNCONFIRMED] if enabled
//
// No checksum exists in ASCII mode, so only the framing and the number syntax can reject a
// line. The E2BOX example parser restarts on '*' and parses at LF; this parser does the same
// and also accepts the CR that precedes the LF.
#include "nav/protocols/ebimu.hpp"

#include <algorithm>
#include <cmath>
#include <string_view>

#include "nav/common/ensure.hpp"
#include "nav/protocols/nmea0183.hpp"

namespace nav::protocols::ebimu {
namespace {

constexpr int kEulerDecimals = 2;  ///< "-12.34" as in the Arduino library's comment
constexpr int kQuatDecimals = 4;   ///< protocols.md example
constexpr int kGyroDecimals = 2;   ///< protocols.md example
constexpr int kAccelDecimals = 3;  ///< protocols.md example

template <typename Message>
ParseResult<Message> malformed(std::size_t consumed, std::string error) {
  ParseResult<Message> r;
  r.status = ParseStatus::kMalformed;
  r.consumed = consumed;
  r.error = std::move(error);
  return r;
}

/// Offset of the next '*' after the first byte, or the buffer size.
std::size_t next_start(ByteSpan buffer) {
  const auto it = std::find(buffer.begin() + 1, buffer.end(), std::uint8_t{kStartOfLine});
  return static_cast<std::size_t>(it - buffer.begin());
}

template <std::size_t N>
void append_values(std::string& out, const std::array<double, N>& values, int decimals) {
  for (const double v : values) {
    NAV_ENSURE(std::isfinite(v), "EBIMU value is not finite");
    if (out.size() > 1) out += ',';
    out += nmea::format_fixed(v, decimals);
  }
}

/// values[at..at+N) into an array; advances `at`.
template <std::size_t N>
std::array<double, N> take(const std::vector<double>& values, std::size_t& at) {
  std::array<double, N> out{};
  for (double& v : out) v = values[at++];
  return out;
}

}  // namespace

std::size_t value_count(const OutputConfig& config) {
  return (config.orientation == Orientation::kEuler ? 3u : 4u) + (config.gyro ? 3u : 0u) +
         (config.accel ? 3u : 0u);
}

OutputConfig config_of(const Sample& s) {
  OutputConfig c;
  c.orientation = s.quat_wxyz ? Orientation::kQuaternion : Orientation::kEuler;
  c.gyro = s.gyro_dps.has_value();
  c.accel = s.accel_g.has_value();
  return c;
}

std::string encode(const Sample& s) {
  NAV_ENSURE(s.euler_deg.has_value() != s.quat_wxyz.has_value(),
             "EBIMU sample needs exactly one of Euler angles and quaternion");
  std::string out(1, kStartOfLine);
  if (s.euler_deg) {
    append_values(out, *s.euler_deg, kEulerDecimals);
  } else {
    const auto& q = *s.quat_wxyz;  // wire order z, y, x, w
    append_values(out, std::array<double, 4>{q[3], q[2], q[1], q[0]}, kQuatDecimals);
  }
  if (s.gyro_dps) append_values(out, *s.gyro_dps, kGyroDecimals);
  if (s.accel_g) append_values(out, *s.accel_g, kAccelDecimals);
  out += "\r\n";
  return out;
}

ParseResult<Line> parse(ByteSpan buffer) {
  if (buffer.empty()) return {};  // kNeedMore
  if (buffer[0] != kStartOfLine) {
    const std::size_t n = next_start(buffer);
    return malformed<Line>(n, std::to_string(n) + " byte(s) before '*'");
  }

  // Find the line end; a new '*', a stray CR, a control byte or an over-long line ends it.
  std::size_t lf = 0;
  for (std::size_t i = 1; i < buffer.size() && lf == 0; ++i) {
    const std::uint8_t c = buffer[i];
    if (c == '\n') {
      lf = i;
    } else if (c == kStartOfLine) {
      return malformed<Line>(i, "line cut short by a new '*' after " + std::to_string(i) +
                                    " byte(s)");
    } else if (c == '\r') {
      if (i + 1 < buffer.size() && buffer[i + 1] != '\n') {
        return malformed<Line>(i + 1, "CR inside a line");
      }
    } else if (c < 0x20 || c > 0x7E) {
      return malformed<Line>(i + 1, "non-printable byte at offset " + std::to_string(i));
    } else if (i + 1 >= kMaxLine) {
      return malformed<Line>(next_start(buffer),
                             "line longer than " + std::to_string(kMaxLine) + " characters");
    }
  }
  if (lf == 0) return {};  // kNeedMore: a line has started, no LF yet

  const std::size_t consumed = lf + 1;
  const std::size_t end = buffer[lf - 1] == '\r' ? lf - 1 : lf;
  const std::string text(buffer.begin() + 1, buffer.begin() + static_cast<std::ptrdiff_t>(end));
  if (text.empty()) return malformed<Line>(consumed, "line holds no values");

  Line line;
  std::size_t pos = 0;
  while (true) {
    const std::size_t comma = std::min(text.find(',', pos), text.size());
    const std::string_view field = std::string_view(text).substr(pos, comma - pos);
    const auto v = nmea::parse_number(field);
    if (!v) {
      return malformed<Line>(consumed, "value " + std::to_string(line.values.size() + 1) + " '" +
                                           std::string(field) + "' is not a number");
    }
    line.values.push_back(*v);
    if (comma == text.size()) break;
    pos = comma + 1;
  }

  ParseResult<Line> r;
  r.status = ParseStatus::kComplete;
  r.consumed = consumed;
  r.message = std::move(line);
  return r;
}

Result<Sample> decode(const Line& line, const OutputConfig& config) {
  const std::size_t expected = value_count(config);
  if (line.values.size() != expected) {
    return fail(ErrorCode::kParse, "line has " + std::to_string(line.values.size()) +
                                       " values, the output configuration gives " +
                                       std::to_string(expected));
  }
  Sample s;
  std::size_t at = 0;
  if (config.orientation == Orientation::kEuler) {
    s.euler_deg = take<3>(line.values, at);
  } else {
    const auto zyxw = take<4>(line.values, at);
    s.quat_wxyz = std::array<double, 4>{zyxw[3], zyxw[2], zyxw[1], zyxw[0]};
  }
  if (config.gyro) s.gyro_dps = take<3>(line.values, at);
  if (config.accel) s.accel_g = take<3>(line.values, at);
  return s;
}

ParseResult<Sample> parse_sample(ByteSpan buffer, const OutputConfig& config) {
  auto line = parse(buffer);
  ParseResult<Sample> r;
  r.status = line.status;
  r.consumed = line.consumed;
  r.error = std::move(line.error);
  if (line.status != ParseStatus::kComplete) return r;
  auto sample = decode(*line.message, config);
  if (!sample) return malformed<Sample>(line.consumed, sample.error().detail);
  r.message = std::move(*sample);
  return r;
}

}  // namespace nav::protocols::ebimu

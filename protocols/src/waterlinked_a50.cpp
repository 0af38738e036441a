// SPDX-License-Identifier: MIT
// Water Linked DVL-A50 / A125 serial codec (protocols.md section 3d; Water Linked
// "DVL protocol" 2.3.x, docs/dvl/dvl-protocol.md).
//
// Framing:  'w' direction command { ',' option } [ '*' hh ] [CR] LF
//   direction = 'c' (to the DVL) | 'r' (from the DVL)
//   hh        = CRC-8 (poly 0x07, init 0, no reflection, no xorout) of every byte before '*',
//               including the 'w'; two lower-case hex digits on output, either case on input.
//               Always present on DVL output, optional on commands.
#include "nav/protocols/waterlinked_a50.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <optional>

#include "nav/common/ensure.hpp"
#include "nav/protocols/nmea0183.hpp"

namespace nav::protocols::waterlinked_a50 {
namespace {

using nmea::format_fixed;
using nmea::parse_number;

constexpr char kHexDigits[] = "0123456789abcdef";

ParseResult<Packet> malformed(std::size_t consumed, std::string error) {
  ParseResult<Packet> r;
  r.status = ParseStatus::kMalformed;
  r.consumed = consumed;
  r.error = std::move(error);
  return r;
}

std::string hex8(std::uint8_t v) { return std::string{kHexDigits[v >> 4], kHexDigits[v & 0xF]}; }

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

/// Bytes from the start of the buffer to the next 'w' after `from` (or to the end).
std::size_t skip_to_next_w(ByteSpan buffer, std::size_t from) {
  const auto next = std::find(buffer.begin() + static_cast<std::ptrdiff_t>(from), buffer.end(),
                              std::uint8_t{'w'});
  return static_cast<std::size_t>(next - buffer.begin());
}

/// Shortest text that reads back as the same double ("1e-07", "0", "-40").
std::string shortest(double v) {
  NAV_ENSURE(std::isfinite(v), "Water Linked field of a non-finite value");
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  NAV_ENSURE(ec == std::errc{}, "shortest: buffer too small");
  return std::string(buf, end);
}

std::optional<std::int64_t> parse_int(std::string_view f) {
  std::int64_t v = 0;
  const auto [end, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
  if (f.empty() || ec != std::errc{} || end != f.data() + f.size()) return std::nullopt;
  return v;
}

/// Reads the options of one report, naming the failing option in the error.
class OptionReader {
 public:
  OptionReader(const Packet& p, char command, std::size_t count, const char* name)
      : p_(p), name_(name) {
    if (p.direction != 'r' || p.command != command) {
      error_ = std::string("packet w") + p.direction + p.command + " is not " + name;
    } else if (p.options.size() != count) {
      error_ = std::string(name) + " has " + std::to_string(p.options.size()) + " options, needs " +
               std::to_string(count);
    }
  }
  double number(std::size_t i, const char* field) {
    const auto v = ok() ? parse_number(p_.options[i]) : std::nullopt;
    if (!v) fail_on(i, field, "a number");
    return v.value_or(0.0);
  }
  std::int64_t integer(std::size_t i, const char* field) {
    const auto v = ok() ? parse_int(p_.options[i]) : std::nullopt;
    if (!v) fail_on(i, field, "an integer");
    return v.value_or(0);
  }
  bool yes_no(std::size_t i, const char* field) {
    const bool y = ok() && p_.options[i] == "y";
    if (ok() && !y && p_.options[i] != "n") fail_on(i, field, "y or n");
    return y;
  }
  const std::string& text(std::size_t i) const { return p_.options[i]; }
  bool ok() const { return error_.empty(); }
  void fail_on(std::size_t i, const char* field, const char* what) {
    if (ok()) {
      error_ = std::string(name_) + " " + field + " '" + p_.options[i] + "' is not " + what;
    }
  }
  template <typename T>
  Result<T> result(const T& value) const {
    if (!ok()) return fail(ErrorCode::kParse, error_);
    return value;
  }

 private:
  const Packet& p_;
  const char* name_;
  std::string error_;
};

}  // namespace

std::uint8_t crc8(std::string_view text) {
  std::uint8_t crc = 0;
  for (const char c : text) {
    crc = static_cast<std::uint8_t>(crc ^ static_cast<std::uint8_t>(c));
    for (int bit = 0; bit < 8; ++bit) {
      crc = static_cast<std::uint8_t>((crc & 0x80) != 0 ? (crc << 1) ^ 0x07 : crc << 1);
    }
  }
  return crc;
}

std::string frame(const Packet& p) {
  NAV_ENSURE(p.direction == 'c' || p.direction == 'r', "Water Linked direction is c or r");
  NAV_ENSURE(p.command > 0x20 && p.command < 0x7F && p.command != ',' && p.command != '*',
             "Water Linked command is one printable character");
  std::string body{'w', p.direction, p.command};
  for (const std::string& o : p.options) {
    NAV_ENSURE(o.find_first_of(",*\r\n") == std::string::npos,
               "Water Linked option contains a delimiter: '" + o + "'");
    body += ',';
    body += o;
  }
  return body + "*" + hex8(crc8(body)) + "\r\n";
}

ParseResult<Packet> parse(ByteSpan buffer) {
  if (buffer.empty()) return {};  // kNeedMore
  if (buffer[0] != 'w') {
    const std::size_t n = skip_to_next_w(buffer, 0);
    return malformed(n, std::to_string(n) + " byte(s) before 'w'");
  }
  if (buffer.size() >= 2 && buffer[1] != 'c' && buffer[1] != 'r') {
    return malformed(skip_to_next_w(buffer, 1), "direction is neither 'c' nor 'r'");
  }

  std::size_t lf = 0;
  for (std::size_t i = 1; i < buffer.size() && lf == 0; ++i) {
    const std::uint8_t c = buffer[i];
    if (i >= kMaxLine) {  // kMaxLine characters, 'w' to LF, and no more
      return malformed(skip_to_next_w(buffer, i),
                       "packet longer than " + std::to_string(kMaxLine) + " characters");
    }
    if (c == '\n') {
      lf = i;
    } else if (c == '\r') {
      if (i + 1 < buffer.size() && buffer[i + 1] != '\n') {
        return malformed(i + 1, "CR inside a packet");
      }
    } else if (c < 0x20 || c > 0x7E) {
      return malformed(i + 1,
                       "non-printable byte 0x" + hex8(c) + " at offset " + std::to_string(i));
    }
  }
  if (lf == 0) return {};  // kNeedMore

  const std::size_t consumed = lf + 1;
  const std::size_t end = buffer[lf - 1] == '\r' ? lf - 1 : lf;
  const std::string line(buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>(end));
  const char direction = line[1];

  const std::size_t star = line.find('*');
  std::string_view body = line;
  if (star != std::string::npos) {
    if (star + 3 != line.size() || hex_value(line[star + 1]) < 0 || hex_value(line[star + 2]) < 0) {
      return malformed(consumed, "checksum is not '*' and two hex digits at the end");
    }
    body = body.substr(0, star);
    const auto received =
        static_cast<std::uint8_t>(hex_value(line[star + 1]) * 16 + hex_value(line[star + 2]));
    const std::uint8_t computed = crc8(body);
    if (received != computed) {
      return malformed(consumed, "CRC-8 0x" + hex8(received) + " != computed 0x" + hex8(computed));
    }
  } else if (direction == 'r') {
    return malformed(consumed, "report without checksum");
  }
  if (body.size() < 3 || body[2] == ',' || body[2] == ' ' ||
      (body.size() > 3 && body[3] != ',')) {
    return malformed(consumed,
                     "no single command character after 'w" + std::string(1, direction) + "'");
  }

  Packet p{direction, body[2], {}};
  if (body.size() > 3) {
    std::size_t pos = 4;
    while (true) {
      const std::size_t next = std::min(body.find(',', pos), body.size());
      p.options.emplace_back(body.substr(pos, next - pos));
      if (next == body.size()) break;
      pos = next + 1;
    }
  }
  ParseResult<Packet> r;
  r.status = ParseStatus::kComplete;
  r.consumed = consumed;
  r.message = std::move(p);
  return r;
}

Packet to_packet(const VelocityReport& r) {
  std::string cov;
  for (std::size_t i = 0; i < r.covariance.size(); ++i) {
    cov += (i == 0 ? "" : ";") + shortest(r.covariance[i]);
  }
  return {'r',
          'z',
          {format_fixed(r.vx_mps, 3), format_fixed(r.vy_mps, 3), format_fixed(r.vz_mps, 3),
           r.valid ? "y" : "n", format_fixed(r.altitude_m, 2), format_fixed(r.fom_mps, 3), cov,
           std::to_string(r.time_of_validity_us), std::to_string(r.time_of_transmission_us),
           format_fixed(r.time_since_last_ms, 2), std::to_string(r.status)}};
}

Packet to_packet(const TransducerReport& r) {
  return {'r',
          'u',
          {std::to_string(r.id), format_fixed(r.velocity_mps, 3), format_fixed(r.distance_m, 2),
           shortest(r.rssi_dbm), shortest(r.nsd_dbm)}};
}

Packet to_packet(const PositionReport& r) {
  return {'r',
          'p',
          {format_fixed(r.time_stamp_s, 3), format_fixed(r.x_m, 2), format_fixed(r.y_m, 2),
           format_fixed(r.z_m, 2), format_fixed(r.pos_std_m, 1), format_fixed(r.roll_deg, 1),
           format_fixed(r.pitch_deg, 1), format_fixed(r.yaw_deg, 1), std::to_string(r.status)}};
}

Packet to_packet(const LegacyVelocityReport& r) {
  return {'r',
          'x',
          {format_fixed(r.time_since_last_ms, 2), format_fixed(r.vx_mps, 3),
           format_fixed(r.vy_mps, 3), format_fixed(r.vz_mps, 3), format_fixed(r.fom_mps, 3),
           format_fixed(r.altitude_m, 2), r.valid ? "y" : "n", std::to_string(r.status)}};
}

Packet to_packet(const LegacyTransducerReport& r) {
  Packet p{'r', 't', {}};
  for (const double d : r.distance_m) p.options.push_back(format_fixed(d, 2));
  return p;
}

Result<VelocityReport> decode_velocity(const Packet& p) {
  OptionReader in(p, 'z', 11, "wrz");
  VelocityReport r;
  r.vx_mps = in.number(0, "vx");
  r.vy_mps = in.number(1, "vy");
  r.vz_mps = in.number(2, "vz");
  r.valid = in.yes_no(3, "valid");
  r.altitude_m = in.number(4, "altitude");
  r.fom_mps = in.number(5, "fom");
  if (in.ok()) {
    const std::string& cov = in.text(6);
    std::size_t pos = 0;
    std::size_t k = 0;
    for (; k < r.covariance.size() && pos <= cov.size(); ++k) {
      const std::size_t next = std::min(cov.find(';', pos), cov.size());
      const auto v = parse_number(std::string_view(cov).substr(pos, next - pos));
      if (!v) break;
      r.covariance[k] = *v;
      pos = next + 1;
    }
    if (k != r.covariance.size() || pos != cov.size() + 1) {
      in.fail_on(6, "covariance", "9 numbers separated by ';'");
    }
  }
  r.time_of_validity_us = in.integer(7, "tov");
  r.time_of_transmission_us = in.integer(8, "tot");
  r.time_since_last_ms = in.number(9, "time");
  r.status = static_cast<int>(in.integer(10, "status"));
  return in.result(r);
}

Result<TransducerReport> decode_transducer(const Packet& p) {
  OptionReader in(p, 'u', 5, "wru");
  TransducerReport r;
  r.id = static_cast<int>(in.integer(0, "id"));
  r.velocity_mps = in.number(1, "velocity");
  r.distance_m = in.number(2, "distance");
  r.rssi_dbm = in.number(3, "rssi");
  r.nsd_dbm = in.number(4, "nsd");
  return in.result(r);
}

Result<PositionReport> decode_position(const Packet& p) {
  OptionReader in(p, 'p', 9, "wrp");
  PositionReport r;
  r.time_stamp_s = in.number(0, "time_stamp");
  r.x_m = in.number(1, "x");
  r.y_m = in.number(2, "y");
  r.z_m = in.number(3, "z");
  r.pos_std_m = in.number(4, "pos_std");
  r.roll_deg = in.number(5, "roll");
  r.pitch_deg = in.number(6, "pitch");
  r.yaw_deg = in.number(7, "yaw");
  r.status = static_cast<int>(in.integer(8, "status"));
  return in.result(r);
}

Result<LegacyVelocityReport> decode_legacy_velocity(const Packet& p) {
  OptionReader in(p, 'x', 8, "wrx");
  LegacyVelocityReport r;
  r.time_since_last_ms = in.number(0, "time");
  r.vx_mps = in.number(1, "vx");
  r.vy_mps = in.number(2, "vy");
  r.vz_mps = in.number(3, "vz");
  r.fom_mps = in.number(4, "fom");
  r.altitude_m = in.number(5, "altitude");
  r.valid = in.yes_no(6, "valid");
  r.status = static_cast<int>(in.integer(7, "status"));
  return in.result(r);
}

Result<LegacyTransducerReport> decode_legacy_transducer(const Packet& p) {
  OptionReader in(p, 't', 4, "wrt");
  LegacyTransducerReport r;
  for (std::size_t i = 0; i < r.distance_m.size(); ++i) r.distance_m[i] = in.number(i, "distance");
  return in.result(r);
}

}  // namespace nav::protocols::waterlinked_a50

// SPDX-License-Identifier: MIT
// EvoLogics USBLLONG / USBLANGLES notifications (protocols.md 6c; field order and types from
// EvoLogics/evins role_at_impl.erl and EvoLogics/dmac parser.h), and navbench's NVBRELATT
// extension in the same form.
//
//   USBLLONG,cur_t,meas_t,addr,X,Y,Z,E,N,U,roll,pitch,yaw,prop_time_us,rssi,integrity,accuracy
//   USBLANGLES,cur_t,meas_t,addr,lbearing,lelevation,bearing,elevation,roll,pitch,yaw,rssi,
//              integrity,accuracy
//   NVBRELATT,cur_t,meas_t,addr,rel_heading,rel_pitch
//
// Wrapped as "+++AT:<len>:<payload>\r\n" in data mode or sent bare in command mode (the bare
// form is PARTIAL in protocols.md: DMAC parses both). No checksum exists; the data-mode length
// is the only integrity check.
#include "nav/protocols/evologics_usbl.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <vector>

#include "nav/common/ensure.hpp"
#include "nav/protocols/nmea0183.hpp"

namespace nav::protocols::evologics {
namespace {

constexpr std::string_view kLongHeader = "USBLLONG";
constexpr std::string_view kAnglesHeader = "USBLANGLES";
constexpr std::string_view kRelativeHeader = "NVBRELATT";
constexpr std::size_t kMaxLengthDigits = 4;  ///< digits of <len> in "+++AT:<len>:"

/// One value of a notification: its name, member and printed decimals (ints: none).
template <typename T>
struct Slot {
  const char* name;
  std::variant<double T::*, int T::*> member;
  int decimals;
};

const Slot<UsblLong> kLongSlots[] = {
    {"current time", &UsblLong::current_time_s, 6},
    {"measurement time", &UsblLong::measurement_time_s, 6},
    {"remote address", &UsblLong::remote_address, 0},
    {"X", &UsblLong::x_m, 4},
    {"Y", &UsblLong::y_m, 4},
    {"Z", &UsblLong::z_m, 4},
    {"E", &UsblLong::e_m, 4},
    {"N", &UsblLong::n_m, 4},
    {"U", &UsblLong::u_m, 4},
    {"roll", &UsblLong::roll_rad, 4},
    {"pitch", &UsblLong::pitch_rad, 4},
    {"yaw", &UsblLong::yaw_rad, 4},
    {"propagation time", &UsblLong::propagation_time_us, 0},
    {"rssi", &UsblLong::rssi_db, 0},
    {"integrity", &UsblLong::integrity, 0},
    {"accuracy", &UsblLong::accuracy_m, 4},
};

const Slot<UsblAngles> kAnglesSlots[] = {
    {"current time", &UsblAngles::current_time_s, 6},
    {"measurement time", &UsblAngles::measurement_time_s, 6},
    {"remote address", &UsblAngles::remote_address, 0},
    {"local bearing", &UsblAngles::local_bearing_rad, 4},
    {"local elevation", &UsblAngles::local_elevation_rad, 4},
    {"bearing", &UsblAngles::bearing_rad, 4},
    {"elevation", &UsblAngles::elevation_rad, 4},
    {"roll", &UsblAngles::roll_rad, 4},
    {"pitch", &UsblAngles::pitch_rad, 4},
    {"yaw", &UsblAngles::yaw_rad, 4},
    {"rssi", &UsblAngles::rssi_db, 0},
    {"integrity", &UsblAngles::integrity, 0},
    {"accuracy", &UsblAngles::accuracy_m, 4},
};

const Slot<RelativeAttitude> kRelativeSlots[] = {
    {"current time", &RelativeAttitude::current_time_s, 6},
    {"measurement time", &RelativeAttitude::measurement_time_s, 6},
    {"remote address", &RelativeAttitude::remote_address, 0},
    {"relative heading", &RelativeAttitude::relative_heading_rad, 4},
    {"relative pitch", &RelativeAttitude::relative_pitch_rad, 4},
};

template <typename T, std::size_t N>
std::string format(std::string_view header, const T& m, const Slot<T> (&slots)[N]) {
  std::string out(header);
  for (const Slot<T>& s : slots) {
    out += ',';
    if (const auto* d = std::get_if<double T::*>(&s.member)) {
      NAV_ENSURE(std::isfinite(m.**d), std::string("USBL value ") + s.name + " is not finite");
      out += nmea::format_fixed(m.**d, s.decimals);
    } else {
      out += std::to_string(m.*std::get<int T::*>(s.member));
    }
  }
  return out;
}

std::optional<int> parse_int(std::string_view field) {
  int v = 0;
  const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), v);
  if (field.empty() || ec != std::errc{} || end != field.data() + field.size()) {
    return std::nullopt;
  }
  return v;
}

/// values = the fields after the header.
template <typename T, std::size_t N>
Result<UsblFix> decode(std::string_view header, const std::vector<std::string_view>& values,
                       const Slot<T> (&slots)[N]) {
  if (values.size() != N) {
    return fail(ErrorCode::kParse, std::string(header) + " has " + std::to_string(values.size()) +
                                       " values, needs " + std::to_string(N));
  }
  T m;
  for (std::size_t i = 0; i < N; ++i) {
    const Slot<T>& s = slots[i];
    const auto bad = [&] {
      return fail(ErrorCode::kParse, std::string(header) + " field " + s.name + " '" +
                                         std::string(values[i]) + "' is not a number");
    };
    if (const auto* d = std::get_if<double T::*>(&s.member)) {
      const auto v = nmea::parse_number(values[i]);
      if (!v) return bad();
      m.**d = *v;
    } else {
      const auto v = parse_int(values[i]);
      if (!v) return bad();
      m.*std::get<int T::*>(s.member) = *v;
    }
  }
  return UsblFix{m};
}

template <typename Message>
ParseResult<Message> malformed(std::size_t consumed, std::string error) {
  ParseResult<Message> r;
  r.status = ParseStatus::kMalformed;
  r.consumed = consumed;
  r.error = std::move(error);
  return r;
}

bool can_start(std::uint8_t c) { return c == '+' || (c >= 'A' && c <= 'Z'); }

/// Bytes through the next LF, or the whole buffer when there is none.
std::size_t through_next_lf(ByteSpan buffer) {
  const auto it = std::find(buffer.begin(), buffer.end(), std::uint8_t{'\n'});
  return it == buffer.end() ? buffer.size() : static_cast<std::size_t>(it - buffer.begin()) + 1;
}

/// Complete result from a payload, or malformed consuming the whole frame.
ParseResult<Notification> finish(std::string_view payload, Framing framing,
                                 std::size_t consumed) {
  auto fix = decode_payload(payload);
  if (!fix) return malformed<Notification>(consumed, fix.error().detail);
  ParseResult<Notification> r;
  r.status = ParseStatus::kComplete;
  r.consumed = consumed;
  r.message = Notification{std::move(*fix), framing};
  return r;
}

ParseResult<Notification> parse_data_mode(ByteSpan buffer) {
  const std::size_t n = std::min(buffer.size(), kDataModePrefix.size());
  if (!std::equal(buffer.begin(), buffer.begin() + static_cast<std::ptrdiff_t>(n),
                  kDataModePrefix.begin())) {
    const auto next = std::find_if(buffer.begin() + 1, buffer.end(), can_start);
    const auto skip = static_cast<std::size_t>(next - buffer.begin());
    return malformed<Notification>(skip, "'+' does not start \"+++AT:\"");
  }
  // "+++AT:" <digits> ":"
  std::size_t i = kDataModePrefix.size();
  std::size_t length = 0;
  for (; i < buffer.size() && buffer[i] != ':'; ++i) {
    if (buffer[i] < '0' || buffer[i] > '9' || i - kDataModePrefix.size() >= kMaxLengthDigits) {
      return malformed<Notification>(through_next_lf(buffer), "bad data-mode length field");
    }
    length = length * 10 + (buffer[i] - '0');
  }
  if (i >= buffer.size()) return {};  // kNeedMore
  if (i == kDataModePrefix.size() || length == 0 || length > kMaxPayload) {
    return malformed<Notification>(through_next_lf(buffer),
                                   "data-mode length " + std::to_string(length) + " out of range");
  }
  const std::size_t start = i + 1;
  const std::size_t end = start + length;
  // Need the payload and at least LF (or CR LF).
  if (buffer.size() < end + 1 || (buffer[end] == '\r' && buffer.size() < end + 2)) return {};
  const bool crlf = buffer[end] == '\r' && buffer[end + 1] == '\n';
  if (!crlf && buffer[end] != '\n') {
    return malformed<Notification>(through_next_lf(buffer),
                                   "data-mode payload of " + std::to_string(length) +
                                       " byte(s) is not followed by CR LF");
  }
  const std::size_t consumed = end + (crlf ? 2 : 1);
  const ByteSpan payload = buffer.subspan(start, length);
  if (!std::all_of(payload.begin(), payload.end(),
                   [](std::uint8_t c) { return c >= 0x20 && c <= 0x7E; })) {
    return malformed<Notification>(consumed, "data-mode payload holds a non-printable byte");
  }
  return finish(std::string_view(reinterpret_cast<const char*>(payload.data()), payload.size()),
                Framing::kDataMode, consumed);
}

ParseResult<Notification> parse_command_mode(ByteSpan buffer) {
  for (std::size_t i = 1; i < buffer.size(); ++i) {
    const std::uint8_t c = buffer[i];
    if (c == '\n') {
      const std::size_t end = buffer[i - 1] == '\r' ? i - 1 : i;
      return finish(std::string_view(reinterpret_cast<const char*>(buffer.data()), end),
                    Framing::kCommandMode, i + 1);
    }
    if (c == '+') return malformed<Notification>(i, "line cut short by '+'");
    if (c == '\r') {
      if (i + 1 < buffer.size() && buffer[i + 1] != '\n') {
        return malformed<Notification>(i + 1, "CR inside a line");
      }
    } else if (c < 0x20 || c > 0x7E) {
      return malformed<Notification>(i + 1, "non-printable byte at offset " + std::to_string(i));
    } else if (i >= kMaxPayload) {
      return malformed<Notification>(i, "line longer than " + std::to_string(kMaxPayload) +
                                            " characters");
    }
  }
  return {};  // kNeedMore
}

}  // namespace

std::string_view header_of(const UsblFix& fix) {
  if (std::holds_alternative<UsblLong>(fix)) return kLongHeader;
  if (std::holds_alternative<UsblAngles>(fix)) return kAnglesHeader;
  return kRelativeHeader;
}

std::string to_payload(const UsblFix& fix) {
  if (const auto* l = std::get_if<UsblLong>(&fix)) return format(kLongHeader, *l, kLongSlots);
  if (const auto* a = std::get_if<UsblAngles>(&fix)) {
    return format(kAnglesHeader, *a, kAnglesSlots);
  }
  return format(kRelativeHeader, std::get<RelativeAttitude>(fix), kRelativeSlots);
}

Result<UsblFix> decode_payload(std::string_view payload) {
  std::vector<std::string_view> fields;
  std::size_t pos = 0;
  while (true) {
    const std::size_t comma = std::min(payload.find(',', pos), payload.size());
    fields.push_back(payload.substr(pos, comma - pos));
    if (comma == payload.size()) break;
    pos = comma + 1;
  }
  const std::string_view header = fields.front();
  const std::vector<std::string_view> values(fields.begin() + 1, fields.end());
  if (header == kLongHeader) return decode(header, values, kLongSlots);
  if (header == kAnglesHeader) return decode(header, values, kAnglesSlots);
  if (header == kRelativeHeader) return decode(header, values, kRelativeSlots);
  return fail(ErrorCode::kParse,
              "unsupported notification '" + std::string(header.substr(0, 32)) + "'");
}

std::string encode(const Notification& n) {
  const std::string payload = to_payload(n.fix);
  if (n.framing == Framing::kCommandMode) return payload + "\r\n";
  return std::string(kDataModePrefix) + std::to_string(payload.size()) + ":" + payload + "\r\n";
}

ParseResult<Notification> parse(ByteSpan buffer) {
  if (buffer.empty()) return {};  // kNeedMore
  if (buffer[0] == '+') return parse_data_mode(buffer);
  if (buffer[0] >= 'A' && buffer[0] <= 'Z') return parse_command_mode(buffer);
  const auto next = std::find_if(buffer.begin() + 1, buffer.end(), can_start);
  const auto skip = static_cast<std::size_t>(next - buffer.begin());
  return malformed<Notification>(skip, std::to_string(skip) +
                                           " byte(s) that cannot start a notification");
}

}  // namespace nav::protocols::evologics

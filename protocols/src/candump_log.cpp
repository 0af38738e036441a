// SPDX-License-Identifier: MIT
// candump text lines (protocols.md section 7; can-utils candump.c, lib.c parse_canframe /
// sprint_canframe / sprint_long_canframe).
#include "nav/protocols/candump_log.hpp"

#include <algorithm>
#include <cstdio>
#include <optional>
#include <string>

#include "nav/common/ensure.hpp"

namespace nav::protocols::candump {
namespace {

/// Value of a hex digit, or -1.
int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

bool is_space(char c) { return c == ' ' || c == '\t'; }

/// The first problem found on a line.
struct LineError {
  LineStatus status = LineStatus::kMalformed;
  std::size_t pos = 0;  ///< 0-based
  std::string why;
};

/// A cursor over one line; a failure records the column it happened at (the first one wins)
/// and every step returns false from then on, so parsers read as straight-line code.
class Cursor {
 public:
  explicit Cursor(std::string_view s) : s_(s) {}

  bool done() const { return pos_ >= s_.size(); }
  char peek() const { return done() ? '\0' : s_[pos_]; }
  std::size_t pos() const { return pos_; }
  void advance(std::size_t n = 1) { pos_ += n; }
  std::string_view rest() const { return s_.substr(std::min(pos_, s_.size())); }

  void skip_spaces() {
    while (!done() && is_space(s_[pos_])) ++pos_;
  }
  /// The run of non-space characters at the cursor (possibly empty); the cursor moves past it.
  std::string_view token() {
    const std::size_t start = pos_;
    while (!done() && !is_space(s_[pos_])) ++pos_;
    return s_.substr(start, pos_ - start);
  }
  /// Records a failure at `at`; always false.
  bool fail(std::size_t at, std::string why, LineStatus status = LineStatus::kMalformed) {
    if (!error_) error_ = LineError{status, at, std::move(why)};
    return false;
  }
  /// Records a failure at the cursor; always false.
  bool fail(std::string why) { return fail(pos_, std::move(why)); }
  /// Consumes `c` or fails naming what was expected.
  bool expect(char c, const char* what) {
    if (peek() != c) return fail(std::string("expected ") + what);
    ++pos_;
    return true;
  }
  const std::optional<LineError>& error() const { return error_; }

 private:
  std::string_view s_;
  std::size_t pos_ = 0;
  std::optional<LineError> error_;
};

bool is_digit(char c) { return c >= '0' && c <= '9'; }

/// `(<digits>.<6 or 9 digits>)`; the cursor is on '('.
bool parse_timestamp(Cursor& c, Timestamp& t) {
  if (!c.expect('(', "'(' opening the timestamp")) return false;
  int digits = 0;
  while (is_digit(c.peek())) {
    if (digits >= 19) return c.fail("timestamp seconds too long");
    t.seconds = t.seconds * 10 + static_cast<std::uint64_t>(c.peek() - '0');
    ++digits;
    c.advance();
  }
  if (digits == 0) return c.fail("expected timestamp seconds");
  t.seconds_digits = digits;
  if (!c.expect('.', "'.' in the timestamp")) return false;
  const std::size_t frac_start = c.pos();
  int decimals = 0;
  std::uint32_t frac = 0;
  while (is_digit(c.peek())) {
    if (decimals < 9) frac = frac * 10 + static_cast<std::uint32_t>(c.peek() - '0');
    ++decimals;
    c.advance();
  }
  if (decimals != 6 && decimals != 9) {
    return c.fail(frac_start,
                  "timestamp needs 6 or 9 decimals, found " + std::to_string(decimals));
  }
  t.decimals = decimals;
  t.nanoseconds = decimals == 6 ? frac * 1000 : frac;
  if (!c.expect(')', "')' closing the timestamp")) return false;
  if (!is_space(c.peek())) return c.fail("expected a space after the timestamp");
  return true;
}

/// Sets id / extended / error from the `digits` (3 or 8) hex digits at the start of `tok`,
/// which starts at line position `at`.
bool parse_id(Cursor& c, std::string_view tok, std::size_t digits, std::size_t at,
              can::Frame& f) {
  std::uint32_t raw = 0;
  for (std::size_t i = 0; i < digits; ++i) {
    const int v = hex_value(tok[i]);
    if (v < 0) {
      return c.fail(at + i, std::string("bad hex digit '") + tok[i] + "' in the identifier");
    }
    raw = raw << 4 | static_cast<std::uint32_t>(v);
  }
  if (digits == 3) {
    if (raw > can::kStandardIdMask) return c.fail(at, "standard identifier above 0x7FF");
    f.id = raw;
    return true;
  }
  if ((raw & kErrorFlag) != 0) {
    if ((raw & ~(kErrorFlag | can::kExtendedIdMask)) != 0) {
      return c.fail(at, "error frame identifier with bits 30-31 set");
    }
    f.error = true;
    f.id = raw & can::kExtendedIdMask;
    return true;
  }
  if (raw > can::kExtendedIdMask) return c.fail(at, "extended identifier above 29 bits");
  f.extended = true;
  f.id = raw;
  return true;
}

/// Optional `_<dlc>` (9..F) after 8 data bytes or R8; the cursor is after the data.
bool parse_raw_dlc(Cursor& c, can::Frame& f, std::size_t length) {
  if (c.peek() != '_') return true;
  if (length != can::kMaxDataLength) return c.fail("'_<dlc>' is only allowed after 8 data bytes");
  c.advance();
  const int v = hex_value(c.peek());
  if (v < 9) return c.fail("'_<dlc>' needs a hex digit 9..F");
  f.dlc = static_cast<std::uint8_t>(v);
  c.advance();
  return true;
}

/// Log-format frame `III#...` / `IIIIIIII#...`; the cursor is at its first character.
bool parse_compact_frame(Cursor& c, can::Frame& f) {
  const std::size_t start = c.pos();
  const std::string_view rest = c.rest();
  std::size_t digits = 0;
  if (rest.size() > 3 && rest[3] == '#') {
    digits = 3;
  } else if (rest.size() > 8 && rest[8] == '#') {
    digits = 8;
  } else {
    return c.fail("identifier must be 3 or 8 hex digits followed by '#'");
  }
  if (!parse_id(c, rest, digits, start, f)) return false;
  c.advance(digits + 1);
  if (c.peek() == '#') {
    return c.fail(c.pos() - 1, "CAN FD frame ('##') not supported", LineStatus::kUnsupported);
  }
  if (c.peek() == 'R' || c.peek() == 'r') {
    if (f.error) return c.fail("error frames cannot be remote requests");
    f.rtr = true;
    c.advance();
    if (is_digit(c.peek())) {
      const int len = c.peek() - '0';
      if (len > 8) return c.fail("remote request length above 8");
      f.dlc = static_cast<std::uint8_t>(len);
      c.advance();
    }
    return parse_raw_dlc(c, f, f.dlc);
  }
  std::size_t n = 0;
  while (!c.done() && !is_space(c.peek()) && c.peek() != '_') {
    if (c.peek() == '.') {
      c.advance();
      continue;
    }
    const int hi = hex_value(c.peek());
    if (hi < 0) return c.fail(std::string("bad hex digit '") + c.peek() + "' in the data");
    c.advance();
    const int lo = hex_value(c.peek());
    if (lo < 0) {
      if (c.done() || is_space(c.peek()) || c.peek() == '_' || c.peek() == '.') {
        return c.fail(c.pos() - 1, "odd number of hex digits in the data");
      }
      return c.fail(std::string("bad hex digit '") + c.peek() + "' in the data");
    }
    if (n == can::kMaxDataLength) {
      return c.fail(c.pos() - 1, "more than 8 data bytes (CAN FD needs '##')");
    }
    f.data[n++] = static_cast<std::uint8_t>(hi << 4 | lo);
    c.advance();
  }
  f.dlc = static_cast<std::uint8_t>(n);
  return parse_raw_dlc(c, f, n);
}

/// Screen-print frame `IIIIIIII   [8]  00 FC ..`; the cursor is at the identifier.
bool parse_print_frame(Cursor& c, can::Frame& f) {
  const std::size_t start = c.pos();
  const std::string_view tok = c.token();
  if (tok.size() != 3 && tok.size() != 8) {
    return c.fail(start, "identifier must be 3 or 8 hex digits");
  }
  if (!parse_id(c, tok, tok.size(), start, f)) return false;
  c.skip_spaces();
  const std::size_t len_at = c.pos();
  if (!c.expect('[', "'[' before the data length")) return false;
  std::size_t len_digits = 0;
  int len = 0;
  while (is_digit(c.peek())) {
    if (len_digits < 2) len = len * 10 + (c.peek() - '0');  // more digits: refused below
    ++len_digits;
    c.advance();
  }
  if (len_digits == 0) return c.fail("expected the data length");
  if (len_digits == 2) {
    return c.fail(len_at, "CAN FD frame ('[NN]' length) not supported",
                  LineStatus::kUnsupported);
  }
  if (len_digits != 1 || len > 8) return c.fail(len_at + 1, "data length must be 0..8");
  if (!c.expect(']', "']' after the data length")) return false;
  f.dlc = static_cast<std::uint8_t>(len);
  c.skip_spaces();
  constexpr std::string_view kRemote = "remote request";
  if (c.rest().starts_with(kRemote)) {
    if (f.error) return c.fail("error frames cannot be remote requests");
    f.rtr = true;
    c.advance(kRemote.size());
    c.skip_spaces();
    return c.done() || c.fail("unexpected text after the frame");
  }
  for (int i = 0; i < len; ++i) {
    c.skip_spaces();
    const int hi = hex_value(c.peek());
    if (hi < 0) {
      return c.fail("expected data byte " + std::to_string(i + 1) + " of " +
                    std::to_string(len));
    }
    c.advance();
    const int lo = hex_value(c.peek());
    if (lo < 0) return c.fail("expected two hex digits per data byte");
    c.advance();
    f.data[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(hi << 4 | lo);
    if (!c.done() && !is_space(c.peek())) return c.fail("expected a space between data bytes");
  }
  // candump appends ERRORFRAME to error frames, and the bytes as ASCII with -a.
  c.skip_spaces();
  const std::string_view tail = c.rest();
  if (tail.empty()) return true;
  if (f.error && tail.starts_with("ERRORFRAME")) return true;
  if (tail.size() >= 2 && tail.front() == '\'' && tail.back() == '\'') return true;
  return c.fail("unexpected text after the data");
}

/// Fills `r` from a non-blank, non-comment line; false with c.error() set on failure.
bool parse_record(Cursor& c, Record& r) {
  if (c.peek() == '(') {
    Timestamp t;
    if (!parse_timestamp(c, t)) return false;
    r.time = t;
    c.skip_spaces();
  }
  const std::size_t if_at = c.pos();
  const std::string_view ifname = c.token();
  if (ifname.empty()) return c.fail("expected an interface name");
  if (ifname.find('#') != std::string_view::npos) {
    return c.fail(if_at, "expected an interface name before the frame");
  }
  // A NUL would cut the name short when it is written again (format_line), and no other
  // control byte is part of a name candump printed.
  for (std::size_t i = 0; i < ifname.size(); ++i) {
    const auto b = static_cast<unsigned char>(ifname[i]);
    if (b < 0x20 || b == 0x7F) return c.fail(if_at + i, "control byte in the interface name");
  }
  r.interface = std::string(ifname);
  c.skip_spaces();
  if (c.done()) return c.fail("expected a frame after the interface name");
  const std::string_view next = c.rest().substr(0, c.rest().find_first_of(" \t"));
  if (next.find('#') == std::string_view::npos) return parse_print_frame(c, r.frame);
  if (!parse_compact_frame(c, r.frame)) return false;
  if (!c.done() && !is_space(c.peek())) return c.fail("unexpected character after the frame");
  c.skip_spaces();
  if (c.peek() == 'T' || c.peek() == 'R') {
    r.direction = c.peek() == 'T' ? Direction::kTx : Direction::kRx;
    c.advance();
    c.skip_spaces();
  }
  return c.done() || c.fail("unexpected text after the frame");
}

std::string_view strip_newline(std::string_view line) {
  while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.remove_suffix(1);
  return line;
}

}  // namespace

LineResult parse_line(std::string_view line) {
  Cursor c(strip_newline(line));
  c.skip_spaces();
  if (c.done() || c.peek() == '#') return LineResult{};  // blank or comment
  Record r;
  if (parse_record(c, r)) return LineResult{LineStatus::kRecord, std::move(r), 0, {}};
  const LineError& e = *c.error();
  const std::size_t column = e.pos + 1;
  return LineResult{e.status, std::nullopt, column,
                    "column " + std::to_string(column) + ": " + e.why};
}

std::string format_frame(const can::Frame& f) {
  char buf[64];
  int n = 0;
  if (f.error) {
    n = std::snprintf(buf, sizeof buf, "%08X#", (f.id & can::kExtendedIdMask) | kErrorFlag);
  } else if (f.extended) {
    n = std::snprintf(buf, sizeof buf, "%08X#", f.id & can::kExtendedIdMask);
  } else {
    n = std::snprintf(buf, sizeof buf, "%03X#", f.id & can::kStandardIdMask);
  }
  std::string out(buf, static_cast<std::size_t>(n));
  const auto raw_dlc = [&](std::size_t length) {
    if (length == can::kMaxDataLength && f.dlc > can::kMaxDataLength) {
      std::snprintf(buf, sizeof buf, "_%X", f.dlc & 0xF);
      out += buf;
    }
  };
  if (f.rtr) {
    out += 'R';
    const std::size_t len = std::min<std::size_t>(f.dlc, can::kMaxDataLength);
    if (len != 0) out += static_cast<char>('0' + len);
    raw_dlc(len);
    return out;
  }
  for (const std::uint8_t b : f.payload()) {
    std::snprintf(buf, sizeof buf, "%02X", b);
    out += buf;
  }
  raw_dlc(f.length());
  return out;
}

std::string format_line(const Record& r, std::size_t interface_width) {
  NAV_ENSURE(r.time.has_value(), "candump log lines need a timestamp");
  const Timestamp& t = *r.time;
  NAV_ENSURE(t.decimals == 6 || t.decimals == 9, "timestamp decimals must be 6 or 9");
  NAV_ENSURE(t.nanoseconds < 1000000000u, "timestamp fraction out of range");
  char buf[96];
  const unsigned frac = t.decimals == 6 ? t.nanoseconds / 1000 : t.nanoseconds;
  std::snprintf(buf, sizeof buf, "(%0*llu.%0*u) ", t.seconds_digits,
                static_cast<unsigned long long>(t.seconds), t.decimals, frac);
  // The name after the buffer: any length, right-aligned as candump's %*s.
  std::string out = buf;
  if (r.interface.size() < interface_width) out.append(interface_width - r.interface.size(), ' ');
  out += r.interface + " " + format_frame(r.frame);
  if (r.direction == Direction::kTx) out += " T";
  if (r.direction == Direction::kRx) out += " R";
  return out;
}

}  // namespace nav::protocols::candump

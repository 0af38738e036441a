// SPDX-License-Identifier: MIT
#include "nav/bench/capture.hpp"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <sstream>
#include <string_view>

namespace nav::bench {
namespace {

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

bool all_digits(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

/// "(<sec>.<nsec>) <port> <hex>" -> line; false when malformed.
bool parse_line(std::string_view s, CaptureLine& out) {
  if (!s.empty() && s.back() == '\r') s.remove_suffix(1);
  if (s.size() < 2 || s[0] != '(') return false;
  const auto close = s.find(')');
  if (close == std::string_view::npos) return false;
  std::string_view time = s.substr(1, close - 1);
  const bool negative = !time.empty() && time[0] == '-';
  if (negative) time.remove_prefix(1);
  const auto dot = time.find('.');
  if (dot == std::string_view::npos) return false;
  const std::string_view sec = time.substr(0, dot), frac = time.substr(dot + 1);
  if (!all_digits(sec) || !all_digits(frac) || frac.size() > 9 || sec.size() > 10) return false;
  long long secs = 0, nsec = 0;
  std::from_chars(sec.data(), sec.data() + sec.size(), secs);
  std::from_chars(frac.data(), frac.data() + frac.size(), nsec);
  // Ten digits of seconds can pass 2^63 ns (about 292 years).
  constexpr long long kMaxSeconds = 9'223'372'035;
  if (secs > kMaxSeconds) return false;
  for (std::size_t i = frac.size(); i < 9; ++i) nsec *= 10;
  const long long ns = secs * 1'000'000'000LL + nsec;
  out.t = Duration{negative ? -ns : ns};

  std::string_view rest = s.substr(close + 1);
  if (rest.empty() || rest[0] != ' ') return false;
  rest.remove_prefix(1);
  const auto space = rest.find(' ');
  if (space == 0 || space == std::string_view::npos) return false;
  // A NUL would cut the name short when the line is written again; no port name has a
  // control byte.
  const std::string_view port = rest.substr(0, space);
  if (std::any_of(port.begin(), port.end(), [](char c) {
        return static_cast<unsigned char>(c) < 0x20 || c == 0x7F;
      })) {
    return false;
  }
  out.port = std::string(port);
  const std::string_view hex = rest.substr(space + 1);
  if (hex.size() % 2 != 0) return false;
  out.bytes.clear();
  out.bytes.reserve(hex.size() / 2);
  for (std::size_t i = 0; i < hex.size(); i += 2) {
    const int hi = hex_digit(hex[i]), lo = hex_digit(hex[i + 1]);
    if (hi < 0 || lo < 0) return false;
    out.bytes.push_back(static_cast<std::uint8_t>(hi * 16 + lo));
  }
  return true;
}

}  // namespace

void append_capture_line(std::string& out, Duration since_t0, std::string_view port,
                         std::span<const std::uint8_t> bytes) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  const long long ns = since_t0.count();
  const long long a = ns < 0 ? -ns : ns;
  char head[48];
  const int n = std::snprintf(head, sizeof head, "(%s%lld.%09lld) ", ns < 0 ? "-" : "",
                              a / 1'000'000'000, a % 1'000'000'000);
  out.append(head, static_cast<std::size_t>(n));
  out += port;
  out += ' ';
  const std::size_t at = out.size();
  out.resize(at + 2 * bytes.size() + 1);  // then filled in place: no check per character
  char* p = out.data() + at;
  for (const auto b : bytes) {
    *p++ = kHex[b >> 4];
    *p++ = kHex[b & 0x0F];
  }
  *p = '\n';
}

void write_capture_line(std::FILE* f, Duration since_t0, const std::string& port,
                        std::span<const std::uint8_t> bytes) {
  std::string line;
  append_capture_line(line, since_t0, port, bytes);
  std::fwrite(line.data(), 1, line.size(), f);  // one call: a whole line, whatever the threads
}


Result<std::vector<CaptureLine>> parse_capture(const std::string& text, const std::string& file) {
  std::vector<CaptureLine> out;
  std::istringstream in(text);
  std::size_t line_no = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_no;
    if (line.empty() || line == "\r") continue;
    CaptureLine l;
    if (!parse_line(line, l)) {
      return fail(ErrorCode::kParse, file + ":" + std::to_string(line_no) +
                                          ": expected '(<sec>.<nsec>) <port> <hex>'");
    }
    l.line_no = line_no;
    out.push_back(std::move(l));
  }
  return out;
}

}  // namespace nav::bench

// SPDX-License-Identifier: MIT
#include "nav/reports/text.hpp"

#include "nav/reports/json_text.hpp"

#include <cstdint>

namespace nav::reports {
namespace {

constexpr std::string_view kReplacement = "\xEF\xBF\xBD";  // U+FFFD

/// Length of the well-formed UTF-8 sequence at s[i], or 0 when the bytes there are not one;
/// bad is then how many bytes form the maximal ill-formed subpart (at least 1).
std::size_t sequence_length(std::string_view s, std::size_t i, std::size_t& bad) {
  const auto b = [&](std::size_t k) { return static_cast<std::uint8_t>(s[i + k]); };
  const std::uint8_t c = b(0);
  bad = 1;
  if (c < 0x80) return 1;
  std::size_t n = 0;
  std::uint8_t lo = 0x80, hi = 0xBF;  // range of the second byte (Unicode Table 3-7)
  if (c >= 0xC2 && c <= 0xDF) {
    n = 2;
  } else if (c >= 0xE0 && c <= 0xEF) {
    n = 3;
    if (c == 0xE0) lo = 0xA0;
    if (c == 0xED) hi = 0x9F;  // no surrogates
  } else if (c >= 0xF0 && c <= 0xF4) {
    n = 4;
    if (c == 0xF0) lo = 0x90;
    if (c == 0xF4) hi = 0x8F;  // at most U+10FFFF
  } else {
    return 0;  // a continuation byte, C0, C1 or F5..FF
  }
  for (std::size_t k = 1; k < n; ++k) {
    if (i + k >= s.size()) return 0;
    const std::uint8_t x = b(k);
    const std::uint8_t min = k == 1 ? lo : 0x80, max = k == 1 ? hi : 0xBF;
    if (x < min || x > max) return 0;
    bad = k + 1;  // the bytes so far are a prefix of a valid sequence
  }
  return n;
}

template <typename Escape>
std::string transform(std::string_view s, Escape escape) {
  std::string out;
  out.reserve(s.size() + s.size() / 8);
  for (std::size_t i = 0; i < s.size();) {
    std::size_t bad = 1;
    const std::size_t n = sequence_length(s, i, bad);
    if (n == 0) {
      out += kReplacement;
      i += bad;
      continue;
    }
    if (n == 1) {
      escape(out, s[i]);
    } else {
      out.append(s.substr(i, n));
    }
    i += n;
  }
  return out;
}

void escape_markup(std::string& out, char c) {
  switch (c) {
    case '&': out += "&amp;"; break;
    case '<': out += "&lt;"; break;
    case '>': out += "&gt;"; break;
    case '"': out += "&quot;"; break;
    case '\'': out += "&#39;"; break;
    default: out += c;
  }
}

template <typename Json>
std::string dump_any(const Json& j, int indent) {
  return j.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace

std::optional<std::size_t> first_invalid_utf8(std::string_view s) {
  for (std::size_t i = 0; i < s.size();) {
    std::size_t bad = 1;
    const std::size_t n = sequence_length(s, i, bad);
    if (n == 0) return i;
    i += n;
  }
  return std::nullopt;
}

std::string valid_utf8(std::string_view s) {
  return transform(s, [](std::string& out, char c) { out += c; });
}

std::string html_escape(std::string_view s) { return transform(s, escape_markup); }

std::string xml_escape(std::string_view s) {
  return transform(s, [](std::string& out, char c) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 && c != '\t' && c != '\n' && c != '\r') {
      out += kReplacement;
      return;
    }
    escape_markup(out, c);
  });
}

std::string dump_json(const nlohmann::json& j, int indent) { return dump_any(j, indent); }
std::string dump_json(const nlohmann::ordered_json& j, int indent) { return dump_any(j, indent); }

std::string json_for_script(const nlohmann::json& j) {
  const std::string text = dump_json(j);
  std::string out;
  out.reserve(text.size() + 64);
  for (const char c : text) {
    switch (c) {
      case '<': out += "\\u003c"; break;
      case '>': out += "\\u003e"; break;
      case '&': out += "\\u0026"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace nav::reports

// SPDX-License-Identifier: MIT
#include "nav/common/escape.hpp"

namespace nav {
namespace {

/// Appends the escape of a byte that is not shown as it is.
void append_escaped(std::string& out, unsigned char b) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  switch (b) {
    case '\n': out += "\\n"; break;
    case '\r': out += "\\r"; break;
    case '\t': out += "\\t"; break;
    default:
      out += "\\x";
      out += kHex[b >> 4];
      out += kHex[b & 0x0F];
  }
}

}  // namespace

std::string escape_controls(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (const char c : s) {
    const auto b = static_cast<unsigned char>(c);
    if (b < 0x20 || b == 0x7F) {
      append_escaped(out, b);
    } else {
      out += c;
    }
  }
  return out;
}

std::string escape_bytes(std::string_view bytes) {
  std::string out;
  out.reserve(bytes.size());
  for (const char c : bytes) {
    const auto b = static_cast<unsigned char>(c);
    if (b == '\\') {
      out += "\\\\";
    } else if (b >= 0x20 && b < 0x7F) {
      out += c;
    } else {
      append_escaped(out, b);
    }
  }
  return out;
}

}  // namespace nav

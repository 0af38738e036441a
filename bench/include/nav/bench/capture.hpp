// SPDX-License-Identifier: MIT
// Serial capture files: one line per message or read, `(<sec>.<nsec>) <port> <hex>`, in the
// spirit of candump logs; times are relative to scenario time 0 and carry a minus sign
// before it.
#pragma once

#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "nav/common/result.hpp"
#include "nav/common/time.hpp"
#include "nav/protocols/parse.hpp"

namespace nav::bench {

/// Appends one capture line, "(<sec>.<nsec>) <port> <hex>\n", to out.
void append_capture_line(std::string& out, Duration since_t0, std::string_view port,
                         std::span<const std::uint8_t> bytes);

/// Appends one capture line to f (no flush).
void write_capture_line(std::FILE* f, Duration since_t0, const std::string& port,
                        std::span<const std::uint8_t> bytes);

/// One line of a capture file.
struct CaptureLine {
  Duration t{};             ///< recorded time (relative to the capture's t0; may be < 0)
  std::string port;         ///< port name
  protocols::Bytes bytes;   ///< bytes of the line
  std::size_t line_no = 0;  ///< 1-based line in the file
};

/// Parses a whole capture; empty lines are skipped. The error of a malformed line is
/// "FILE:LINE: expected '(<sec>.<nsec>) <port> <hex>'" (kParse).
Result<std::vector<CaptureLine>> parse_capture(const std::string& text, const std::string& file);

}  // namespace nav::bench

// SPDX-License-Identifier: MIT
// Serial capture files: one line per message or read, `(<sec>.<nsec>) <port> <hex>`, in the
// spirit of candump logs; times are relative to scenario time 0 and carry a minus sign
// before it.
#pragma once

#include <cstdint>
#include <cstdio>
#include <span>
#include <string>

#include "nav/common/time.hpp"

namespace nav::bench {

/// Appends one capture line to f (no flush).
void write_capture_line(std::FILE* f, Duration since_t0, const std::string& port,
                        std::span<const std::uint8_t> bytes);

}  // namespace nav::bench

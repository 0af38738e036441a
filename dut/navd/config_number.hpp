// SPDX-License-Identifier: MIT
// A config key whose number must be whole (a count, an experiment): shared by the papers' key
// tables (config_p2.cpp, config_p3.cpp).
#pragma once

#include <cmath>

namespace nav::dut {

/// A whole number in [lo, hi] as an int; otherwise lo − 1 (which the group's validate()
/// refuses).
inline int whole_or_invalid(double v, int lo, int hi) {
  const bool whole = std::isfinite(v) && v == std::floor(v) && v >= lo && v <= hi;
  return whole ? static_cast<int>(v) : lo - 1;
}

}  // namespace nav::dut

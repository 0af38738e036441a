// SPDX-License-Identifier: MIT
// Numbers in messages: the one way errors and help texts print a value.
#pragma once

#include <cstdio>
#include <string>

namespace nav {

/// v as printf's %g (six significant digits, fixed or exponent, whichever is shorter), as a
/// refusal quotes what it was given: "must be > 0 (got -1.5e-07)".
inline std::string format_g(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace nav

// SPDX-License-Identifier: MIT
// Bytes shown within one line of text: an error that quotes what a file held (the scenario
// loader, navd's config), a report that shows what a DUT wrote.
#pragma once

#include <string>
#include <string_view>

namespace nav {

/// s with its control bytes (below 0x20, and 0x7F) escaped as "\n", "\r", "\t" or "\xHH";
/// every other byte, UTF-8 included, as it is. A message quoting s stays one line.
std::string escape_controls(std::string_view s);

/// Bytes as printable ASCII, as a C string literal would show them: printable ASCII as is
/// (backslash doubled), CR, LF and tab as \r, \n, \t, every other byte as \xHH.
std::string escape_bytes(std::string_view bytes);

}  // namespace nav

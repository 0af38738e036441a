// SPDX-License-Identifier: MIT
// Validators shared by navbench's subcommands (CLI11). Private to navbench's main.
#pragma once

#include <algorithm>
#include <string>
#include <string_view>

#include <CLI/CLI.hpp>

namespace nav::bench::cli {

/// Decimal digits only, at most 2^64 - 1, leading zeros dropped (a transform): CLI11 would take
/// "-1" for an unsigned option and wrap it around, saturate a number too large, and read
/// "010" as octal.
inline const CLI::Validator kUnsignedInteger(
    [](std::string& text) -> std::string {
      const bool digits = !text.empty() && std::all_of(text.begin(), text.end(), [](char c) {
        return c >= '0' && c <= '9';
      });
      if (!digits) return "expected an unsigned decimal integer, got '" + text + "'";
      const auto first = std::min(text.find_first_not_of('0'), text.size() - 1);
      const std::string_view significant = std::string_view(text).substr(first);
      constexpr std::string_view kMax = "18446744073709551615";
      if (significant.size() > kMax.size() ||
          (significant.size() == kMax.size() && significant > kMax)) {
        return "expected at most 18446744073709551615, got '" + text + "'";
      }
      text = std::string(significant);
      return {};
    },
    "", "unsigned 64-bit integer");

/// An empty folder argument is a mistake (an unset shell variable), not a request for a default.
inline const CLI::Validator kNotEmpty(
    [](std::string& v) { return v.empty() ? std::string("must not be empty") : std::string(); },
    "FOLDER");

}  // namespace nav::bench::cli

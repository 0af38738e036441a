// SPDX-License-Identifier: MIT
// Test helpers for navd's NMEA-framed sentences ($PNVBSOL, $PNVBCOV, $PNVBINN): a framed line
// parsed as the bench's output reader parses it, and a sentence made from its field text.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "nav/protocols/navd_solution.hpp"
#include "nav/protocols/nmea0183.hpp"

namespace nav::protocols::navd::test_support {

/// One framed line parsed with navd's sentence limit (a failure to parse fails the test).
inline nmea::Sentence parsed(const std::string& line) {
  const auto r = nmea::parse_with_limit(
      ByteSpan(reinterpret_cast<const std::uint8_t*>(line.data()), line.size()), kMaxSentence);
  EXPECT_EQ(r.status, ParseStatus::kComplete) << line << r.error;
  return r.message ? *r.message : nmea::Sentence{};
}

/// A sentence of talker "P", `type`, and the fields of `fields` split at every comma.
inline nmea::Sentence with_fields(const std::string& type, const std::string& fields) {
  nmea::Sentence s{"P", type, {}};
  for (std::size_t at = 0;;) {
    const auto comma = fields.find(',', at);
    s.fields.push_back(fields.substr(at, comma - at));
    if (comma == std::string::npos) break;
    at = comma + 1;
  }
  return s;
}

}  // namespace nav::protocols::navd::test_support

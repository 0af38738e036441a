// SPDX-License-Identifier: MIT
// The DUT's `$PNVBSOL`, `$PNVBCOV` and `$PNVBINN` output (docs/dut-contract.md) as the bench's
// OutputReader reads it: NMEA framing up to navd::kMaxSentence, whatever the DUT writes, in any
// reads, then navd::decode, decode_covariance or decode_innovation. A solution that decodes is a fixed point
// of encode(decode(.)); a covariance or an innovation is one after its first round (six
// significant digits).
#include "fuzz_support.hpp"
#include "nav/protocols/navd_covariance.hpp"
#include "nav/protocols/navd_innovation.hpp"
#include "nav/protocols/navd_solution.hpp"

namespace {

namespace nmea = nav::protocols::nmea;
namespace navd = nav::protocols::navd;


nav::protocols::ParseResult<nmea::Sentence> parse_output(nav::fuzz::ByteSpan buffer) {
  return nmea::parse_with_limit(buffer, navd::kMaxSentence);
}

/// encode(decode(.)) of a covariance sentence's text; empty when it does not decode.
std::string covariance_round(const std::string& text) {
  const auto again =
      nav::fuzz::parse_exactly<nmea::Sentence, &parse_output>(nav::fuzz::bytes_of(text));
  const auto decoded = navd::decode_covariance(again);
  NAV_ENSURE(decoded.has_value(), "an encoded covariance does not decode: " + text);
  return navd::encode(*decoded);
}

void check_covariance(const nmea::Sentence& s) {
  const auto cov = navd::decode_covariance(s);
  if (!cov) return;
  const std::string text = navd::encode(*cov);
  if (text.size() > navd::kMaxSentence) return;  // huge σ written out: no sentence
  const std::string once = covariance_round(text);
  if (once.size() > navd::kMaxSentence) return;
  NAV_ENSURE(covariance_round(once) == once, "encode(decode(.)) moves: " + once);
}

/// encode(decode(.)) of an innovation sentence's text.
std::string innovation_round(const std::string& text) {
  const auto again =
      nav::fuzz::parse_exactly<nmea::Sentence, &parse_output>(nav::fuzz::bytes_of(text));
  const auto decoded = navd::decode_innovation(again);
  NAV_ENSURE(decoded.has_value(), "an encoded innovation does not decode: " + text);
  return navd::encode(*decoded);
}

void check_innovation(const nmea::Sentence& s) {
  const auto in = navd::decode_innovation(s);
  if (!in) return;
  const std::string text = navd::encode(*in);
  if (text.size() > navd::kMaxSentence) return;  // huge ν written out: no sentence
  const std::string once = innovation_round(text);
  if (once.size() > navd::kMaxSentence) return;
  NAV_ENSURE(innovation_round(once) == once, "encode(decode(.)) moves: " + once);
}

void check(const nmea::Sentence& s) {
  if (s.talker + s.type == navd::kCovarianceAddress) {
    check_covariance(s);
    return;
  }
  if (s.talker + s.type == navd::kInnovationAddress) {
    check_innovation(s);
    return;
  }
  if (s.talker + s.type != navd::kAddress) return;
  const auto sol = navd::decode(s);
  if (!sol) return;
  const std::string text = navd::encode(*sol);
  if (text.size() > navd::kMaxSentence) return;  // e.g. "1e300" written out: no sentence
  const auto again =
      nav::fuzz::parse_exactly<nmea::Sentence, &parse_output>(nav::fuzz::bytes_of(text));
  const auto decoded = navd::decode(again);
  NAV_ENSURE(decoded.has_value(), "an encoded solution does not decode: " + text);
  NAV_ENSURE(navd::encode(*decoded) == text, "encode(decode(.)) moves: " + text);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const nav::fuzz::Input in(data, size);
  for (const auto& s : nav::fuzz::stream<nmea::Sentence, &parse_output>(in, '$')) {
    check(s);
  }
  return 0;
}

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

/// encode(decode(.)) of a sentence's text, with `decode` the codec of its kind.
template <auto decode>
std::string round_trip(const std::string& text) {
  const auto again =
      nav::fuzz::parse_exactly<nmea::Sentence, &parse_output>(nav::fuzz::bytes_of(text));
  const auto decoded = decode(again);
  NAV_ENSURE(decoded.has_value(), "an encoded sentence does not decode: " + text);
  return navd::encode(*decoded);
}

/// A covariance or an innovation that decodes is a fixed point of encode(decode(.)) after its
/// first round (six significant digits).
template <auto decode>
void check_rounded(const nmea::Sentence& s) {
  const auto decoded = decode(s);
  if (!decoded) return;
  const std::string text = navd::encode(*decoded);
  if (text.size() > navd::kMaxSentence) return;  // huge σ or ν written out: no sentence
  const std::string once = round_trip<decode>(text);
  if (once.size() > navd::kMaxSentence) return;
  NAV_ENSURE(round_trip<decode>(once) == once, "encode(decode(.)) moves: " + once);
}

void check(const nmea::Sentence& s) {
  if (s.talker + s.type == navd::kCovarianceAddress) {
    check_rounded<&navd::decode_covariance>(s);
    return;
  }
  if (s.talker + s.type == navd::kInnovationAddress) {
    check_rounded<&navd::decode_innovation>(s);
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

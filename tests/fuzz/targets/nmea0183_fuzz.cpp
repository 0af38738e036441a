// SPDX-License-Identifier: MIT
// NMEA 0183 (protocols.md 4) as navd reads its GPS line: sentences through the StreamDecoder in
// any reads, then the GGA / RMC / VTG / HDT / ZDA field decoders. A sentence framed again
// parses back to itself, and a decoded sentence built again is a fixed point of
// to_sentence(decode(.)).
#include "fuzz_support.hpp"
#include "nav/protocols/nmea0183.hpp"

namespace {

namespace nmea = nav::protocols::nmea;
using nav::fuzz::ByteSpan;


bool same(const nmea::Sentence& a, const nmea::Sentence& b) {
  return a.talker == b.talker && a.type == b.type && a.fields == b.fields;
}

/// s re-framed parses to s.
nmea::Sentence reframed(const nmea::Sentence& s) {
  const std::string text = nmea::frame(s);
  return nav::fuzz::parse_exactly<nmea::Sentence, &nmea::parse>(nav::fuzz::bytes_of(text));
}

/// to_sentence(decode(.)) reaches a fixed point after one step.
template <typename Decode>
void fixed_point(const nmea::Sentence& s, Decode decode) {
  const auto first = decode(s);
  if (!first) return;
  const nmea::Sentence built = nmea::to_sentence(*first, s.talker);
  const auto second = decode(built);
  NAV_ENSURE(second.has_value(), "a built sentence does not decode: " + nmea::frame(built));
  NAV_ENSURE(same(nmea::to_sentence(*second, s.talker), built),
             "to_sentence(decode(.)) moves: " + nmea::frame(built));
}

void check(const nmea::Sentence& s) {
  NAV_ENSURE(same(reframed(s), s), "a sentence framed again parses differently");
  if (s.type == "GGA") fixed_point(s, nmea::decode_gga);
  if (s.type == "RMC") fixed_point(s, nmea::decode_rmc);
  if (s.type == "VTG") fixed_point(s, nmea::decode_vtg);
  if (s.type == "HDT") fixed_point(s, nmea::decode_hdt);
  if (s.type == "ZDA") fixed_point(s, nmea::decode_zda);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const nav::fuzz::Input in(data, size);
  for (const auto& s : nav::fuzz::stream<nmea::Sentence, &nmea::parse>(in, '$')) {
    check(s);
  }
  return 0;
}

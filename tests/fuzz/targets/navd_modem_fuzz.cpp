// SPDX-License-Identifier: MIT
// `$PNVBPOS` (docs/dut-contract.md, "Acoustic modem") as navd's modem link reads what the
// channel delivers: NMEA sentences through the StreamDecoder in any reads, then
// navd_modem::parse on each. A report that decodes is encodable, fits one modem packet and is
// a fixed point of encode(parse(.)).
#include "fuzz_support.hpp"
#include "nav/protocols/navd_modem.hpp"

namespace {

namespace modem = nav::protocols::navd_modem;
namespace nmea = nav::protocols::nmea;


void check(const modem::Position& p) {
  NAV_ENSURE(modem::encodable(p), "a decoded report is not encodable");
  const std::string text = modem::encode(p);
  NAV_ENSURE(text.size() <= modem::kMaxPacketBytes, "a report longer than a packet: " + text);
  const auto again =
      nav::fuzz::parse_exactly<modem::Position, &modem::parse>(nav::fuzz::bytes_of(text));
  NAV_ENSURE(modem::encode(again) == text, "encode(parse(.)) moves: " + text);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const nav::fuzz::Input in(data, size);
  // navd's modem link: framing first, then the report's fields.
  for (const auto& s : nav::fuzz::stream<nmea::Sentence, &nmea::parse>(in, '$')) {
    if (s.talker + s.type != modem::kAddress) continue;
    if (const auto p = modem::decode(s)) check(*p);
  }
  // The one-step parser of the same stream.
  nav::fuzz::drain<modem::Position, &modem::parse>(
      in.stream, [](const modem::Position& p, nav::fuzz::ByteSpan) { check(p); });
  return 0;
}

// SPDX-License-Identifier: MIT
// Water Linked DVL-A50 packets (protocols.md 3d) as navd reads its DVL line: through the
// StreamDecoder in any reads, then the report decoders. A packet framed again parses back to
// itself; a decoded report is a fixed point of to_packet(decode(.)).
#include "fuzz_support.hpp"
#include "nav/protocols/waterlinked_a50.hpp"

namespace {

namespace a50 = nav::protocols::waterlinked_a50;


bool same(const a50::Packet& a, const a50::Packet& b) {
  return a.direction == b.direction && a.command == b.command && a.options == b.options;
}

template <typename Decode>
void fixed_point(const a50::Packet& p, Decode decode) {
  const auto first = decode(p);
  if (!first) return;
  const a50::Packet built = a50::to_packet(*first);
  const auto second = decode(built);
  NAV_ENSURE(second.has_value(), "a built report does not decode: " + a50::frame(built));
  NAV_ENSURE(same(a50::to_packet(*second), built),
             "to_packet(decode(.)) moves: " + a50::frame(built));
}

void check(const a50::Packet& p) {
  const std::string text = a50::frame(p);
  // A command read without its optional checksum close to the bound is, framed with one,
  // longer than a packet may be: not a line to parse back.
  if (text.size() > a50::kMaxLine) return;
  const auto again = nav::fuzz::parse_exactly<a50::Packet, &a50::parse>(nav::fuzz::bytes_of(text));
  NAV_ENSURE(same(again, p), "a packet framed again parses differently: " + text);
  switch (p.command) {
    case 'z': fixed_point(p, a50::decode_velocity); break;
    case 'u': fixed_point(p, a50::decode_transducer); break;
    case 'p': fixed_point(p, a50::decode_position); break;
    case 'x': fixed_point(p, a50::decode_legacy_velocity); break;
    case 't': fixed_point(p, a50::decode_legacy_transducer); break;
    default: break;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const nav::fuzz::Input in(data, size);
  for (const auto& p : nav::fuzz::stream<a50::Packet, &a50::parse>(in, 'w')) check(p);
  return 0;
}

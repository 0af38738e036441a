// SPDX-License-Identifier: MIT
// EvoLogics USBL notifications (protocols.md 6c) as navd reads its USBL line: data-mode and
// command-mode frames through the StreamDecoder (sync on '+' or an upper-case letter, as
// navd) in any reads. A notification encoded again is a fixed point of encode(parse(.)).
#include "fuzz_support.hpp"
#include "nav/protocols/evologics_usbl.hpp"

namespace {

namespace evo = nav::protocols::evologics;


bool usbl_sync(std::uint8_t b) { return b == '+' || (b >= 'A' && b <= 'Z'); }  // as navd

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const nav::fuzz::Input in(data, size);
  for (const auto& n : nav::fuzz::stream<evo::Notification, &evo::parse>(in, &usbl_sync)) {
    const std::string text = evo::encode(n);
    if (text.size() > evo::kMaxPayload) continue;  // e.g. "1e300" written out: no line
    const auto again =
        nav::fuzz::parse_exactly<evo::Notification, &evo::parse>(nav::fuzz::bytes_of(text));
    NAV_ENSURE(again.framing == n.framing, "framing changes: " + text);
    NAV_ENSURE(evo::encode(again) == text, "encode(parse(.)) moves: " + text);
  }
  return 0;
}

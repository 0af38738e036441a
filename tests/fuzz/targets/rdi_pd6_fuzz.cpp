// SPDX-License-Identifier: MIT
// Teledyne RDI PD6 lines (protocols.md 3c) as navd reads its DVL line: through the
// StreamDecoder in any reads. A decoded line encoded again is a fixed point of
// encode(parse(.)).
#include "fuzz_support.hpp"
#include "nav/protocols/rdi_pd6.hpp"

namespace {

namespace pd6 = nav::protocols::rdi_pd6;
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const nav::fuzz::Input in(data, size);
  for (const auto& line : nav::fuzz::stream<pd6::Line, &pd6::parse>(in, ':')) {
    const std::string text = pd6::encode(line);
    if (text.size() > pd6::kMaxLine) continue;  // e.g. "1e300" written out: no line
    const auto again = nav::fuzz::parse_exactly<pd6::Line, &pd6::parse>(nav::fuzz::bytes_of(text));
    NAV_ENSURE(pd6::encode(again) == text, "encode(parse(.)) moves: " + text);
  }
  return 0;
}

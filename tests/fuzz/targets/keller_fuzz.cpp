// SPDX-License-Identifier: MIT
// Keller bus frames (protocols.md 6a): answers as navd's poller reads them (through the
// StreamDecoder, a frame starting at any address byte 0..250) and requests as the emulator
// reads them. Frames are CRC-checked binary, so each one decoded must encode back to exactly
// its own bytes.
#include <algorithm>

#include "fuzz_support.hpp"
#include "nav/protocols/keller_bus.hpp"

namespace {

namespace keller = nav::protocols::keller;
using nav::fuzz::ByteSpan;


bool keller_sync(std::uint8_t b) { return b <= keller::kMaxAddress; }  // as navd

template <typename Message>
void encodes_to(const Message& m, ByteSpan bytes) {
  const nav::protocols::Bytes e = keller::encode(m);
  NAV_ENSURE(e.size() == bytes.size() && std::equal(e.begin(), e.end(), bytes.begin()),
             "a Keller frame does not encode back to its bytes");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const nav::fuzz::Input in(data, size);
  nav::fuzz::stream<keller::Response, &keller::parse_response>(in, &keller_sync);
  nav::fuzz::stream<keller::Request, &keller::parse_request>(in, &keller_sync);
  nav::fuzz::drain<keller::Response, &keller::parse_response>(in.stream,
                                                              encodes_to<keller::Response>);
  nav::fuzz::drain<keller::Request, &keller::parse_request>(in.stream,
                                                            encodes_to<keller::Request>);
  return 0;
}

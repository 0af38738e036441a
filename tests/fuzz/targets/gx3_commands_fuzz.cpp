// SPDX-License-Identifier: MIT
// MicroStrain GX3 host commands (protocols.md 1a) as the emulator reads them from the host:
// `C4 C1 29 xx` and `FA 75 B4` among any bytes, in any reads. A command decoded must encode
// back to exactly its bytes.
#include <algorithm>

#include "fuzz_support.hpp"
#include "nav/protocols/microstrain_gx3.hpp"

namespace {

namespace gx3 = nav::protocols::gx3;

bool command_start(std::uint8_t b) {
  return b == gx3::kCmdSetContinuous || b == gx3::kCmdStopContinuous;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const nav::fuzz::Input in(data, size);
  nav::fuzz::stream<gx3::HostCommand, &gx3::parse_host_command>(in, &command_start, 64);
  nav::fuzz::drain<gx3::HostCommand, &gx3::parse_host_command>(
      in.stream, [](const gx3::HostCommand& c, nav::fuzz::ByteSpan bytes) {
        const nav::protocols::Bytes e = gx3::encode(c);
        NAV_ENSURE(e.size() == bytes.size() && std::equal(e.begin(), e.end(), bytes.begin()),
                   "a host command does not encode back to its bytes");
      });
  return 0;
}

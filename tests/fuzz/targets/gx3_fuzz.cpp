// SPDX-License-Identifier: MIT
// MicroStrain GX3 replies (protocols.md 1a) as navd reads its AHRS line: 0xCB through the
// StreamDecoder, and the 0xCE and 0xC4 replies with the same resynchronisation. A reply is
// checksummed binary, so each one decoded must encode back to exactly its own bytes.
#include "fuzz_support.hpp"
#include "nav/protocols/microstrain_gx3.hpp"

namespace {

namespace gx3 = nav::protocols::gx3;
using nav::fuzz::ByteSpan;
using nav::fuzz::Input;


/// encode(m) is the bytes m was parsed from.
template <typename Message>
void encodes_to(const Message& m, ByteSpan bytes) {
  const nav::protocols::Bytes e = gx3::encode(m);
  NAV_ENSURE(ByteSpan(e).size() == bytes.size() && std::equal(e.begin(), e.end(), bytes.begin()),
             "a GX3 reply does not encode back to its bytes");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const Input in(data, size);
  nav::fuzz::stream<gx3::AccelRateMag, &gx3::parse>(in, gx3::kCmdAccelRateMag);
  nav::fuzz::stream<gx3::EulerAngles, &gx3::parse_euler_angles>(in, gx3::kCmdEulerAngles);
  nav::fuzz::drain<gx3::AccelRateMag, &gx3::parse>(in.stream, encodes_to<gx3::AccelRateMag>);
  nav::fuzz::drain<gx3::EulerAngles, &gx3::parse_euler_angles>(in.stream,
                                                               encodes_to<gx3::EulerAngles>);
  nav::fuzz::drain<gx3::ContinuousModeReply, &gx3::parse_continuous_mode_reply>(
      in.stream, encodes_to<gx3::ContinuousModeReply>);
  return 0;
}

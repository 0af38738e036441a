// SPDX-License-Identifier: MIT
// LinkQuest NavQuest NQ1 lines (protocols.md 3a) as navd reads its DVL line: through the
// StreamDecoder in any reads. encode(parse(.)) settles after two steps: a value that rounds to
// "0.0" prints as an exact zero, "0", the second time.
#include "fuzz_support.hpp"
#include "nav/protocols/navquest_nq1.hpp"

namespace {

namespace nq1 = nav::protocols::navquest_nq1;
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const nav::fuzz::Input in(data, size);
  for (const auto& m : nav::fuzz::stream<nq1::Nq1, &nq1::parse>(in, '$')) {
    const std::string first = nq1::encode(m);
    if (first.size() > nq1::kMaxLine) continue;  // e.g. "1e300" written out: no line
    const std::string text = nq1::encode(
        nav::fuzz::parse_exactly<nq1::Nq1, &nq1::parse>(nav::fuzz::bytes_of(first)));
    const auto again = nav::fuzz::parse_exactly<nq1::Nq1, &nq1::parse>(nav::fuzz::bytes_of(text));
    NAV_ENSURE(nq1::encode(again) == text, "encode(parse(.)) moves: " + text);
    (void)nq1::vehicle_velocity_mps(m);
  }
  return 0;
}

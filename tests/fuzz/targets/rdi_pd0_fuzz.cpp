// SPDX-License-Identifier: MIT
// Teledyne RDI PD0 ensembles (protocols.md 3b) as navd reads its DVL line: through the
// StreamDecoder (with navd's 72 KiB PD0 bound) in any reads, and the SI helpers on what
// decodes. An ensemble encoded again parses back and is a fixed point of encode(parse(.)),
// when the encoder can write it: encode() (the emulator's) needs a known data type (an
// ensemble of unknown ones parses empty) and writes RTC years 1980..2079 (the Y2K clock
// carries any).
#include "fuzz_support.hpp"
#include "nav/protocols/rdi_pd0.hpp"

namespace {

namespace pd0 = nav::protocols::rdi_pd0;

constexpr std::size_t kMaxBuffer = 72 * 1024;  // navd's bound for PD0 (AidingInput)

void check(const pd0::Ensemble& e) {
  if (e.fixed_leader) {
    (void)pd0::coordinates(*e.fixed_leader);
    (void)pd0::beam_angle_deg(*e.fixed_leader);
  }
  if (!e.fixed_leader && !e.variable_leader && !e.velocity && !e.correlation &&
      !e.echo_intensity && !e.percent_good && !e.bottom_track) {
    return;
  }
  if (e.variable_leader) {
    (void)pd0::pressure_pa(*e.variable_leader);
    (void)pd0::unix_seconds(e.variable_leader->rtc);
  }
  if (e.bottom_track) (void)pd0::vehicle_velocity_mps(*e.bottom_track);
  if (!e.fixed_leader && !e.variable_leader && !e.velocity && !e.correlation &&
      !e.echo_intensity && !e.percent_good && !e.bottom_track) {
    return;
  }
  if (e.variable_leader) {
    const int year = e.variable_leader->rtc.year;
    if (year < 1980 || year > 2079) return;
  }
  const nav::protocols::Bytes bytes = pd0::encode(e);
  const pd0::Ensemble again = nav::fuzz::parse_exactly<pd0::Ensemble, &pd0::parse>(bytes);
  NAV_ENSURE(pd0::encode(again) == bytes, "encode(parse(.)) of a PD0 ensemble moves");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const nav::fuzz::Input in(data, size);
  for (const auto& e : nav::fuzz::stream<pd0::Ensemble, &pd0::parse>(in, pd0::kHeaderId,
                                                                     kMaxBuffer)) {
    check(e);
  }
  return 0;
}

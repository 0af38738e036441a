// SPDX-License-Identifier: MIT
// Wheel-encoder frames (protocols/wheel_encoder.hpp) read through fixtures/crawler.dbc, as
// navd's CAN front end reads a crawler's bus (it also takes the NMEA 2000 frames among them):
// frames of any identifier (can_frames.hpp). A sample that decodes encodes back to a frame
// that decodes to the same sample.
#include <cstdlib>

#include "can_frames.hpp"
#include "can_input.hpp"
#include "fuzz_support.hpp"
#include "nav/protocols/wheel_encoder.hpp"
#include "source_paths.hpp"

namespace {

namespace dbc = nav::protocols::dbc;
namespace wheel = nav::protocols::wheel_encoder;

const dbc::Database& crawler() {
  static const dbc::Database db = [] {
    auto loaded = dbc::load(nav::test_paths::source_dir() + "/fixtures/crawler.dbc");
    NAV_ENSURE(loaded.has_value(), "fixtures/crawler.dbc does not load");
    return *loaded;
  }();
  return db;
}

bool same(const wheel::WheelEncoderSample& a, const wheel::WheelEncoderSample& b) {
  return a.wheel == b.wheel && a.ticks == b.ticks && a.omega == b.omega &&
         a.counter == b.counter && a.valid == b.valid;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const wheel::WheelEncoderCodec codec = *wheel::WheelEncoderCodec::from_database(crawler());
  auto input = nav::dut::CanInput::with_dbc(crawler());
  NAV_ENSURE(input.has_value(), "the crawler DBC is refused");
  nav::protocols::ByteSpan bytes(data, size);
  while (const auto f = nav::fuzz::next_frame(bytes)) {
    input->feed(*f);
    if (f->rtr || f->error || !codec.wheel_of(f->id, f->extended)) continue;
    const dbc::Frame frame{f->id, f->extended, nav::protocols::Bytes(f->payload().begin(),
                                                                     f->payload().end())};
    const auto sample = codec.decode(frame);
    if (!sample) continue;
    const auto encoded = codec.encode(*sample);
    NAV_ENSURE(encoded.has_value(), "a decoded sample does not encode");
    const auto again = codec.decode(*encoded);
    NAV_ENSURE(again.has_value() && same(*again, *sample), "decode(encode(.)) differs");
  }
  (void)input->counters_text();
  return 0;
}

// SPDX-License-Identifier: MIT
// EBIMU-9DOF lines (protocols.md 2) as navd reads them: lines through the StreamDecoder in any
// reads, each decoded under every output configuration. A sample encoded again is a fixed
// point of encode(decode(parse(.))).
#include "fuzz_support.hpp"
#include "nav/protocols/ebimu.hpp"

namespace {

namespace ebimu = nav::protocols::ebimu;


void check(const ebimu::Line& line) {
  for (const auto orientation : {ebimu::Orientation::kEuler, ebimu::Orientation::kQuaternion}) {
    for (int extra = 0; extra < 4; ++extra) {
      const ebimu::OutputConfig config{orientation, (extra & 1) != 0, (extra & 2) != 0};
      const auto sample = ebimu::decode(line, config);
      NAV_ENSURE(sample.has_value() == (line.values.size() == ebimu::value_count(config)),
                 "decode fails for a line of the right length, or decodes one of another");
      if (!sample) continue;
      const std::string text = ebimu::encode(*sample);
      if (text.size() > ebimu::kMaxLine) continue;  // e.g. "1e300" written out: no line
      const auto again = nav::fuzz::parse_exactly<ebimu::Line, &ebimu::parse>(
          nav::fuzz::bytes_of(text));
      const auto decoded = ebimu::decode(again, ebimu::config_of(*sample));
      NAV_ENSURE(decoded.has_value(), "an encoded sample does not decode: " + text);
      NAV_ENSURE(ebimu::encode(*decoded) == text, "encode(decode(.)) moves: " + text);
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const nav::fuzz::Input in(data, size);
  for (const auto& line : nav::fuzz::stream<ebimu::Line, &ebimu::parse>(
           in, static_cast<std::uint8_t>(ebimu::kStartOfLine))) {
    check(line);
  }
  return 0;
}

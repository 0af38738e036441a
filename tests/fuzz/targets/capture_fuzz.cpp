// SPDX-License-Identifier: MIT
// Serial capture files (bench/include/nav/bench/capture.hpp) as `navbench replay` and
// `decode` read them. A capture that parses, written again line by line as `record` writes
// it, parses back to the same lines.
#include <cstdio>
#include <cstdlib>

#include "fuzz_support.hpp"
#include "nav/bench/capture.hpp"

namespace {

namespace bench = nav::bench;

std::string written(const std::vector<bench::CaptureLine>& lines) {
  char* buf = nullptr;
  std::size_t len = 0;
  std::FILE* f = ::open_memstream(&buf, &len);
  NAV_ENSURE(f != nullptr, "open_memstream failed");
  for (const auto& l : lines) bench::write_capture_line(f, l.t, l.port, l.bytes);
  std::fclose(f);
  std::string text(buf, len);
  std::free(buf);
  return text;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const auto lines = bench::parse_capture(text, "fuzz.log");
  if (!lines) return 0;
  const std::string again_text = written(*lines);
  const auto again = bench::parse_capture(again_text, "again.log");
  NAV_ENSURE(again.has_value(), "a written capture does not parse: " + again_text);
  NAV_ENSURE(again->size() == lines->size(), "a written capture has other lines");
  for (std::size_t i = 0; i < lines->size(); ++i) {
    const auto& a = (*lines)[i];
    const auto& b = (*again)[i];
    NAV_ENSURE(a.t == b.t && a.port == b.port && a.bytes == b.bytes,
               "a written capture line parses differently: line " + std::to_string(a.line_no));
  }
  return 0;
}

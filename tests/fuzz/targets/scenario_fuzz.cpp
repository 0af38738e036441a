// SPDX-License-Identifier: MIT
// Scenario files (docs/scenario.md) as `navbench run` loads them: any bytes, through
// load_scenario(). A refused file has a one-line error naming the file.
#include "file_input.hpp"
#include "nav/bench/scenario.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = nav::fuzz::as_file(data, size);
  const auto s = nav::bench::load_scenario(path);
  if (!s) {
    const std::string& detail = s.error().detail;
    NAV_ENSURE(detail.rfind(path, 0) == 0, "an error that does not name the file: " + detail);
    NAV_ENSURE(detail.find('\n') == std::string::npos, "a multi-line error: " + detail);
  }
  return 0;
}

// SPDX-License-Identifier: MIT
// navd's config file (dut/navd/config.hpp) as `navd --config` loads it: any bytes, through
// load_config(). A refused file has a one-line error; an accepted one has valid parameters.
#include "config.hpp"
#include "file_input.hpp"
#include "nav/estimator/filter_params.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = nav::fuzz::as_file(data, size);
  const auto config = nav::dut::load_config(path);
  if (!config) {
    const std::string& detail = config.error().detail;
    NAV_ENSURE(detail.find('\n') == std::string::npos, "a multi-line error: " + detail);
    return 0;
  }
  NAV_ENSURE(nav::estimator::validate(config->filter).has_value(), "invalid filter parameters");
  NAV_ENSURE(nav::dut::validate(config->navd).has_value(), "invalid navd parameters");
  return 0;
}

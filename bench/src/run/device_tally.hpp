// SPDX-License-Identifier: MIT
// What every device of a run put on its line: totals, and second by second of scenario time
// (the report's device timeline, device-rates.csv). Private to nav_bench.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "nav/common/time.hpp"
#include "nav/reports/run_record.hpp"

namespace nav::bench::detail {

class DeviceTally {
 public:
  /// devices: how many; duration: the scenario's (seconds past it are counted in the last).
  void reset(std::size_t devices, Duration duration) {
    const auto seconds = static_cast<std::size_t>(std::ceil(to_seconds(duration)));
    per_second_.assign(devices, std::vector<reports::DeviceSecond>(std::max<std::size_t>(seconds, 1)));
    total_.assign(devices, {});
  }

  /// Counts what device d wrote (or dropped) at scenario time t.
  void add(std::uint32_t d, Duration t, std::uint32_t messages, std::uint64_t bytes,
           std::uint64_t dropped) {
    auto& row = per_second_[d];
    const double s = std::max(0.0, to_seconds(t));
    const auto k = std::min(static_cast<std::size_t>(s), row.size() - 1);
    for (auto* c : {&row[k], &total_[d]}) {
      c->messages += messages;
      c->bytes += bytes;
      c->bytes_dropped += dropped;
    }
  }

  const reports::DeviceSecond& total(std::uint32_t d) const { return total_[d]; }
  const std::vector<reports::DeviceSecond>& per_second(std::uint32_t d) const {
    return per_second_[d];
  }

 private:
  std::vector<std::vector<reports::DeviceSecond>> per_second_;
  std::vector<reports::DeviceSecond> total_;
};

}  // namespace nav::bench::detail

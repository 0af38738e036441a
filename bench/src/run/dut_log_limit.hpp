// SPDX-License-Identifier: MIT
// A limit on a DUT's log (dut.log): the DUT writes the file itself (its stdout and stderr,
// appended), so the bench cuts it back to the limit every time the watchdog looks, counting
// what it cut, and says so in the file once the DUT has stopped. The disk holds at most the
// limit plus what the DUT writes in one watchdog period (10 ms). Private to nav_bench.
#pragma once

#include <cstdint>
#include <string>

namespace nav::bench::detail {

class DutLogLimit {
 public:
  /// Opens the log the DUT was started with; a limit of 0 is no limit.
  DutLogLimit(std::string path, std::uint64_t limit);
  ~DutLogLimit();
  DutLogLimit(const DutLogLimit&) = delete;
  DutLogLimit& operator=(const DutLogLimit&) = delete;

  /// Cuts the file back to the limit (from the loop, while the DUT runs).
  void enforce();
  /// After the DUT stopped: the last cut, and a line at the end of the file saying what was
  /// cut.
  void finish();

  const std::string& path() const { return path_; }
  std::uint64_t limit() const { return limit_; }
  /// Bytes the DUT wrote past the limit, not kept.
  std::uint64_t cut_bytes() const { return cut_; }

 private:
  std::string path_;
  std::uint64_t limit_;
  int fd_ = -1;
  std::uint64_t cut_ = 0;
  bool finished_ = false;
};

}  // namespace nav::bench::detail

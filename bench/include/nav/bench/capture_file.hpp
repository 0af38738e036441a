// SPDX-License-Identifier: MIT
// A receive capture (what a DUT wrote) with a size limit: a DUT that floods its lines cannot
// fill the disk. Lines are written whole until the file holds `limit` bytes; after that
// they are counted, not written, and the run says so (RunRecord::logs_cut).
#pragma once

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <span>
#include <string>

#include "nav/common/time.hpp"

namespace nav::bench {

/// navbench's default limit of each log a DUT fills (receive captures, dut.log) [bytes].
inline constexpr std::uint64_t kDefaultLogLimit = 256ull << 20;

class CaptureFile {
 public:
  /// Creates (truncates) the file; throws std::runtime_error naming it when it cannot. A
  /// limit of 0 is no limit.
  CaptureFile(const std::filesystem::path& path, std::uint64_t limit);
  ~CaptureFile();
  CaptureFile(const CaptureFile&) = delete;
  CaptureFile& operator=(const CaptureFile&) = delete;

  /// Appends "(<sec>.<nsec>) <port> <hex>" (append_capture_line), or counts it when
  /// the line would take the file past its limit. Safe from several threads.
  void write(Duration since_t0, const std::string& port, std::span<const std::uint8_t> bytes);
  void flush();

  const std::filesystem::path& path() const { return path_; }
  std::uint64_t limit() const { return limit_; }
  /// Bytes of the lines not written (what the DUT sent, not their hex).
  std::uint64_t cut_bytes() const;

 private:
  std::filesystem::path path_;
  std::uint64_t limit_;
  mutable std::mutex mutex_;
  std::FILE* f_ = nullptr;
  std::uint64_t size_ = 0;
  std::uint64_t cut_bytes_ = 0;
  std::string line_;  ///< the line being formatted (kept: no allocation per line)
};

}  // namespace nav::bench

// SPDX-License-Identifier: MIT
#include "run/dut_log_limit.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <utility>

namespace nav::bench::detail {

DutLogLimit::DutLogLimit(std::string path, std::uint64_t limit)
    : path_(std::move(path)), limit_(limit), fd_(::open(path_.c_str(), O_WRONLY | O_CLOEXEC)) {}

DutLogLimit::~DutLogLimit() {
  if (fd_ >= 0) ::close(fd_);
}

void DutLogLimit::enforce() {
  if (fd_ < 0 || limit_ == 0) return;
  struct stat st {};
  if (::fstat(fd_, &st) != 0) return;
  const auto size = static_cast<std::uint64_t>(st.st_size);
  if (size <= limit_) return;
  // The DUT appends (O_APPEND): its next write goes to the new end.
  if (::ftruncate(fd_, static_cast<off_t>(limit_)) == 0) cut_ += size - limit_;
}

void DutLogLimit::finish() {
  if (finished_) return;
  finished_ = true;
  enforce();
  if (fd_ < 0 || cut_ == 0) return;
  char note[200];
  const int n = std::snprintf(note, sizeof note,
                              "\n[navbench] this log was cut at its limit of %llu bytes: %llu "
                              "bytes the DUT wrote after that were not kept\n",
                              static_cast<unsigned long long>(limit_),
                              static_cast<unsigned long long>(cut_));
  if (n > 0) (void)::pwrite(fd_, note, static_cast<std::size_t>(n), static_cast<off_t>(limit_));
}

}  // namespace nav::bench::detail

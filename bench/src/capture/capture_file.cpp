// SPDX-License-Identifier: MIT
#include "nav/bench/capture_file.hpp"

#include <stdexcept>

#include "nav/bench/capture.hpp"

namespace nav::bench {

CaptureFile::CaptureFile(const std::filesystem::path& path, std::uint64_t limit)
    : path_(path), limit_(limit), f_(std::fopen(path.c_str(), "w")) {
  if (!f_) throw std::runtime_error("cannot write " + path.string());
}

CaptureFile::~CaptureFile() { std::fclose(f_); }

void CaptureFile::write(Duration since_t0, const std::string& port,
                        std::span<const std::uint8_t> bytes) {
  std::lock_guard lock(mutex_);
  line_.clear();
  append_capture_line(line_, since_t0, port, bytes);
  if (limit_ > 0 && size_ + line_.size() > limit_) {
    cut_bytes_ += bytes.size();
    return;
  }
  std::fwrite(line_.data(), 1, line_.size(), f_);
  size_ += line_.size();
}

void CaptureFile::flush() {
  std::lock_guard lock(mutex_);
  std::fflush(f_);
}

std::uint64_t CaptureFile::cut_bytes() const {
  std::lock_guard lock(mutex_);
  return cut_bytes_;
}

}  // namespace nav::bench

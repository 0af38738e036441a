// SPDX-License-Identifier: MIT
#include "nav/bench/capture_file.hpp"

#include <stdexcept>

namespace nav::bench {

CaptureFile::CaptureFile(const std::filesystem::path& path, std::uint64_t limit)
    : path_(path), limit_(limit), f_(std::fopen(path.c_str(), "w")) {
  if (!f_) throw std::runtime_error("cannot write " + path.string());
}

CaptureFile::~CaptureFile() { std::fclose(f_); }

void CaptureFile::write(Duration since_t0, const std::string& port,
                        std::span<const std::uint8_t> bytes) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  const long long ns = since_t0.count();
  const long long a = ns < 0 ? -ns : ns;
  char head[64];
  const int n = std::snprintf(head, sizeof head, "(%s%lld.%09lld) ", ns < 0 ? "-" : "",
                              a / 1'000'000'000, a % 1'000'000'000);
  std::lock_guard lock(mutex_);
  const std::uint64_t length = static_cast<std::uint64_t>(n) + port.size() + 1 + 2 * bytes.size() + 1;
  if (limit_ > 0 && size_ + length > limit_) {
    cut_bytes_ += bytes.size();
    ++cut_lines_;
    return;
  }
  line_.assign(head, static_cast<std::size_t>(n));
  line_ += port;
  line_ += ' ';
  for (const auto b : bytes) {
    line_ += kHex[b >> 4];
    line_ += kHex[b & 0x0F];
  }
  line_ += '\n';
  std::fwrite(line_.data(), 1, line_.size(), f_);
  size_ += length;
}

void CaptureFile::flush() {
  std::lock_guard lock(mutex_);
  std::fflush(f_);
}

std::uint64_t CaptureFile::cut_bytes() const {
  std::lock_guard lock(mutex_);
  return cut_bytes_;
}

std::uint64_t CaptureFile::cut_lines() const {
  std::lock_guard lock(mutex_);
  return cut_lines_;
}

}  // namespace nav::bench

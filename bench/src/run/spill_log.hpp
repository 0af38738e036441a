// SPDX-License-Identifier: MIT
// An append-only log of fixed-size records that keeps one block in memory: a long run's
// per-message records (lateness, the DUT's solutions) go to an unnamed file as they come and
// are read back once, at the end, so that a run's memory does not grow with its length.
// Private to nav_bench.
//
//   push_back() --(block full)--> write to the file (O_TMPFILE in dir: gone when closed)
//   read_all()  --> the file's records, then the block's, in order
//
// A file that cannot be made or written (a full disk) is not a lost run: the log keeps its
// records in memory from then on.
#pragma once

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace nav::bench::detail {

template <class T>
class SpillLog {
  static_assert(std::is_trivially_copyable_v<T>, "records go to a file byte for byte");

 public:
  /// dir: where the unnamed file is made (the run folder); empty: the system's temporary
  /// folder. block: records kept in memory before they go to the file.
  explicit SpillLog(std::string dir = {}, std::size_t block = 4096)
      : dir_(std::move(dir)), block_items_(block) {
    block_.reserve(block_items_);
  }
  ~SpillLog() {
    if (fd_ >= 0) ::close(fd_);
  }
  SpillLog(const SpillLog&) = delete;
  SpillLog& operator=(const SpillLog&) = delete;

  /// Where the file is made, when set before the first block goes (the run folder).
  void place(std::string dir) {
    if (fd_ < 0) dir_ = std::move(dir);
  }

  void push_back(const T& v) {
    block_.push_back(v);
    if (block_.size() >= block_items_ && !in_memory_) spill();
  }
  std::size_t size() const { return spilled_ + block_.size(); }
  bool empty() const { return size() == 0; }
  /// Records spilled to the file so far.
  std::size_t spilled() const { return spilled_; }

  /// Every record, in the order pushed.
  std::vector<T> read_all() const {
    std::vector<T> out(spilled_);
    const std::size_t bytes = spilled_ * sizeof(T);
    std::size_t done = 0;
    while (done < bytes) {
      const ssize_t n = ::pread(fd_, reinterpret_cast<char*>(out.data()) + done, bytes - done,
                                static_cast<off_t>(done));
      if (n <= 0) break;
      done += static_cast<std::size_t>(n);
    }
    out.resize(done / sizeof(T));  // a file that could not be read back: what it gave
    out.insert(out.end(), block_.begin(), block_.end());
    return out;
  }

 private:
  void spill() {
    if (fd_ < 0 && !open_file()) {
      in_memory_ = true;
      return;
    }
    const char* p = reinterpret_cast<const char*>(block_.data());
    std::size_t left = block_.size() * sizeof(T);
    const auto at = static_cast<off_t>(spilled_ * sizeof(T));
    std::size_t done = 0;
    while (done < left) {
      const ssize_t n = ::pwrite(fd_, p + done, left - done, at + static_cast<off_t>(done));
      if (n <= 0) {
        in_memory_ = true;  // the disk is full: keep everything here from now on
        return;
      }
      done += static_cast<std::size_t>(n);
    }
    spilled_ += block_.size();
    block_.clear();
  }
  bool open_file() {
    const std::string dir = dir_.empty() ? std::string(P_tmpdir) : dir_;
    fd_ = ::open(dir.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
    if (fd_ < 0) {  // a file system without O_TMPFILE: a named file, unlinked at once
      std::string path = dir + "/.spill-XXXXXX";
      fd_ = ::mkostemp(path.data(), O_CLOEXEC);
      if (fd_ >= 0) ::unlink(path.c_str());
    }
    return fd_ >= 0;
  }

  std::string dir_;
  std::size_t block_items_;
  std::vector<T> block_;
  int fd_ = -1;
  std::size_t spilled_ = 0;
  bool in_memory_ = false;
};

}  // namespace nav::bench::detail

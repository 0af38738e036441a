// SPDX-License-Identifier: MIT
// Reads the DUT's output port on its own thread: timestamps every read (CLOCK_MONOTONIC),
// writes it to the receive capture, and decodes `$PNVBSOL` solutions.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include "nav/common/time.hpp"
#include "nav/protocols/navd_solution.hpp"
#include "nav/protocols/parse.hpp"

namespace nav::bench {

/// One solution as received.
struct Answer {
  Timestamp rx{};  ///< CLOCK_MONOTONIC when the read that completed it returned
  protocols::navd::Solution solution;
};

class OutputReader {
 public:
  /// fd: master side of the DUT's output pty (non-blocking). capture: file for
  /// "(<sec>.<nsec>) output <hex>" lines, times relative to t0 (CLOCK_MONOTONIC).
  OutputReader(int fd, std::FILE* capture, Timestamp t0);
  ~OutputReader();
  OutputReader(const OutputReader&) = delete;
  OutputReader& operator=(const OutputReader&) = delete;

  void start();
  /// Stops the thread after reading what is already buffered.
  void stop();

  /// Waits until `count` answers naming this tag have arrived (a trigger repeated by a
  /// `stuck` fault is answered once per copy) or the deadline passes; true if they did.
  bool wait_for(std::uint64_t tag, Timestamp deadline, std::size_t count = 1);
  /// Time of the latest answer (0 if none).
  Timestamp last_answer_time() const;
  std::size_t answer_count() const;
  /// All answers so far, in arrival order.
  std::vector<Answer> answers() const;
  std::size_t malformed() const;

 private:
  void loop();
  void consume(Timestamp rx);

  int fd_;
  std::FILE* capture_;
  Timestamp t0_;
  std::thread thread_;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  bool stop_ = false;
  protocols::Bytes buffer_;
  std::vector<Answer> answers_;
  std::unordered_map<std::uint64_t, std::size_t> answers_by_tag_;  ///< answers naming each tag
  std::size_t malformed_ = 0;
};

}  // namespace nav::bench

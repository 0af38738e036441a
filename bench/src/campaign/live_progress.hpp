// SPDX-License-Identifier: MIT
// A long campaign's live progress line on a terminal: runs done of the total, running,
// failures so far, elapsed time and an estimate of the time left, rewritten in place at most
// once a second. Each finished run's own line is printed above it and stays, so a log (stderr
// not a terminal) gets those lines only. Private to nav_bench's campaign/.
#pragma once

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>

namespace nav::bench::detail {

class LiveProgress {
 public:
  using Clock = std::chrono::steady_clock;

  /// Draws nothing unless `enabled` (not --quiet) and stderr is a terminal.
  LiveProgress(std::size_t total, bool enabled)
      : total_(total), live_(enabled && ::isatty(STDERR_FILENO) == 1), start_(Clock::now()) {}

  /// A run ended: its line stays; `failed` counts it among the failures.
  void finished(const std::string& line, bool failed) {
    ++done_;
    failed_ += failed ? 1 : 0;
    if (running_ > 0) --running_;
    clear();
    std::fprintf(stderr, "%s\n", line.c_str());
    draw(running_);
  }

  /// Redraws the live line (at most once a second) with `running` runs in flight.
  void tick(std::size_t running) {
    running_ = running;
    if (Clock::now() - drawn_ >= std::chrono::seconds(1)) draw(running);
  }

  /// Removes the live line (before the table and the last messages).
  void clear() {
    if (live_ && shown_) std::fputs("\r\033[K", stderr);
    shown_ = false;
  }

  /// "[12/40 done, 2 running, 1 failed] 1:23 elapsed, about 3:10 left".
  static std::string text(std::size_t done, std::size_t total, std::size_t running,
                          std::size_t failed, double elapsed_s) {
    std::string s = "[" + std::to_string(done) + "/" + std::to_string(total) + " done, " +
                    std::to_string(running) + " running, " + std::to_string(failed) +
                    " failed] " + clock_text(elapsed_s) + " elapsed";
    if (done > 0 && done < total) {
      s += ", about " + clock_text(elapsed_s * static_cast<double>(total - done) /
                                   static_cast<double>(done)) + " left";
    }
    return s;
  }

 private:
  static std::string clock_text(double s) {
    const long t = static_cast<long>(s + 0.5);
    char buf[32];
    if (t >= 3600) {
      std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", t / 3600, t / 60 % 60, t % 60);
    } else {
      std::snprintf(buf, sizeof buf, "%ld:%02ld", t / 60, t % 60);
    }
    return buf;
  }

  void draw(std::size_t running) {
    drawn_ = Clock::now();
    if (!live_) return;
    const double elapsed = std::chrono::duration<double>(drawn_ - start_).count();
    std::fprintf(stderr, "\r\033[K%s", text(done_, total_, running, failed_, elapsed).c_str());
    std::fflush(stderr);
    shown_ = true;
  }

  std::size_t total_;
  bool live_;
  Clock::time_point start_;
  Clock::time_point drawn_{};
  std::size_t done_ = 0, failed_ = 0, running_ = 0;
  bool shown_ = false;
};

}  // namespace nav::bench::detail

// SPDX-License-Identifier: MIT
// What the DUTs write to the device lines (a GX3's commands, a polled device's requests, a
// modem's bytes). Realtime: read on the bench's event loop, an async_wait(wait_read) per
// line, and at each readiness the loop reads the line dry into that line's queue, stamped
// with the time of the read (CLOCK_MONOTONIC), then tells the player (on_news). Lockstep: the
// player alone reads them, in take() (the loop would only wake for bytes take() reads anyway,
// and contend with it for the lines). Private to nav_bench.
//
//   loop:   readiness --> read until EAGAIN --> queue[line] += {bytes, rx} --> on_news()
//   player: take() --> read every line dry, hand over the queues (a mutex keeps each read
//           and its append together); take_ready() --> the queues, if the loop is not
//           reading just now (a realtime player never waits for the loop thread)
//
// take() reads the lines itself, so it returns everything the DUT wrote before the call:
// lockstep relies on that (a request the DUT wrote before its solution is taken after the
// solution was read: a dry read of a pty master first pushes what the slave was given), and
// no byte is ever between the kernel and a queue when it runs.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "nav/common/time.hpp"
#include "nav/protocols/parse.hpp"

namespace nav::bench {
class EventLoop;
}

namespace nav::bench::detail {

class HostLines {
 public:
  /// What one read of a line got.
  struct Received {
    std::uint32_t line = 0;
    Timestamp rx{};
    protocols::Bytes bytes;
  };

  /// Who reads the lines as bytes come: the event loop (realtime), or only take() (lockstep).
  enum class Reader { kLoop, kTakeOnly };

  /// fds: per line, the bench's end to read (non-blocking; it stays the caller's), or -1 for
  /// a line not read. on_news: called on the loop after a read that got bytes (kLoop).
  HostLines(EventLoop& loop, const std::vector<int>& fds, std::function<void()> on_news,
            Reader reader = Reader::kLoop);
  /// Stops reading (on the loop); the fds stay open.
  ~HostLines();
  HostLines(const HostLines&) = delete;
  HostLines& operator=(const HostLines&) = delete;

  /// Everything read since the last take(), and what the lines hold now, line by line in
  /// line order, each line's reads in order (lockstep).
  std::vector<Received> take();
  /// What the loop has read so far, without reading the lines and without waiting: empty
  /// while the loop is reading (its news follows). For the realtime player.
  std::vector<Received> take_ready();
  /// kTakeOnly: sleeps until a line has bytes to read, or CLOCK_MONOTONIC time `until`.
  void wait_readable(Timestamp until) const;

 private:
  struct Io;
  EventLoop& loop_;
  std::unique_ptr<Io> io_;  ///< the descriptors and queues, loop thread only
};

}  // namespace nav::bench::detail

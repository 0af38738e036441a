// SPDX-License-Identifier: MIT
// The bench's event loop: one boost::asio::io_context run by one thread, where everything that
// waits for an event rather than a deadline of the wire schedule happens: the DUTs' output
// readers (posix::stream_descriptor reads), the startup and drain waits (steady_timer),
// SIGINT/SIGTERM (signal_set). The realtime writes keep their own thread on absolute
// clock_nanosleep deadlines (pacer.hpp; docs/design-notes.md, "The run engine", has the
// measurement that chose so). Private to nav_bench.
//
//   player thread                         loop thread (io_context::run)
//   ------------                          -----------------------------
//   wait_until(deadline, tick, step) ---> deadline timer, tick timer; step() at each tick and
//        (blocked)                        at each poke() (an output reader's new answer)
//                                    <--- step() true, the deadline, or stop(): done
//   call(fn)                         ---> fn() on the loop thread
//        (blocked)                   <--- returned
//                                         readers: async_read_some -> capture, decode, notify
//                                         signal_set: SIGINT/SIGTERM -> the stop flag
#pragma once

#include <atomic>
#include <functional>
#include <memory>

#include "nav/common/time.hpp"

namespace boost::asio {
class io_context;
}

namespace nav::bench {

class EventLoop {
 public:
  /// Starts the loop's thread; it runs until the destructor.
  EventLoop();
  /// Stops the loop and joins its thread (every reader must have been stopped before).
  ~EventLoop();
  EventLoop(const EventLoop&) = delete;
  EventLoop& operator=(const EventLoop&) = delete;

  boost::asio::io_context& context();
  /// Whether the calling thread is the loop's.
  bool on_loop_thread() const;
  /// Runs fn on the loop thread (at once when called there) and returns when it has.
  void call(const std::function<void()>& fn);
  /// Runs fn on the loop thread later and returns at once (fn must own what it uses).
  void post(std::function<void()> fn);

  /// The calling thread (a player) at SCHED_FIFO 20 and the loop's just below it, when
  /// permitted: what the loop reads is stamped as it arrives (DUT latency, the devices'
  /// requests), not when the scheduler gets round to it on a DUT-loaded machine.
  void try_realtime_priorities();

  /// From now until the destructor, SIGINT and SIGTERM set `flag`, end a wait_until and
  /// call `also` (on the loop thread; to wake a thread that waits elsewhere).
  void stop_on_signals(std::atomic<bool>& flag, std::function<void()> also = {});

  /// Blocks the caller until `step()` returns true, CLOCK_MONOTONIC time `deadline` passes or
  /// a signal of stop_on_signals() arrived; step() runs on the loop thread at once, every
  /// `tick`, at every poke() and a last time at the deadline. One wait at a time.
  void wait_until(Timestamp deadline, Duration tick, std::function<bool()> step);
  /// On the loop thread: runs the current wait's step() now (an event it waits for came).
  void poke();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace nav::bench

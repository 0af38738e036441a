// SPDX-License-Identifier: MIT
// The one write loop of the bench, for a run in realtime or lockstep and for a replay: every
// write of a schedule in order, each after its pacer advanced to it (pacer.hpp), what happens
// around each write left to the owner of the lines (a PlayHost). Private to nav_bench.
//
//   for each group of writes due at one instant (realtime; in lockstep each write alone; in
//   realtime a message's later chunks are due its first chunk's lateness after their
//   scheduled times, as a UART clocks bytes out from the first, and a line's next message
//   first sends what its predecessor still holds):
//     host.go_on(t)          stop on a signal or a DUT that died; progress
//     pacer.advance(t, host) CAN frames due (a CAN trigger's barrier), idle work (reactive
//                            devices), the deadline
//     per write, back to back:
//       host.begin(k)        at a message's first byte: write it, skip it, or stop (also
//                            when a CAN trigger's barrier failed in advance)
//       host.write(...)      the bytes, stamped before and after
//     per write, after the group's last:
//       host.wrote(...)      counts them
//       host.done(k, ...)    the message is whole on the wire: captures, triggers, barrier
//   pacer.finish(host)       the CAN frames due after the last write
#pragma once

#include <atomic>
#include <cstdint>
#include <vector>

#include "nav/bench/wire_schedule.hpp"
#include "run/clock.hpp"
#include "run/pacer.hpp"

namespace nav::bench::detail {

class PlayHost : public IdleWork {
 public:
  enum class Begin { kWrite, kSkip, kStop };
  /// Before the write at scenario time t; false stops the play.
  virtual bool go_on(Duration t) = 0;
  /// After the last write: whether the play still goes on (to send the last CAN frames).
  virtual bool alive() = 0;
  /// At the first byte of message k: write it, skip the whole of it, or stop.
  virtual Begin begin(std::uint32_t k) = 0;
  /// The last write of a skipped message k passed.
  virtual void skipped(std::uint32_t k) = 0;
  /// The size of message k [bytes].
  virtual std::size_t size(std::uint32_t k) const = 0;
  /// Writes bytes [offset, offset + length) of message k; returns how many the line took.
  /// Realtime writes at once (a line never blocks); lockstep waits for room while its DUT
  /// lives.
  virtual std::size_t write(std::uint32_t k, std::uint32_t offset, std::uint32_t length,
                            bool lockstep) = 0;
  /// A write took `written` bytes of chunk c; its first byte left at start.
  virtual void wrote(const Chunk& c, std::size_t written, Timestamp start) = 0;
  /// Message k is whole on the wire, its first byte written at first, its last at end;
  /// false stops the play.
  virtual bool done(std::uint32_t k, Timestamp first, Timestamp end) = 0;
};

/// Plays writes (chunks of messages; whole messages in lockstep) in order. Returns false
/// when it stopped early (a signal, or the host said stop).
bool play_wires(const std::vector<ScheduledMessage>& messages, const std::vector<Chunk>& writes,
                Pacer& pacer, PlayHost& host, const Clock& clock, const std::atomic<bool>& stop);

/// The writes of a schedule for a pacer: realtime every chunk (bytes paced at the line's
/// baud rate), lockstep every whole message at its start.
std::vector<Chunk> writes_for(const WireSchedule& s, const Pacer& pacer,
                              const std::vector<std::size_t>& message_sizes);

}  // namespace nav::bench::detail

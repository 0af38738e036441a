// SPDX-License-Identifier: MIT
// How the wire player keeps time (wire_player.hpp has the loop). Private to nav_bench.
//
//   RealtimePacer: every write at its absolute deadline t0 + (t - origin) / speed on a Clock,
//                  slept to in absolute sleeps of at most max_sleep (a short sleep wakes
//                  closer to its deadline); while it waits it serves the idle work after each
//                  sleep, which ends early when the event loop has news for it (a DUT wrote
//                  to a device line) or an answer falls due; the CAN frames due before a
//                  write are sent at their own deadlines first.
//   LockstepPacer: virtual time: no waiting; before each message the idle work is served at
//                  the scenario time the DUT has reached (the end of the last message, or the
//                  due time of the last CAN frame if later), then the CAN frames and answers
//                  due by the message's start. So serial messages (each written whole at its
//                  first byte's time) and CAN frames (each at its due time, the end of its
//                  EOF; first on a tie) leave in one wire-time order.
#pragma once

#include <atomic>
#include <functional>
#include <optional>

#include "run/clock.hpp"

namespace nav::bench::detail {

/// The realtime pacer's longest single sleep in a run and a replay: measured against sleeping
/// straight to each deadline in docs/design-notes.md ("Which timer paces the writes").
inline constexpr Duration kMaxSleep = std::chrono::milliseconds(1);

/// What is served between writes: a run's reactive devices and CAN bus; nothing in a replay.
class IdleWork {
 public:
  virtual ~IdleWork() = default;
  /// Reads what the DUTs wrote to the device lines and acts on it, at scenario time now.
  virtual void poll(Duration now) { (void)now; }
  /// Writes the answers and deliveries due by scenario time t.
  virtual void send_due(Duration t) { (void)t; }
  /// Writes the CAN frames due by scenario time t, in bus order; each first waits for its due
  /// time with wait (realtime; lockstep only notes the time). A CAN trigger's barrier runs
  /// here; when it fails the host stops the play at its next begin().
  virtual void send_can_due(Duration t, const std::function<void(Duration)>& wait) {
    (void)t;
    (void)wait;
  }
  /// Whether poll() and send_due() must run while the pacer waits.
  virtual bool active() const { return false; }
  /// When active: notified (by the event loop) when poll() has something new.
  virtual Wakeup* news() { return nullptr; }
  /// The next scenario time send_due() has something, if any.
  virtual std::optional<Duration> next_due() const { return std::nullopt; }
};

class Pacer {
 public:
  virtual ~Pacer() = default;
  virtual bool lockstep() const = 0;
  /// Everything before the write at scenario time t: CAN frames due, idle work and (realtime)
  /// the wait for its deadline.
  virtual void advance(Duration t, IdleWork& idle) = 0;
  /// A whole message has been written; it ends on the wire at scenario time end.
  virtual void written(Duration end) = 0;
  /// The scenario time now: what the DUT writes is stamped with it.
  virtual Duration now() const = 0;
  /// How late a write at `at` on the clock was for scenario time t (never below 0; always 0
  /// in lockstep, which has no deadlines).
  virtual Duration late(Duration t, Timestamp at) const = 0;
  /// After the last write: the CAN frames due after it.
  virtual void finish(IdleWork& idle) = 0;
};

class RealtimePacer final : public Pacer {
 public:
  /// stop ends every wait; max_sleep: the longest single sleep; spin: the last part of each
  /// wait is spent reading the clock in a loop instead of sleeping (bench.spin).
  RealtimePacer(Clock& clock, const std::atomic<bool>& stop, Duration max_sleep,
                Duration spin = Duration{0});
  /// Scenario time `origin` is at t0 on the clock; scenario time runs `speed` times faster.
  void set_origin(Timestamp t0, Duration origin = Duration{0}, double speed = 1.0);
  bool lockstep() const override { return false; }
  void advance(Duration t, IdleWork& idle) override;
  void written(Duration) override {}
  Duration now() const override { return clock_.now() - t0_; }
  Duration late(Duration t, Timestamp at) const override;
  void finish(IdleWork& idle) override;
  /// The clock's deadline of scenario time t.
  Timestamp deadline(Duration t) const;
  /// Waits until scenario time t, serving the idle work meanwhile.
  void wait(Duration t, IdleWork& idle);

 private:
  Clock& clock_;
  const std::atomic<bool>& stop_;
  Duration max_sleep_;
  Duration spin_;
  Timestamp t0_{};
  Duration origin_{0};
  double speed_ = 1.0;
};

class LockstepPacer final : public Pacer {
 public:
  bool lockstep() const override { return true; }
  void advance(Duration t, IdleWork& idle) override;
  void written(Duration end) override { now_ = end; }
  Duration now() const override { return now_; }
  Duration late(Duration, Timestamp) const override { return Duration{0}; }
  void finish(IdleWork& idle) override;

 private:
  Duration now_{0};  ///< the end on the wire of the last message (or later CAN frame) written
};

}  // namespace nav::bench::detail

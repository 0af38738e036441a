// SPDX-License-Identifier: MIT
// A period counted on the AHRS timer (3DM-GX3 0xCB timer field, uint32 ticks of 1/62500 s,
// wrapping at 2^32), shared by navd's periodic writers (Keller polls, modem reports). Pure:
// the caller hands it each sample's timer and decides what marks an event, so no wall clock
// enters a schedule and lockstep runs stay reproducible.
//
//   mark(t0)            origin or last event
//   elapsed(t)          (t − t0) mod 2^32 >= period_ticks: a wrap between events is harmless;
//                       a timer that went backwards looks like a long interval (due at once)
#pragma once

#include <cstdint>

namespace nav::dut {

class AhrsPeriod {
 public:
  /// period_s: in (0, 3600] [s]; rounded to whole timer ticks, at least one.
  explicit AhrsPeriod(double period_s);

  /// Records `timer_ticks` as the time of the last event (or the origin) [1/62500 s].
  void mark(std::uint32_t timer_ticks) {
    marked_ = true;
    last_ticks_ = timer_ticks;
  }
  /// True once mark() was called.
  bool started() const { return marked_; }
  /// True when at least one period has passed from the last mark to `timer_ticks`
  /// (wrap-safe); false before the first mark.
  bool elapsed(std::uint32_t timer_ticks) const {
    return marked_ && static_cast<std::uint32_t>(timer_ticks - last_ticks_) >= period_ticks_;
  }
  /// The period in timer ticks [1/62500 s].
  std::uint32_t period_ticks() const { return period_ticks_; }

 private:
  std::uint32_t period_ticks_;
  bool marked_ = false;
  std::uint32_t last_ticks_ = 0;
};

}  // namespace nav::dut

// SPDX-License-Identifier: MIT
#include "run/pacer.hpp"

#include <algorithm>
#include <cmath>

namespace nav::bench::detail {

RealtimePacer::RealtimePacer(Clock& clock, const std::atomic<bool>& stop, Duration max_sleep,
                             Duration spin)
    : clock_(clock), stop_(stop), max_sleep_(max_sleep), spin_(spin) {}

void RealtimePacer::set_origin(Timestamp t0, Duration origin, double speed) {
  t0_ = t0;
  origin_ = origin;
  speed_ = speed;
}

Timestamp RealtimePacer::deadline(Duration t) const {
  if (speed_ == 1.0) return t0_ + (t - origin_);
  return t0_ + Duration{static_cast<Duration::rep>(static_cast<double>((t - origin_).count()) /
                                                   speed_)};
}

Duration RealtimePacer::late(Duration t, Timestamp at) const {
  const Timestamp due = deadline(t);
  if (at <= due) return Duration{0};
  if (speed_ == 1.0) return at - due;
  return Duration{static_cast<Duration::rep>(static_cast<double>((at - due).count()) * speed_)};
}

void RealtimePacer::advance(Duration t, IdleWork& idle) {
  idle.send_can_due(t, [&](Duration due) { wait(due, idle); });
  wait(t, idle);
  idle.poll(now());
}

void RealtimePacer::finish(IdleWork& idle) {
  idle.send_can_due(Duration::max(), [&](Duration due) { wait(due, idle); });
}

void RealtimePacer::wait(Duration t, IdleWork& idle) {
  const Timestamp until = deadline(t);
  const bool active = idle.active();
  Wakeup* news = active ? idle.news() : nullptr;
  for (;;) {
    const Timestamp now = clock_.now();
    if (active) {
      idle.poll(now - t0_);
      idle.send_due(now - t0_);
    }
    if (now >= until || stop_) return;
    if (spin_.count() > 0 && until - now <= spin_) {
      // The last stretch: spin on the clock, no wake-up to wait for.
      while (clock_.now() < until && !stop_) {
      }
      continue;
    }
    // Never longer than max_sleep at a time: a short sleep wakes closer to its deadline
    // (docs/design-notes.md, "Which timer paces the writes").
    Timestamp wake = std::min(until - spin_, now + max_sleep_);
    if (active) {
      if (const auto due = idle.next_due()) wake = std::min(wake, deadline(*due));
    }
    if (news != nullptr) {
      clock_.sleep_until_news(wake, stop_, *news);
    } else {
      clock_.sleep_until(wake, stop_);
    }
  }
}

void LockstepPacer::advance(Duration t, IdleWork& idle) {
  // What the DUT wrote while answering the messages so far happened at now_; CAN frames and
  // answers due before this message's first byte go out first (a frame due at t too). A
  // frame is whole at its due time: the DUT has reached it once it was written.
  idle.poll(now_);
  idle.send_can_due(t, [this](Duration due) { now_ = std::max(now_, due); });
  idle.send_due(t);
}

void LockstepPacer::finish(IdleWork& idle) {
  idle.send_can_due(Duration::max(), [this](Duration due) { now_ = std::max(now_, due); });
}

}  // namespace nav::bench::detail

// SPDX-License-Identifier: MIT
#include "run/run_wires.hpp"

#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include "devices/device_kind.hpp"
#include "nav/bench/capture.hpp"

namespace nav::bench::detail {
namespace {

using namespace std::chrono_literals;

constexpr Duration kWaitSlice = 10ms;      // a wait for the DUT looks at stop and the watchdog
constexpr Duration kProgressPeriod = 10s;  // progress lines on long runs

}  // namespace

RunWires::RunWires(Parts parts)
    : p_(parts), lockstep_(parts.sc->mode == TimeMode::kLockstep), next_progress_(kProgressPeriod) {
  const auto& devices = *p_.devices;
  std::vector<StreamInput> inputs;
  for (std::uint32_t d = 0; d < devices.size(); ++d) {
    inputs.push_back(StreamInput{&p_.streams->serial[d], devices[d].spec.baud});
  }
  schedule_ = build_schedule(inputs, kChunkPeriod);
  tag_serial_triggers();
  tag_can_triggers();
  suppressed_.assign(devices.size(), 0);
  unread_.assign(devices.size(), 0);
}

void RunWires::tag_serial_triggers() {
  // Per device, the tag of each of its messages as its kind names them, counting the LF bytes
  // its line carried before each (a line carries its messages in stream order).
  const auto& devices = *p_.devices;
  std::vector<std::vector<std::optional<std::uint64_t>>> tags(devices.size());
  for (std::uint32_t d = 0; d < devices.size(); ++d) {
    const auto rule = device_kind(devices[d].spec).trigger.of_message;
    if (rule == nullptr || d != p_.watch->vehicle_of(d).trigger_device) continue;
    std::uint64_t lines = 0;
    for (const auto& msg : p_.streams->serial[d]) {
      tags[d].push_back(rule(devices[d].spec, msg, lines));
      lines += static_cast<std::uint64_t>(std::count(msg.bytes.begin(), msg.bytes.end(), 0x0A));
    }
  }
  for (std::uint32_t k = 0; k < schedule_.messages.size(); ++k) {
    const auto& m = schedule_.messages[k];
    // A message a fault destroyed (garbage, truncated) has no tag: the DUT cannot answer it.
    if (tags[m.device].empty() || !tags[m.device][m.index]) continue;
    auto& veh = p_.watch->vehicle_of(m.device);
    trigger_of_message_[k] = {p_.watch->vehicle_index(m.device), veh.triggers.size()};
    veh.triggers.push_back(TriggerRecord{*tags[m.device][m.index], message(m).t_valid});
  }
}

void RunWires::tag_can_triggers() {
  if (p_.can == nullptr) return;
  const auto& frames = p_.can->frames();
  for (std::size_t i = 0; i < frames.size(); ++i) {
    // Only frames the DUT receives can be triggers (not reports, not withheld frames).
    if (frames[i].delivery != CanTxFrame::Delivery::kFrame) continue;
    const std::uint32_t d = frames[i].device;
    const auto& spec = (*p_.devices)[d].spec;
    const auto rule = device_kind(spec).trigger.of_frame;
    auto& veh = p_.watch->vehicle_of(d);
    if (rule == nullptr || d != veh.trigger_device) continue;
    const auto tag = rule(spec, frames[i].f.frame);
    if (!tag) continue;
    trigger_of_frame_[i] = {p_.watch->vehicle_index(d), veh.triggers.size()};
    veh.triggers.push_back(TriggerRecord{*tag, frames[i].f.t_valid});
  }
}

void RunWires::play(Pacer& pacer, const Clock& clock) {
  std::vector<std::size_t> sizes;
  for (const auto& m : schedule_.messages) sizes.push_back(message(m).bytes.size());
  play_wires(schedule_.messages, writes_for(schedule_, pacer, sizes), pacer, *this, clock,
             *p_.stop);
}

TriggerRecord& RunWires::trigger_record(std::uint32_t k) {
  const auto [v, i] = trigger_of_message_.at(k);
  return p_.watch->vehicles()[v].triggers[i];
}

void RunWires::send_can_due(Duration t, const std::function<void(Duration)>& wait) {
  if (failed_) return;
  // In wire-time order with the serial messages (the pacer calls this before the message at
  // t) and, in lockstep, with a polled device's answers due before each frame.
  const auto before = [&](Duration due) {
    wait(due);
    if (lockstep_) {
      restarts_due(due);
      p_.reactive->send_due_answers(due);
    }
  };
  const auto after = [&](std::size_t i, bool sent) { return frame_done(i, sent); };
  if (!p_.can->send_due(t, before, p_.watch->max_watchdog(), *p_.stop, after)) failed_ = true;
}

bool RunWires::frame_done(std::size_t i, bool sent) {
  const auto it = trigger_of_frame_.find(i);
  // A frame the interface did not take never reached the DUT: no trigger.
  if (it == trigger_of_frame_.end() || !sent) return true;
  Vehicle& veh = p_.watch->vehicles()[it->second.first];
  return trigger_sent(veh, veh.triggers[it->second.second], monotonic_now());
}

bool RunWires::trigger_sent(Vehicle& veh, TriggerRecord& tr, Timestamp wire_end) {
  tr.sent = true;
  tr.wire_end = wire_end;
  p_.watch->note_trigger_sent(veh, tr);
  if (p_.watch->off(veh)) return true;  // nobody to answer it
  // Answers naming this tag the DUT owes so far: a tag that wrapped counts again.
  ++veh.answers_expected[tr.tag];
  return !lockstep_ || barrier(veh, tr);
}

void RunWires::progress(Duration scenario_t) {
  if (p_.quiet || p_.sc->duration < 30s || scenario_t < next_progress_) return;
  next_progress_ += kProgressPeriod;
  const Vehicle& veh = p_.watch->vehicles().front();
  if (veh.dut->witness) {  // a timing audit: nobody answers
    std::fprintf(stderr, "[navbench] t=%.0f/%.0f s, timing audit, %zu triggers sent\n",
                 to_seconds(scenario_t), to_seconds(p_.sc->duration), veh.triggers_sent);
    return;
  }
  std::fprintf(stderr, "[navbench] t=%.0f/%.0f s, %zu solutions for %zu triggers\n",
               to_seconds(scenario_t), to_seconds(p_.sc->duration), veh.reader->answer_count(),
               veh.triggers_sent);
}

void RunWires::restarts_due(Duration t) {
  const Duration startup = p_.watch->restarts_due(t);
  if (startup <= Duration{0}) return;
  // As at the first start: the DUT opens its ports before anything more is written, and the
  // wait ends early once it said it is ready (sd_notify; a DUT that does not say waits it all).
  const Timestamp end = monotonic_now() + startup;
  for (Timestamp now = monotonic_now(); now < end && !*p_.stop && p_.watch->ok();
       now = monotonic_now()) {
    if (p_.watch->ready_after_restart()) break;
    p_.reactive->news().wait_until(std::min(end, now + DutWatch::kReadyPoll), *p_.stop);
  }
}

bool RunWires::go_on(Duration t) {
  // Lockstep stops at the barrier of the trigger a failed DUT did not answer; realtime at
  // the next write after the watchdog's verdict.
  p_.watch->at_scenario_time(t);
  if (lockstep_) restarts_due(t);
  if (!lockstep_ && !p_.watch->ok()) return false;
  progress(t);
  return true;
}

PlayHost::Begin RunWires::begin(std::uint32_t k) {
  const ScheduledMessage& m = schedule_.messages[k];
  auto& reactive = *p_.reactive;
  auto& watch = *p_.watch;
  Vehicle& veh = watch.vehicle_of(m.device);
  if (failed_) return Begin::kStop;  // a CAN trigger went unanswered
  if (lockstep_ && !reactive.streaming(m.device) && is_trigger(k) && veh.triggers_sent == 0) {
    // The first trigger waits for the DUT's start command, as long as the watchdog allows;
    // the wait ends when the DUT writes to a device line.
    const Timestamp wait_end = monotonic_now() + veh.dut->watchdog;
    for (;;) {
      reactive.poll_host_lines(m.start);
      if (reactive.streaming(m.device)) break;
      if (*p_.stop || !watch.ok()) return Begin::kStop;
      if (monotonic_now() > wait_end) {
        char t[200];
        std::snprintf(t, sizeof t, "hung: no start command (C4 C1 29 CB) on '%s' within %.1f s",
                      (*p_.devices)[m.device].local_name.c_str(), to_seconds(veh.dut->watchdog));
        watch.set_hung(veh, t);
        return Begin::kStop;
      }
      reactive.wait_for_host_bytes(std::min(wait_end, monotonic_now() + kWaitSlice), *p_.stop);
    }
  }
  // A GX3 not (yet) told to stream sends nothing.
  return reactive.streaming(m.device) ? Begin::kWrite : Begin::kSkip;
}

std::size_t RunWires::write(std::uint32_t k, std::uint32_t offset, std::uint32_t length,
                            bool lockstep) {
  const ScheduledMessage& m = schedule_.messages[k];
  const std::uint8_t* data = message(m).bytes.data() + offset;
  const int fd = (*p_.lines)[m.device].fd();
  if (!lockstep || p_.watch->off(p_.watch->vehicle_of(m.device))) {
    // A serial line never blocks: bytes the DUT does not take are lost, like a UART overrun.
    const ssize_t n = ::write(fd, data, length);
    return n > 0 ? static_cast<std::size_t>(n) : 0;
  }
  std::size_t off = 0;
  const Duration watchdog = p_.watch->vehicle_of(m.device).dut->watchdog;
  const Timestamp give_up = monotonic_now() + watchdog;
  while (off < length) {
    const ssize_t n = ::write(fd, data + off, length - off);
    if (n > 0) {
      off += static_cast<std::size_t>(n);
      unread_[m.device] = 0;  // the DUT makes room again: wait for it as before
      continue;
    }
    // A line the DUT left unread for a whole watchdog period is not waited for again until
    // it makes room (a DUT that does not use the device): its bytes are lost, as a UART's.
    if (unread_[m.device] != 0) break;
    // The DUT has not read its input yet: wait for room, as long as the watchdog allows.
    if (!p_.watch->ok()) break;
    if (monotonic_now() > give_up) {
      unread_[m.device] = 1;
      std::fprintf(stderr,
                   "navbench: warning: device '%s': the DUT read nothing of its line for %.1f s "
                   "(dut.watchdog) at t=%.3f s; its bytes are dropped while the DUT does not "
                   "read it\n",
                   (*p_.devices)[m.device].spec.name.c_str(), to_seconds(watchdog),
                   to_seconds(m.start));
      break;
    }
    pollfd p{fd, POLLOUT, 0};
    ::poll(&p, 1, 10);
  }
  return off;
}

void RunWires::wrote(const Chunk& c, std::size_t written, Timestamp start) {
  const ScheduledMessage& m = schedule_.messages[c.message];
  p_.log->tally.add(m.device, c.t, 0, written, c.length - written);
  if (!lockstep_ && c.offset == 0) {
    p_.log->lateness.push_back(
        LatenessEntry{m.device, m.index, to_seconds(c.t), to_seconds(start - t0_)});
  }
}

bool RunWires::done(std::uint32_t k, Timestamp first, Timestamp end) {
  const ScheduledMessage& m = schedule_.messages[k];
  const auto& bytes = message(m).bytes;
  p_.log->tally.add(m.device, m.start, 1, 0, 0);
  // Realtime stamps the capture when the first byte left; lockstep with the scheduled time.
  write_capture_line(p_.log->tx.get(), lockstep_ ? m.start : first - t0_,
                     (*p_.devices)[m.device].spec.name, bytes);
  Vehicle& veh = p_.watch->vehicle_of(m.device);
  if (!is_trigger(k)) {
    if (!lockstep_) return true;
    // Readable by the DUT before anything later is written, on any line or the CAN bus.
    (*p_.lines)[m.device].flush();
    return p_.watch->off(veh) || wait_for_repeat_answer(veh, m);
  }
  return trigger_sent(veh, trigger_record(k), lockstep_ ? monotonic_now() : end);
}

bool RunWires::barrier(Vehicle& veh, const TriggerRecord& tr) {
  // The next message or frame leaves only once the DUT of its vehicle answered this trigger:
  // one more answer naming its tag than it owed before.
  // A DUT that answers nothing is judged hung by the watchdog; one that answers, but never
  // names this trigger, here, one watchdog period after the trigger left.
  const std::size_t count = veh.answers_expected[tr.tag];
  const Timestamp deadline = tr.wire_end + veh.dut->watchdog;
  while (!veh.reader->wait_for(tr.tag, std::min(deadline, monotonic_now() + kWaitSlice),
                               count)) {
    if (*p_.stop || !p_.watch->ok()) return false;
    if (monotonic_now() >= deadline) {
      char t[200];
      std::snprintf(t, sizeof t,
                    "hung: no solution naming trigger %llu (sent at t=%.3f s) within %.1f s; "
                    "%zu solutions so far",
                    static_cast<unsigned long long>(tr.tag), to_seconds(tr.t_valid),
                    to_seconds(veh.dut->watchdog), veh.reader->answer_count());
      p_.watch->set_hung(veh, t);
      return false;
    }
  }
  return true;
}

bool RunWires::wait_for_repeat_answer(Vehicle& veh, const ScheduledMessage& m) {
  // A copy of a trigger (a `stuck` fault): the DUT may answer it again; wait for that, or one
  // watchdog period for a DUT that does not answer repeats (not a hang). Either way the DUT
  // is idle before the next message, so the run stays reproducible.
  const auto& repeated = message(m).repeat_of_tag;
  if (!repeated || m.device != veh.trigger_device) return true;
  std::size_t* expected = veh.answers_expected.find(*repeated);
  if (expected == nullptr) return true;  // its original was never sent
  const std::size_t count = ++*expected;
  const Timestamp deadline = monotonic_now() + veh.dut->watchdog;
  while (!veh.reader->wait_for(*repeated, std::min(deadline, monotonic_now() + kWaitSlice),
                               count)) {
    if (*p_.stop || !p_.watch->ok()) return false;
    if (monotonic_now() >= deadline) {
      --*expected;  // this DUT does not answer copies: it owes none for this one
      break;
    }
  }
  return true;
}

}  // namespace nav::bench::detail

// SPDX-License-Identifier: MIT
#include "run/run_wires.hpp"

#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include "nav/bench/capture.hpp"

namespace nav::bench::detail {
namespace {

using namespace std::chrono_literals;

constexpr Duration kCheckPeriod = 50ms;    // how often the DUT is watched while sending
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
  for (std::uint32_t k = 0; k < schedule_.messages.size(); ++k) {
    const auto& m = schedule_.messages[k];
    if (!is_trigger(m)) continue;
    auto& veh = p_.watch->vehicle_of(m.device);
    trigger_of_message_[k] = {p_.watch->vehicle_index(m.device), veh.triggers.size()};
    veh.triggers.push_back(TriggerRecord{message(m).trigger_tag.value_or(0), message(m).t_valid});
  }
  suppressed_.assign(devices.size(), 0);
}

void RunWires::play(Pacer& pacer, const Clock& clock) {
  std::vector<std::size_t> sizes;
  for (const auto& m : schedule_.messages) sizes.push_back(message(m).bytes.size());
  play_wires(schedule_.messages, writes_for(schedule_, pacer, sizes), pacer, *this, clock,
             *p_.stop);
}

bool RunWires::is_trigger(const ScheduledMessage& m) const {
  // A message of a vehicle's trigger device that still carries its tag (a fault such as
  // garbage or truncated destroys it: the DUT cannot answer such a message).
  return m.device == p_.watch->vehicle_of(m.device).trigger_device &&
         message(m).trigger_tag.has_value();
}

TriggerRecord& RunWires::trigger_record(std::uint32_t k) {
  const auto [v, i] = trigger_of_message_.at(k);
  return p_.watch->vehicles()[v].triggers[i];
}

void RunWires::send_can_due(Duration t, const std::function<void(Duration)>& wait) {
  p_.can->send_due(t, wait, p_.watch->max_watchdog(), *p_.stop);
}

void RunWires::progress(Duration scenario_t) {
  if (p_.quiet || p_.sc->duration < 30s || scenario_t < next_progress_) return;
  next_progress_ += kProgressPeriod;
  const Vehicle& veh = p_.watch->vehicles().front();
  std::fprintf(stderr, "[navbench] t=%.0f/%.0f s, %zu solutions for %zu triggers\n",
               to_seconds(scenario_t), to_seconds(p_.sc->duration), veh.reader->answer_count(),
               veh.triggers_sent);
}

bool RunWires::go_on(Duration t) {
  if (lockstep_) {
    progress(t);
    return true;  // lockstep watches the DUTs while it waits for them
  }
  if (t >= next_check_) {
    if (!p_.watch->ok(monotonic_now())) return false;
    next_check_ = t + kCheckPeriod;
    progress(t);
  }
  return true;
}

bool RunWires::alive() { return p_.watch->ok(monotonic_now()); }

PlayHost::Begin RunWires::begin(std::uint32_t k) {
  const ScheduledMessage& m = schedule_.messages[k];
  auto& reactive = *p_.reactive;
  auto& watch = *p_.watch;
  Vehicle& veh = watch.vehicle_of(m.device);
  if (lockstep_ && !reactive.streaming(m.device) && is_trigger(m) && veh.triggers_sent == 0) {
    // The first trigger waits for the DUT's start command, as long as the watchdog allows.
    const int fd = (*p_.lines)[m.device].fd();
    const Timestamp wait_end = monotonic_now() + veh.dut->watchdog;
    while (!reactive.streaming(m.device)) {
      if (*p_.stop || !watch.ok(monotonic_now())) return Begin::kStop;
      if (monotonic_now() > wait_end) {
        char t[200];
        std::snprintf(t, sizeof t, "hung: no start command (C4 C1 29 CB) on '%s' within %.1f s",
                      (*p_.devices)[m.device].local_name.c_str(), to_seconds(veh.dut->watchdog));
        watch.set_hung(veh, t);
        return Begin::kStop;
      }
      pollfd p{fd, POLLIN, 0};
      ::poll(&p, 1, 10);
      reactive.poll_host_lines(m.start);
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
  if (!lockstep) {
    // A serial line never blocks: bytes the DUT does not take are lost, like a UART overrun.
    const ssize_t n = ::write(fd, data, length);
    return n > 0 ? static_cast<std::size_t>(n) : 0;
  }
  std::size_t off = 0;
  const Timestamp give_up = monotonic_now() + p_.watch->vehicle_of(m.device).dut->watchdog;
  while (off < length) {
    const ssize_t n = ::write(fd, data + off, length - off);
    if (n > 0) {
      off += static_cast<std::size_t>(n);
      continue;
    }
    // The DUT has not read its input yet: wait for room, as long as the watchdog allows.
    if (!p_.watch->ok(monotonic_now()) || monotonic_now() > give_up) break;
    pollfd p{fd, POLLOUT, 0};
    ::poll(&p, 1, 10);
  }
  return off;
}

void RunWires::wrote(const Chunk& c, std::size_t written, Timestamp start) {
  const ScheduledMessage& m = schedule_.messages[c.message];
  p_.log->tally.add(m.device, c.t, 0, written, c.length - written);
  if (!lockstep_ && c.offset == 0) {
    p_.log->lateness.push_back(reports::LatenessRow{(*p_.devices)[m.device].spec.name,
                                                    to_seconds(c.t), to_seconds(start - t0_)});
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
  if (!is_trigger(m)) {
    if (!lockstep_) return true;
    (*p_.lines)[m.device].flush();  // visible to the DUT before the next trigger
    return wait_for_repeat_answer(veh, m);
  }
  auto& tr = trigger_record(k);
  tr.sent = true;
  tr.wire_end = lockstep_ ? monotonic_now() : end;
  veh.note_trigger_sent(tr);
  return !lockstep_ || barrier(veh, tr);
}

bool RunWires::barrier(Vehicle& veh, const TriggerRecord& tr) {
  // The next message leaves only once the DUT of its vehicle answered this trigger.
  veh.answers_expected[tr.tag] = 1;
  const Timestamp deadline = tr.wire_end + veh.dut->watchdog;
  while (!veh.reader->wait_for(tr.tag, std::min(deadline, monotonic_now() + kCheckPeriod))) {
    if (*p_.stop || !p_.watch->ok(monotonic_now())) return false;
  }
  return true;
}

bool RunWires::wait_for_repeat_answer(Vehicle& veh, const ScheduledMessage& m) {
  // A copy of a trigger (a `stuck` fault): the DUT may answer it again; wait for that, or one
  // watchdog period for a DUT that does not answer repeats (not a hang). Either way the DUT
  // is idle before the next message, so the run stays reproducible.
  const auto& repeated = message(m).repeat_of_tag;
  if (!repeated || m.device != veh.trigger_device) return true;
  const auto expected = veh.answers_expected.find(*repeated);
  if (expected == veh.answers_expected.end()) return true;  // its original was never sent
  const std::size_t count = ++expected->second;
  const Timestamp deadline = monotonic_now() + veh.dut->watchdog;
  while (!veh.reader->wait_for(*repeated, std::min(deadline, monotonic_now() + kCheckPeriod),
                               count)) {
    if (*p_.stop || !p_.watch->ok(monotonic_now())) return false;
    if (monotonic_now() >= deadline) break;
  }
  return true;
}

}  // namespace nav::bench::detail

// SPDX-License-Identifier: MIT
#include "run/wire_player.hpp"

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
constexpr Duration kPollPeriod = 1ms;      // realtime: how often polled lines are read

}  // namespace

WirePlayer::WirePlayer(Parts parts) : p_(parts), next_progress_(kProgressPeriod) {
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

bool WirePlayer::is_trigger(const ScheduledMessage& m) const {
  // A message of a vehicle's trigger device that still carries its tag (a fault such as
  // garbage or truncated destroys it: the DUT cannot answer such a message).
  return m.device == p_.watch->vehicle_of(m.device).trigger_device &&
         message(m).trigger_tag.has_value();
}

TriggerRecord& WirePlayer::trigger_record(std::uint32_t k) {
  const auto [v, i] = trigger_of_message_.at(k);
  return p_.watch->vehicles()[v].triggers[i];
}

void WirePlayer::play() {
  if (p_.sc->mode == TimeMode::kRealtime) play_realtime();
  else play_lockstep();
  // CAN frames due after the last serial message.
  if (p_.watch->ok(monotonic_now()) && !*p_.stop) send_can_due(Duration::max());
}

bool WirePlayer::send_can_due(Duration t) {
  return p_.can->send_due(
      t, [this](Timestamp deadline) { wait_realtime(deadline); }, p_.watch->max_watchdog(),
      *p_.stop);
}

void WirePlayer::wait_realtime(Timestamp deadline) {
  if (!p_.reactive->any_to_read()) {
    p_.clock->sleep_until(deadline, *p_.stop);
    return;
  }
  for (;;) {
    const Timestamp now = p_.clock->now();
    p_.reactive->poll_host_lines(now - t0_);
    p_.reactive->send_due_answers(now - t0_);
    if (now >= deadline || *p_.stop) return;
    Timestamp wake = std::min(deadline, now + kPollPeriod);
    if (const auto due = p_.reactive->next_due()) wake = std::min(wake, t0_ + *due);
    p_.clock->sleep_until(wake, *p_.stop);
  }
}

void WirePlayer::progress(Duration scenario_t) {
  if (p_.quiet || p_.sc->duration < 30s || scenario_t < next_progress_) return;
  next_progress_ += kProgressPeriod;
  const Vehicle& veh = p_.watch->vehicles().front();
  std::fprintf(stderr, "[navbench] t=%.0f/%.0f s, %zu solutions for %zu triggers\n",
               to_seconds(scenario_t), to_seconds(p_.sc->duration), veh.reader->answer_count(),
               veh.triggers_sent);
}

void WirePlayer::play_realtime() {
  auto& lines = *p_.lines;
  auto& log = *p_.log;
  std::vector<Timestamp> first_byte(schedule_.messages.size());
  std::vector<char> suppressed(schedule_.messages.size(), 0);
  Timestamp next_check = t0_;
  for (const Chunk& c : schedule_.chunks) {
    if (*p_.stop) return;
    const Timestamp deadline = t0_ + c.t;
    if (deadline >= next_check) {
      if (!p_.watch->ok(monotonic_now())) return;
      next_check = deadline + kCheckPeriod;
      progress(c.t);
    }
    send_can_due(c.t);  // CAN frames due before this chunk, each at its time
    wait_realtime(deadline);
    p_.reactive->poll_host_lines(p_.clock->now() - t0_);
    const ScheduledMessage& m = schedule_.messages[c.message];
    const auto& bytes = message(m).bytes;
    // A GX3 not (yet) told to stream sends nothing; a message once begun is finished.
    if (c.offset == 0) suppressed[c.message] = p_.reactive->streaming(m.device) ? 0 : 1;
    if (suppressed[c.message] != 0) {
      if (c.offset + c.length == bytes.size()) ++suppressed_[m.device];
      continue;
    }
    const Timestamp start = p_.clock->now();
    const ssize_t n = ::write(lines[m.device].fd(), bytes.data() + c.offset, c.length);
    const Timestamp done = p_.clock->now();
    // A serial line never blocks: bytes the DUT does not take are lost, like a UART overrun.
    const std::size_t written = n > 0 ? static_cast<std::size_t>(n) : 0;
    log.tally.add(m.device, c.t, 0, written, c.length - written);
    const std::string& name = (*p_.devices)[m.device].spec.name;
    if (c.offset == 0) {
      first_byte[c.message] = start;
      log.lateness.push_back(reports::LatenessRow{name, to_seconds(c.t), to_seconds(start - t0_)});
    }
    if (c.offset + c.length == bytes.size()) {
      log.tally.add(m.device, m.start, 1, 0, 0);
      write_capture_line(log.tx.get(), first_byte[c.message] - t0_, name, bytes);
      if (is_trigger(m)) {
        auto& tr = trigger_record(c.message);
        tr.sent = true;
        tr.wire_end = done;
        p_.watch->vehicle_of(m.device).note_trigger_sent(tr);
      }
    }
  }
}

void WirePlayer::play_lockstep() {
  auto& lines = *p_.lines;
  auto& log = *p_.log;
  auto& reactive = *p_.reactive;
  auto& watch = *p_.watch;
  for (std::uint32_t k = 0; k < schedule_.messages.size(); ++k) {
    if (*p_.stop) return;
    const ScheduledMessage& m = schedule_.messages[k];
    const auto& bytes = message(m).bytes;
    const int fd = lines[m.device].fd();
    // What the DUT wrote while answering the messages so far happened at lockstep_now_;
    // answers due before this message's first byte go out first.
    reactive.poll_host_lines(lockstep_now_);
    send_can_due(m.start);  // CAN frames due at or before this message's first byte go first
    reactive.send_due_answers(m.start);
    Vehicle& veh = watch.vehicle_of(m.device);
    if (!reactive.streaming(m.device) && is_trigger(m) && veh.triggers_sent == 0) {
      // The first trigger waits for the DUT's start command, as long as the watchdog allows.
      const Timestamp wait_end = monotonic_now() + veh.dut->watchdog;
      while (!reactive.streaming(m.device)) {
        if (*p_.stop || !watch.ok(monotonic_now())) return;
        if (monotonic_now() > wait_end) {
          char t[200];
          std::snprintf(t, sizeof t,
                        "hung: no start command (C4 C1 29 CB) on '%s' within %.1f s",
                        (*p_.devices)[m.device].local_name.c_str(),
                        to_seconds(veh.dut->watchdog));
          watch.set_hung(veh, t);
          return;
        }
        pollfd p{fd, POLLIN, 0};
        ::poll(&p, 1, 10);
        reactive.poll_host_lines(m.start);
      }
    }
    if (!reactive.streaming(m.device)) {
      ++suppressed_[m.device];
      continue;
    }
    std::size_t off = 0;
    const Timestamp give_up = monotonic_now() + veh.dut->watchdog;
    while (off < bytes.size()) {
      const ssize_t n = ::write(fd, bytes.data() + off, bytes.size() - off);
      if (n > 0) {
        off += static_cast<std::size_t>(n);
        continue;
      }
      // The DUT has not read its input yet: wait for room, as long as the watchdog allows.
      if (!watch.ok(monotonic_now()) || monotonic_now() > give_up) break;
      pollfd p{fd, POLLOUT, 0};
      ::poll(&p, 1, 10);
    }
    log.tally.add(m.device, m.start, 1, off, bytes.size() - off);
    write_capture_line(log.tx.get(), m.start, (*p_.devices)[m.device].spec.name, bytes);
    lockstep_now_ = m.end;
    progress(m.start);
    if (!is_trigger(m)) {
      lines[m.device].flush();  // visible to the DUT before the next trigger
      if (!wait_for_repeat_answer(veh, m)) return;
      continue;
    }
    auto& tr = trigger_record(k);
    tr.sent = true;
    tr.wire_end = monotonic_now();
    veh.note_trigger_sent(tr);
    veh.answers_expected[tr.tag] = 1;
    // Barrier: the next message leaves only once the DUT of its vehicle answered this one.
    const Timestamp deadline = tr.wire_end + veh.dut->watchdog;
    while (!veh.reader->wait_for(tr.tag, std::min(deadline, monotonic_now() + kCheckPeriod))) {
      if (*p_.stop || !watch.ok(monotonic_now())) return;
    }
  }
}

bool WirePlayer::wait_for_repeat_answer(Vehicle& veh, const ScheduledMessage& m) {
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

// SPDX-License-Identifier: MIT
#include "run/wire_player.hpp"

#include <algorithm>
#include <deque>

namespace nav::bench::detail {
namespace {

/// Realtime: the later chunks of a message whose first chunk went out late, each held back by
/// that lateness, one queue per line. A UART clocks a message's bytes out from its first one:
/// so does the bench, and the message keeps its length on the wire instead of arriving squeezed
/// (docs/design-notes.md, "Byte pacing under load"). The next message on a line sends what its
/// predecessor still holds first: a lateness never carries on from one message to the next.
class HeldChunks {
 public:
  explicit HeldChunks(const std::vector<ScheduledMessage>& messages) : messages_(messages) {
    std::uint32_t lines = 0;
    for (const auto& m : messages) lines = std::max(lines, m.device + 1);
    held_.resize(lines);
  }
  /// Holds chunk c until t.
  void hold(const Chunk& c, Duration t) {
    held_[messages_[c.message].device].push_back(Held{t, &c});
    ++count_;
  }
  /// The earliest time a chunk is held until, if it is before `before`.
  [[nodiscard]] Duration next(Duration before) const {
    if (count_ == 0) return before;
    for (const auto& line : held_) {
      if (!line.empty()) before = std::min(before, line.front().t);
    }
    return before;
  }
  /// Appends to out the chunks held until t or earlier.
  void take_due(Duration t, std::vector<const Chunk*>& out) {
    if (count_ == 0) return;
    for (auto& line : held_) {
      while (!line.empty() && line.front().t <= t) take_front(line, out);
    }
  }
  /// Appends to out every chunk held on the line of message k.
  void take_line(std::uint32_t k, std::vector<const Chunk*>& out) {
    if (count_ == 0) return;
    auto& line = held_[messages_[k].device];
    while (!line.empty()) take_front(line, out);
  }
  [[nodiscard]] bool empty() const { return count_ == 0; }

 private:
  struct Held {
    Duration t;
    const Chunk* c;
  };
  void take_front(std::deque<Held>& line, std::vector<const Chunk*>& out) {
    out.push_back(line.front().c);
    line.pop_front();
    --count_;
  }
  const std::vector<ScheduledMessage>& messages_;
  std::vector<std::deque<Held>> held_;
  std::size_t count_ = 0;
};

}  // namespace

bool play_wires(const std::vector<ScheduledMessage>& messages, const std::vector<Chunk>& writes,
                Pacer& pacer, PlayHost& host, const Clock& clock, const std::atomic<bool>& stop) {
  const bool lockstep = pacer.lockstep();
  std::vector<Timestamp> first(messages.size());
  std::vector<Duration> lag(messages.size(), Duration{0});  // how late its first chunk left
  std::vector<char> skip(messages.size(), 0);
  HeldChunks held(messages);
  // The writes of one instant in order, then each stamped, for their bookkeeping after the
  // last of them.
  std::vector<const Chunk*> due;
  struct Done {
    const Chunk* c;
    std::size_t written;
    Timestamp start, end;
  };
  std::vector<Done> group;
  std::size_t i = 0;
  for (;;) {
    // A later chunk of a message begun late waits as long again.
    while (i < writes.size() && writes[i].offset != 0 && lag[writes[i].message].count() > 0) {
      held.hold(writes[i], writes[i].t + lag[writes[i].message]);
      ++i;
    }
    if (i == writes.size() && held.empty()) break;
    const Duration t = held.next(i < writes.size() ? writes[i].t : Duration::max());
    if (stop || !host.go_on(t)) return false;
    pacer.advance(t, host);
    if (stop) return false;
    // Realtime: every write due at this same instant goes out back to back, and what the
    // bench records about them follows the last (a burst of lines no longer waits on the
    // bookkeeping of the lines before it: docs/design-notes.md, "Timing you can prove").
    // Lockstep: one message at a time, its barrier before the next.
    due.clear();
    held.take_due(t, due);
    for (; i < writes.size() && writes[i].t == t; ++i) {
      const Chunk& c = writes[i];
      if (c.offset == 0) {
        held.take_line(c.message, due);  // the line's previous message ends first
      } else if (lag[c.message].count() > 0) {
        held.hold(c, c.t + lag[c.message]);
        continue;
      }
      due.push_back(&c);
      if (lockstep) {
        ++i;
        break;
      }
    }
    group.clear();
    for (const Chunk* cp : due) {
      const Chunk& c = *cp;
      const std::uint32_t k = c.message;
      if (c.offset == 0) {
        const auto b = host.begin(k);
        if (b == PlayHost::Begin::kStop) return false;
        skip[k] = b == PlayHost::Begin::kSkip ? 1 : 0;
      }
      // A message once begun is finished; one skipped at its first byte is skipped whole.
      if (skip[k] != 0) {
        group.push_back(Done{&c, 0, Timestamp{}, Timestamp{}});
        continue;
      }
      const Timestamp start = clock.now();
      const std::size_t written = host.write(k, c.offset, c.length, lockstep);
      group.push_back(Done{&c, written, start, clock.now()});
      if (c.offset == 0) lag[k] = pacer.late(c.t, start);
    }
    for (const Done& d : group) {
      const Chunk& c = *d.c;
      const std::uint32_t k = c.message;
      const bool last = c.offset + c.length == host.size(k);
      if (skip[k] != 0) {
        if (last) host.skipped(k);
        continue;
      }
      if (c.offset == 0) first[k] = d.start;
      host.wrote(c, d.written, d.start);
      if (last) {
        pacer.written(messages[k].end);
        if (!host.done(k, first[k], d.end)) return false;
      }
    }
  }
  if (stop || !host.alive()) return false;
  pacer.finish(host);
  return true;
}

std::vector<Chunk> writes_for(const WireSchedule& s, const Pacer& pacer,
                              const std::vector<std::size_t>& message_sizes) {
  if (!pacer.lockstep()) return s.chunks;
  std::vector<Chunk> out;
  out.reserve(s.messages.size());
  for (std::uint32_t k = 0; k < s.messages.size(); ++k) {
    out.push_back(Chunk{s.messages[k].start, k, 0, static_cast<std::uint32_t>(message_sizes[k])});
  }
  return out;
}

}  // namespace nav::bench::detail

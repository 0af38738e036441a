// SPDX-License-Identifier: MIT
#include "run/wire_player.hpp"

namespace nav::bench::detail {

bool play_wires(const std::vector<ScheduledMessage>& messages, const std::vector<Chunk>& writes,
                Pacer& pacer, PlayHost& host, const Clock& clock, const std::atomic<bool>& stop) {
  std::vector<Timestamp> first(messages.size());
  std::vector<char> skip(messages.size(), 0);
  // The writes of one group, stamped, for their bookkeeping after the last of them.
  struct Done {
    const Chunk* c;
    std::size_t written;
    Timestamp start, end;
  };
  std::vector<Done> group;
  for (std::size_t i = 0; i < writes.size();) {
    const Chunk& head = writes[i];
    if (stop || !host.go_on(head.t)) return false;
    pacer.advance(head.t, host);
    if (stop) return false;
    // Realtime: every write due at this same instant goes out back to back, and what the
    // bench records about them follows the last (a burst of lines no longer waits on the
    // bookkeeping of the lines before it: docs/design-notes.md, "Timing you can prove").
    // Lockstep: one message at a time, its barrier before the next.
    std::size_t end = i + 1;
    if (!pacer.lockstep()) {
      while (end < writes.size() && writes[end].t == head.t) ++end;
    }
    group.clear();
    for (; i < end; ++i) {
      const Chunk& c = writes[i];
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
      const std::size_t written = host.write(k, c.offset, c.length, pacer.lockstep());
      group.push_back(Done{&c, written, start, clock.now()});
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

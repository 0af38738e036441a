// SPDX-License-Identifier: MIT
#include "run/wire_player.hpp"

namespace nav::bench::detail {

bool play_wires(const std::vector<ScheduledMessage>& messages, const std::vector<Chunk>& writes,
                Pacer& pacer, PlayHost& host, const Clock& clock, const std::atomic<bool>& stop) {
  std::vector<Timestamp> first(messages.size());
  std::vector<char> skip(messages.size(), 0);
  for (const Chunk& c : writes) {
    if (stop || !host.go_on(c.t)) return false;
    pacer.advance(c.t, host);
    if (stop) return false;
    const std::uint32_t k = c.message;
    const bool last = c.offset + c.length == host.size(k);
    if (c.offset == 0) {
      const auto b = host.begin(k);
      if (b == PlayHost::Begin::kStop) return false;
      skip[k] = b == PlayHost::Begin::kSkip ? 1 : 0;
    }
    // A message once begun is finished; one skipped at its first byte is skipped whole.
    if (skip[k] != 0) {
      if (last) host.skipped(k);
      continue;
    }
    const Timestamp start = clock.now();
    const std::size_t written = host.write(k, c.offset, c.length, pacer.lockstep());
    const Timestamp end = clock.now();
    if (c.offset == 0) first[k] = start;
    host.wrote(c, written, start);
    if (last) {
      pacer.written(messages[k].end);
      if (!host.done(k, first[k], end)) return false;
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

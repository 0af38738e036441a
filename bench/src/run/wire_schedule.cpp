// SPDX-License-Identifier: MIT
#include "nav/bench/wire_schedule.hpp"

#include <algorithm>

namespace nav::bench {

Duration byte_time(std::size_t n, int baud) {
  // 10 bits per byte (start, 8 data, stop); integer ns, rounded down per call site's sum.
  return Duration{static_cast<std::int64_t>(n) * 10 * 1'000'000'000LL / baud};
}

WireSchedule build_schedule(const std::vector<StreamInput>& streams, Duration chunk_period) {
  WireSchedule s;
  for (std::uint32_t d = 0; d < streams.size(); ++d) {
    Duration line_free{0};
    const auto& msgs = *streams[d].messages;
    for (std::uint32_t i = 0; i < msgs.size(); ++i) {
      ScheduledMessage m{d, i, std::max(msgs[i].t_send, line_free), {}};
      m.end = m.start + byte_time(msgs[i].bytes.size(), streams[d].baud);
      line_free = m.end;
      s.messages.push_back(m);
    }
  }
  std::stable_sort(s.messages.begin(), s.messages.end(),
                   [](const auto& a, const auto& b) { return a.start < b.start; });
  for (std::uint32_t k = 0; k < s.messages.size(); ++k) {
    const auto& m = s.messages[k];
    const int baud = streams[m.device].baud;
    const std::size_t n = (*streams[m.device].messages)[m.index].bytes.size();
    const auto per_chunk = static_cast<std::size_t>(
        std::max<std::int64_t>(1, chunk_period.count() * baud / 10 / 1'000'000'000LL));
    for (std::size_t off = 0; off < n; off += per_chunk) {
      s.chunks.push_back(Chunk{m.start + byte_time(off, baud), k,
                               static_cast<std::uint32_t>(off),
                               static_cast<std::uint32_t>(std::min(per_chunk, n - off))});
    }
  }
  std::stable_sort(s.chunks.begin(), s.chunks.end(),
                   [](const auto& a, const auto& b) { return a.t < b.t; });
  return s;
}

}  // namespace nav::bench

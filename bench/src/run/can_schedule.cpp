// SPDX-License-Identifier: MIT
#include "nav/bench/can_schedule.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <queue>

#include "nav/common/ensure.hpp"

namespace nav::bench {

std::uint32_t can_frame_bits(bool extended, bool remote, std::uint8_t dlc) {
  NAV_ENSURE(dlc <= 8, "a classic CAN frame has at most 8 data bytes");
  const std::uint32_t g = extended ? 54 : 34;
  const std::uint32_t data_bits = remote ? 0 : 8u * dlc;
  return g + data_bits + 13 + (g + data_bits - 1) / 4;  // (C1)
}

std::uint64_t can_arbitration_key(std::uint32_t id, bool extended, bool remote) {
  // Bit 20..0 after the 11-bit base: standard [RTR][IDE=0][18 x 0][0];
  // extended [SRR=1][IDE=1][18-bit extension][RTR].
  if (!extended) {
    NAV_ENSURE(id < (1u << 11), "an 11-bit identifier is below 0x800");
    return (std::uint64_t{id} << 21) | (std::uint64_t{remote} << 20);
  }
  NAV_ENSURE(id < (1u << 29), "a 29-bit identifier is below 0x20000000");
  const std::uint64_t base = id >> 18;
  const std::uint64_t ext = id & 0x3FFFFu;
  return (base << 21) | (1u << 20) | (1u << 19) | (ext << 1) | std::uint64_t{remote};
}

std::vector<CanFrameSlot> schedule_can_bus(const std::vector<CanFrameRequest>& frames,
                                           double bitrate) {
  NAV_ENSURE(std::isfinite(bitrate) && bitrate > 0.0, "the CAN bitrate must be > 0");
  std::vector<std::size_t> by_ready(frames.size());
  std::iota(by_ready.begin(), by_ready.end(), std::size_t{0});
  std::stable_sort(by_ready.begin(), by_ready.end(), [&](std::size_t a, std::size_t b) {
    return frames[a].ready < frames[b].ready;
  });
  // Pending frames: lowest arbitration key first, then earliest ready, then input order.
  struct Pending {
    std::uint64_t key;
    Duration ready;
    std::size_t index;
    bool operator>(const Pending& o) const {
      if (key != o.key) return key > o.key;
      if (ready != o.ready) return ready > o.ready;
      return index > o.index;
    }
  };
  std::priority_queue<Pending, std::vector<Pending>, std::greater<>> pending;
  std::vector<CanFrameSlot> slots(frames.size());
  const double ns_per_bit = 1e9 / bitrate;
  Duration bus_free{std::numeric_limits<Duration::rep>::min()};
  std::size_t next = 0;
  while (next < by_ready.size() || !pending.empty()) {
    if (pending.empty()) bus_free = std::max(bus_free, frames[by_ready[next]].ready);
    // Arbitration at bus_free among every frame ready by then.
    while (next < by_ready.size() && frames[by_ready[next]].ready <= bus_free) {
      const auto& f = frames[by_ready[next]];
      pending.push({can_arbitration_key(f.id, f.extended, f.remote), f.ready, by_ready[next]});
      ++next;
    }
    const Pending winner = pending.top();
    pending.pop();
    const auto& f = frames[winner.index];
    CanFrameSlot& s = slots[winner.index];
    s.bits = can_frame_bits(f.extended, f.remote, f.dlc);
    s.start = bus_free;
    s.end = s.start + Duration{std::llround(s.bits * ns_per_bit)};
    bus_free = s.end;
  }
  return slots;
}

double can_bus_load(const std::vector<CanFrameSlot>& slots, Duration duration) {
  NAV_ENSURE(duration.count() > 0, "the load window must be > 0");
  Duration busy{0};
  for (const auto& s : slots) {
    const Duration a = std::max(s.start, Duration{0});
    const Duration b = std::min(s.end, duration);
    if (b > a) busy += b - a;
  }
  return static_cast<double>(busy.count()) / static_cast<double>(duration.count());
}

}  // namespace nav::bench

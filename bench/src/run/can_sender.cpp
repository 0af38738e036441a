// SPDX-License-Identifier: MIT
#include "run/can_sender.hpp"

#include <poll.h>

#include <algorithm>
#include <string>

#include "nav/protocols/candump_log.hpp"

namespace nav::bench::detail {

CanSender::CanSender(const Scenario& sc, std::vector<CanTxFrame> frames,
                     std::vector<transport::CanSocket> sockets, std::size_t devices, RunLog& log)
    : sc_(sc), frames_(std::move(frames)), sockets_(std::move(sockets)), log_(log) {
  sent_.assign(devices, 0);
  bytes_.assign(devices, 0);
  dropped_.assign(devices, 0);
}

bool CanSender::send_due(Duration t, const std::function<void(Duration)>& wait,
                         Duration queue_wait, const std::atomic<bool>& stop,
                         const std::function<bool(std::size_t, bool)>& after) {
  while (next_ < frames_.size() && frames_[next_].due <= t) {
    if (stop) return false;
    const CanTxFrame& tx = frames_[next_];
    wait(tx.due);
    const bool sent = send(tx, queue_wait);
    if (!after(next_++, sent)) return false;
  }
  return true;
}

bool CanSender::send(const CanTxFrame& tx, Duration queue_wait) {
  // The DUT's controller was bus-off: the frame was on the bus, nobody here received it.
  if (tx.delivery == CanTxFrame::Delivery::kWithheld) return false;
  const bool report = tx.delivery == CanTxFrame::Delivery::kErrorReport;
  transport::CanFrame f;
  f.id = tx.f.frame.id;
  f.extended = tx.f.frame.extended;
  f.rtr = tx.f.frame.rtr;
  f.error = tx.f.frame.error;
  f.dlc = static_cast<std::uint8_t>(tx.f.frame.length());
  std::copy(tx.f.frame.data.begin(), tx.f.frame.data.end(), f.data.begin());
  transport::CanSocket& socket = sockets_[tx.bus];
  const Timestamp start = monotonic_now();
  auto r = socket.send(f);
  if (!r && r.error().code == ErrorCode::kTimeout && sc_.mode == TimeMode::kLockstep) {
    // Lockstep: wait for room in the transmit queue, as long as the watchdog allows.
    const Timestamp give_up = monotonic_now() + queue_wait;
    while (!r && r.error().code == ErrorCode::kTimeout && monotonic_now() < give_up) {
      pollfd p{socket.fd(), POLLOUT, 0};
      ::poll(&p, 1, 10);
      r = socket.send(f);
    }
  }
  const std::uint32_t d = tx.device;
  // A report is the DUT's controller's, not a device's message: not in a device's counts.
  if (!report) {
    if (!r) {
      ++dropped_[d];
      log_.tally.add(d, tx.due, 0, 0, f.dlc);
      return false;
    }
    ++sent_[d];
    bytes_[d] += f.dlc;
    log_.tally.add(d, tx.due, 1, f.dlc, 0);
  } else if (!r) {
    return false;
  }
  // Realtime stamps the capture when the frame was written; lockstep with its due time.
  const bool realtime = sc_.mode == TimeMode::kRealtime;
  const Duration stamp = realtime ? start - t0_ : tx.due;
  if (realtime) log_.can_lateness.push_back({tx.bus, to_seconds(stamp - tx.due)});
  protocols::candump::Record rec;
  const auto ns = std::max<std::int64_t>(0, stamp.count());
  rec.time = protocols::candump::Timestamp{static_cast<std::uint64_t>(ns / 1000000000),
                                           static_cast<std::uint32_t>(ns % 1000000000), 6, 10};
  rec.interface = sc_.can_buses[tx.bus].interface;
  rec.frame = tx.f.frame;
  const std::string line = protocols::candump::format_line(rec) + "\n";
  std::fputs(line.c_str(), log_.can.get());
  return true;
}

}  // namespace nav::bench::detail

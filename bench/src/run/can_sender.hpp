// SPDX-License-Identifier: MIT
// The run's CAN buses: every device's frames, in due order, each written to its bus's socket
// at its due time (realtime) or before the serial message it precedes (lockstep), each
// captured in capture-can.log. Private to nav_bench.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "nav/bench/scenario.hpp"
#include "nav/transport/can_socket.hpp"
#include "run/device_streams.hpp"
#include "run/run_log.hpp"

namespace nav::bench::detail {

class CanSender {
 public:
  /// frames: DeviceStreams::can (due order); sockets: one per bus (Scenario::can_buses).
  CanSender(const Scenario& sc, std::vector<CanTxFrame> frames,
            std::vector<transport::CanSocket> sockets, std::size_t devices, RunLog& log);

  void set_t0(Timestamp t0) { t0_ = t0; }
  /// Sends every frame due at or before scenario time t, in bus order, each after wait(its
  /// due time) (the realtime pacer waits for it; lockstep does not wait) and followed by
  /// after(its index in frames(), whether the interface took it). Lockstep waits for room in
  /// a full transmit queue up to queue_wait. Returns false when stop was set or after() said
  /// stop (a CAN trigger's barrier failed).
  bool send_due(Duration t, const std::function<void(Duration)>& wait, Duration queue_wait,
                const std::atomic<bool>& stop,
                const std::function<bool(std::size_t, bool)>& after);

  const std::vector<CanTxFrame>& frames() const { return frames_; }
  std::size_t frames_sent(std::uint32_t d) const { return sent_[d]; }
  std::size_t bytes_sent(std::uint32_t d) const { return bytes_[d]; }
  std::size_t frames_dropped(std::uint32_t d) const { return dropped_[d]; }

 private:
  /// Writes one frame; false when the interface did not take it (counted as dropped).
  bool send(const CanTxFrame& tx, Duration queue_wait);

  const Scenario& sc_;
  std::vector<CanTxFrame> frames_;
  std::vector<transport::CanSocket> sockets_;
  RunLog& log_;
  Timestamp t0_{};
  std::size_t next_ = 0;
  std::vector<std::size_t> sent_, bytes_, dropped_;  ///< per device
};

}  // namespace nav::bench::detail

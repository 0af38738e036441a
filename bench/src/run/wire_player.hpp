// SPDX-License-Identifier: MIT
// Plays a run's wire schedule to the DUTs: every serial message at its wire time, the CAN
// frames due before it, and, while it waits, the reactive devices. Private to nav_bench.
//
//   realtime: each chunk of a message at its absolute deadline t0 + t on the clock (bytes
//             paced at the line's baud rate), the reactive devices served every kPollPeriod
//             while waiting; a line never blocks (bytes the DUT does not take are lost);
//   lockstep: each whole message as soon as the previous one is done, stamped with its
//             scheduled time; after a trigger nothing more until its DUT answered it (the
//             barrier), after a stuck copy of one until the DUT answered that copy.
#pragma once

#include <atomic>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "lines/bench_line.hpp"
#include "nav/bench/wire_schedule.hpp"
#include "run/can_sender.hpp"
#include "run/clock.hpp"
#include "run/device_streams.hpp"
#include "run/dut_watch.hpp"
#include "run/reactive_devices.hpp"
#include "run/run_log.hpp"

namespace nav::bench::detail {

/// Pacing granularity of serial bytes [ns].
inline constexpr Duration kChunkPeriod = std::chrono::milliseconds(1);

class WirePlayer {
 public:
  struct Parts {
    const Scenario* sc = nullptr;
    const std::vector<RunDevice>* devices = nullptr;
    const DeviceStreams* streams = nullptr;
    std::vector<BenchLine>* lines = nullptr;
    RunLog* log = nullptr;
    ReactiveDevices* reactive = nullptr;
    DutWatch* watch = nullptr;
    CanSender* can = nullptr;
    Clock* clock = nullptr;
    const std::atomic<bool>* stop = nullptr;
    bool quiet = false;  ///< no progress lines
  };
  /// Builds the wire schedule of the serial streams and the vehicles' trigger records.
  explicit WirePlayer(Parts parts);

  void set_t0(Timestamp t0) { t0_ = t0; }
  /// Plays every serial message, then the CAN frames due after the last one.
  void play();
  /// Realtime: waits until deadline, serving the reactive devices meanwhile.
  void wait_realtime(Timestamp deadline);
  /// Per device: messages not written because the device was not streaming.
  const std::vector<std::size_t>& suppressed() const { return suppressed_; }

 private:
  void play_realtime();
  void play_lockstep();
  bool is_trigger(const ScheduledMessage& m) const;
  const emulators::WireMessage& message(const ScheduledMessage& m) const {
    return p_.streams->serial[m.device][m.index];
  }
  TriggerRecord& trigger_record(std::uint32_t k);
  bool wait_for_repeat_answer(Vehicle& veh, const ScheduledMessage& m);
  bool send_can_due(Duration t);
  void progress(Duration scenario_t);

  Parts p_;
  WireSchedule schedule_;
  /// Schedule message index -> (vehicle, index into its triggers).
  std::unordered_map<std::uint32_t, std::pair<std::uint32_t, std::size_t>> trigger_of_message_;
  std::vector<std::size_t> suppressed_;
  Timestamp t0_{};
  /// Lockstep: scenario time the DUT has reached, the end on the wire of the last message
  /// written (the DUT answers at once in lockstep, so its requests are stamped with it).
  Duration lockstep_now_{0};
  Duration next_progress_;
};

}  // namespace nav::bench::detail

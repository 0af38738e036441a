// SPDX-License-Identifier: MIT
// A run's side of the wire player (wire_player.hpp): its serial streams as one schedule, its
// vehicles' triggers, and what happens around each write. Private to nav_bench.
//
//   realtime: the play stops at the watchdog's verdict (dut_watch.hpp); a GX3 not told to stream sends nothing; a
//             line never blocks (bytes the DUT does not take are lost, like a UART overrun);
//             every message's lateness is measured at its first byte;
//   lockstep: the first trigger waits for the DUT's start command; a message waits for room
//             on its line while the DUT lives; after a trigger, serial message or CAN frame,
//             nothing more is written on any line or bus until its DUT answered it (the
//             barrier), after a stuck copy of a trigger until the DUT answered that copy (or
//             one watchdog period); a restart fault is done by the player before the
//             write it precedes, and the restarted DUT is given its startup (dut_watch.hpp).
//   both:     while a DUT is off (a restart fault) nothing waits for it: its triggers and
//             messages are written once, what its lines do not take is lost.
//
// Triggers are named as their device's kind says (DeviceKind::trigger): a serial message by
// its tag given the LF bytes its line carried before it, a CAN frame by its own bytes.
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
#include "run/pacer.hpp"
#include "run/reactive_devices.hpp"
#include "run/run_log.hpp"
#include "run/wire_player.hpp"

namespace nav::bench::detail {

/// Pacing granularity of serial bytes [ns].
inline constexpr Duration kChunkPeriod = std::chrono::milliseconds(1);

class RunWires final : public PlayHost {
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
    const std::atomic<bool>* stop = nullptr;
    bool quiet = false;  ///< no progress lines
  };
  /// Builds the wire schedule of the serial streams and the vehicles' trigger records (serial
  /// messages or CAN frames of each vehicle's trigger device).
  explicit RunWires(Parts parts);

  void set_t0(Timestamp t0) { t0_ = t0; }
  /// Plays the schedule with the pacer of the scenario's mode.
  void play(Pacer& pacer, const Clock& clock);
  /// Per device: messages not written because the device was not streaming.
  const std::vector<std::size_t>& suppressed() const { return suppressed_; }

  // IdleWork: the reactive devices and the CAN bus.
  void poll(Duration now) override { p_.reactive->poll_host_lines(now); }
  void send_due(Duration t) override { p_.reactive->send_due_answers(t); }
  void send_can_due(Duration t, const std::function<void(Duration)>& wait) override;
  bool active() const override { return p_.reactive->any_to_read(); }
  Wakeup* news() override { return &p_.reactive->news(); }
  std::optional<Duration> next_due() const override { return p_.reactive->next_due(); }

  // PlayHost.
  bool go_on(Duration t) override;
  bool alive() override { return !failed_ && p_.watch->ok(); }
  Begin begin(std::uint32_t k) override;
  void skipped(std::uint32_t k) override { ++suppressed_[schedule_.messages[k].device]; }
  std::size_t size(std::uint32_t k) const override {
    return message(schedule_.messages[k]).bytes.size();
  }
  std::size_t write(std::uint32_t k, std::uint32_t offset, std::uint32_t length,
                    bool lockstep) override;
  void wrote(const Chunk& c, std::size_t written, Timestamp start) override;
  bool done(std::uint32_t k, Timestamp first, Timestamp end) override;

 private:
  bool is_trigger(std::uint32_t k) const { return trigger_of_message_.count(k) != 0; }
  /// Message k's trigger tag: set for the messages of a trigger device that its kind names.
  void tag_serial_triggers();
  void tag_can_triggers();
  /// After CAN frame i was written: a trigger is recorded and, in lockstep, waited for.
  bool frame_done(std::size_t i, bool sent);
  /// A trigger has left: it is recorded and, in lockstep, waited for.
  bool trigger_sent(Vehicle& veh, TriggerRecord& tr, Timestamp wire_end);
  const emulators::WireMessage& message(const ScheduledMessage& m) const {
    return p_.streams->serial[m.device][m.index];
  }
  TriggerRecord& trigger_record(std::uint32_t k);
  bool barrier(Vehicle& veh, const TriggerRecord& tr);
  bool wait_for_repeat_answer(Vehicle& veh, const ScheduledMessage& m);
  void progress(Duration scenario_t);
  /// Lockstep: the restart faults due by scenario time t, and the startup of a DUT started.
  void restarts_due(Duration t);

  Parts p_;
  bool lockstep_;
  WireSchedule schedule_;
  /// Schedule message index -> (vehicle, index into its triggers).
  std::unordered_map<std::uint32_t, std::pair<std::uint32_t, std::size_t>> trigger_of_message_;
  /// CAN frame index (CanSender::frames()) -> (vehicle, index into its triggers).
  std::unordered_map<std::size_t, std::pair<std::uint32_t, std::size_t>> trigger_of_frame_;
  bool failed_ = false;  ///< a CAN trigger's barrier failed: the play stops
  std::vector<std::size_t> suppressed_;
  /// Lockstep, per device: its line was left unread for a watchdog period (write()).
  std::vector<char> unread_;
  Timestamp t0_{};
  Duration next_progress_;
};

}  // namespace nav::bench::detail

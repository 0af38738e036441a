// SPDX-License-Identifier: MIT
// The vehicles of a run and their DUTs: each DUT started as a child process on its lines, its
// output read on the bench's event loop, watched for a crash or a hang, drained at the end
// and stopped. Private to nav_bench.
//
//   start(): argv with {port:NAME} -> the lines' paths; dut.log / dut-<peer>.log; readers;
//            the watchdog: a steady_timer on the event loop, every 10 ms, that finds a DUT
//            crashed (exited) or hung (a trigger unanswered for longer than its watchdog),
//            then wakes every wait of the player (news, the loop's wait) at once
//   ok():    the watchdog's verdict so far; the player looks at its own points (lockstep
//            stops at the barrier of the trigger the DUT did not answer)
//   restarts_due(t): the restart faults due by scenario time t (dut.faults), on the loop: the
//            DUT's group killed with SIGKILL at `from`, the unfinished line it left dropped;
//            at `to` what its lines hold unread discarded and its command started again;
//            the watchdog does not wait for triggers sent before the new DUT's startup ended
//   drain(): after the last message, on the event loop: done at the answer to each DUT's last
//            trigger (the readers poke it), or at the deadline timer one watchdog on, or at
//            a crash or a signal (looked at every 5 ms)
#pragma once

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

#include "lines/bench_line.hpp"
#include "nav/bench/dut_process.hpp"
#include "nav/bench/judge.hpp"
#include "nav/bench/output_reader.hpp"
#include "nav/bench/scenario.hpp"
#include "run/device_streams.hpp"
#include "run/event_loop.hpp"
#include "run/ready_notice.hpp"
#include "run/recent_counts.hpp"
#include "run/dut_log_limit.hpp"
#include "run/run_log.hpp"
#include "run/wakeup.hpp"

namespace nav::bench::detail {

/// One vehicle: the primary (index 0) or a peer (1 + its index in the scenario's peers).
struct Vehicle {
  std::string name;
  const emulators::Truth* truth = nullptr;
  const DutSpec* dut = nullptr;
  std::uint32_t output_line = 0;     ///< index into the run's lines
  std::uint32_t trigger_device = 0;  ///< index into the run's devices
  std::vector<std::string> argv;     ///< as started
  std::unique_ptr<DutProcess> proc;
  std::unique_ptr<OutputReader> reader;
  std::unique_ptr<CaptureFile> output_capture;  ///< peers: capture-rx-<name>.log
  std::unique_ptr<DutLogLimit> log_limit;        ///< on its dut.log (dut-<name>.log)
  /// Where its DUT may say it is ready (NOTIFY_SOCKET); null: none could be made, or a
  /// witness stands in the DUT's place.
  std::unique_ptr<ReadyNotice> ready;
  std::vector<TriggerRecord> triggers;  ///< every trigger of the schedule, in order
  std::size_t triggers_sent = 0;
  /// Of the triggers sent, in send order: one slot per trigger, set by the player, the first
  /// DutWatch::sent_[v] of them read by the watchdog.
  std::vector<Timestamp> sent_wire_ends;
  std::uint64_t last_trigger_tag = 0;
  /// Lockstep: answers naming each trigger tag the DUT may give so far (1 per trigger, one
  /// more per copy a `stuck` fault sent).
  RecentCounts answers_expected;
  /// Restart faults (dut->restarts): the next one due and what each did.
  std::size_t next_restart = 0;
  std::vector<RestartRecord> restarts;
  /// Triggers sent before this are not waited for: the DUT was off, or starting again.
  Timestamp watch_from{};
  bool failed = false;  ///< crashed or hung (watched)
  bool never_commanded = false;  ///< alive, but it never sent its trigger device's start command
  std::string status;   ///< (watched)
};

/// A run of witnesses (DutSpec::witness) waits this long after its last write, for the bytes
/// still on their way to reach them.
inline constexpr Duration kWitnessDrain = std::chrono::milliseconds(200);

class DutWatch {
 public:
  /// stop: set by SIGINT/SIGTERM; every wait ends when it is. loop: where the output readers
  /// read, the watchdog runs and the drain waits. news: woken when a DUT failed.
  DutWatch(const Scenario& sc, const std::vector<RunDevice>& devices,
           const VehicleTruths& truths, const std::atomic<bool>& stop, EventLoop& loop,
           Wakeup& news);
  ~DutWatch();

  std::vector<Vehicle>& vehicles() { return vehicles_; }
  const std::vector<Vehicle>& vehicles() const { return vehicles_; }
  Vehicle& vehicle_of(std::uint32_t device) { return vehicles_[devices_[device].vehicle]; }
  std::uint32_t vehicle_index(std::uint32_t device) const { return devices_[device].vehicle; }

  /// Starts every vehicle's DUT with its {port:NAME} replaced by the lines' paths, its
  /// stdout and stderr to dir/dut.log (a peer's: dut-<name>.log), and a reader of its output
  /// line capturing to the primary's capture-rx.log (a peer's: capture-rx-<name>.log), times
  /// from t0. Each DUT log and peer capture holds at most log_limit bytes (0: no limit).
  /// Throws (naming a peer) when a DUT cannot be started.
  void start(const std::vector<BenchLine>& lines, const std::filesystem::path& dir, Timestamp t0,
             RunLog& log, std::uint64_t log_limit);

  /// Whether every DUT has said it is ready (ReadyNotice; reads what they sent). On the loop.
  bool all_ready();
  /// How often a lockstep startup or restart looks whether every DUT said it is ready.
  static constexpr Duration kReadyPoll = std::chrono::milliseconds(2);
  /// From the player, after restarts_due() started a DUT again: whether every DUT has said it
  /// is ready (the restarted ones since their restart). Goes to the loop.
  bool ready_after_restart();
  /// Moves the run's t0 (before anything was sent): a lockstep run starts once every DUT is
  /// ready, before the end of its dut.startup.
  void set_t0(Timestamp t0);

  /// At scenario time 0: on the loop (the caller goes on), a warning on stderr for each pty
  /// a DUT was given but has not opened yet. What the bench writes to it before the DUT
  /// opens it is lost (LibSerial flushes a port it opens; docs/dut-contract.md §7).
  void warn_of_ports_not_opened(const std::vector<BenchLine>& lines);

  /// False once a DUT crashed or hung (its vehicle's status says how).
  bool ok() const { return !failed_; }
  bool crashed() const { return crashed_; }
  bool hung() const { return hung_; }
  /// Records that a vehicle's DUT hung for a reason only the player sees.
  void set_hung(Vehicle& v, std::string status);
  /// The player has reached scenario time t (what a lockstep verdict names; realtime names
  /// the clock's).
  void at_scenario_time(Duration t) { scenario_ns_.store(t.count(), std::memory_order_relaxed); }

  /// Powers off and starts again the DUTs whose restart faults are due by scenario time t (on
  /// the loop; realtime: the watchdog calls it, lockstep: the player, before each write).
  /// Returns the longest startup of a DUT it started again (0: none).
  Duration restarts_due(Duration t);
  /// Whether vehicle v's DUT is off (between a restart fault's power-off and its restart).
  bool off(const Vehicle& v) const;

  /// A trigger of vehicle v has left (its wire_end set): the watchdog waits for its answer.
  void note_trigger_sent(Vehicle& v, const TriggerRecord& tr);

  /// After the last message: waits until each DUT answered its last trigger, at most one
  /// watchdog period; the rest count as unanswered.
  void drain();
  /// The longest watchdog of any vehicle.
  Duration max_watchdog() const;
  /// Stops the watchdog, sets the final status of the DUTs still alive, then stops every
  /// DUT and reader.
  void finish(const std::vector<std::size_t>& suppressed);
  /// The scenario time a signal stopped the run at (set by finish()), or none.
  std::optional<Duration> stopped_at() const { return stopped_at_; }
  /// The primary's DUT status, with any peer that failed.
  std::string primary_status() const;
  bool primary_alive() const;

 private:
  struct Watchdog;
  /// On the loop: the watchdog's next look, kWatchPeriod from now.
  void arm_watchdog();
  /// Stops the watchdog (from any thread but the loop's).
  void stop_watchdog();
  /// On the loop, under mutex_: looks at every DUT; false (and the verdict set) once one
  /// crashed or hung.
  bool look(Timestamp now);
  /// The scenario time of a verdict made at now: lockstep, the player's; realtime, the clock's.
  Duration scenario_time(Timestamp now) const;
  /// sent: how many of its triggers have been sent.
  bool vehicle_ok(Vehicle& veh, std::size_t sent, Timestamp now);
  /// Under mutex_: the verdict is in; every wait of the player ends.
  void failed();
  /// On the loop, under mutex_: restarts_due().
  Duration apply_restarts(Duration t);
  void power_off(std::uint32_t v, const DutRestart& r);
  /// False (and the vehicle failed) when the command could not be started again.
  bool power_on(std::uint32_t v, const DutRestart& r);
  /// The vehicle's DUT, just started (or started again); in lockstep at kLockstepDutPriority.
  void adopt(Vehicle& veh, DutProcess dut);
  std::vector<std::string> argv_of(std::uint32_t v, const std::vector<BenchLine>& lines,
                                   const std::filesystem::path& dir) const;
  /// `navbench witness` in vehicle v's DUT's place (DutSpec::witness).
  std::vector<std::string> witness_argv(std::uint32_t v, const std::vector<BenchLine>& lines,
                                        const std::filesystem::path& dir) const;

  const Scenario& sc_;
  const std::vector<RunDevice>& devices_;
  const std::atomic<bool>& stop_;
  EventLoop& loop_;
  Wakeup& news_;
  std::vector<Vehicle> vehicles_;
  std::optional<Duration> stopped_at_;
  Timestamp t0_{};
  const std::vector<BenchLine>* lines_ = nullptr;  ///< set by start()
  /// Per vehicle: its DUT is off (a restart fault), read by the player without the lock.
  std::unique_ptr<std::atomic<bool>[]> off_;
  /// The scenario time of the next restart fault's power-off or restart of any vehicle
  /// (Duration::max() when none is left): restarts_due() before it does not go to the loop.
  std::atomic<Duration::rep> next_restart_{Duration::max().count()};
  /// Under mutex_: next_restart_ from every vehicle's next restart fault.
  void update_next_restart();
  /// Per vehicle: how many of its sent_wire_ends are set (release by the player, acquire by
  /// the watchdog: no lock per trigger).
  std::unique_ptr<std::atomic<std::size_t>[]> sent_;
  /// Guards each vehicle's failed and status and the verdict (the watchdog's and set_hung's).
  mutable std::mutex mutex_;
  std::atomic<bool> failed_{false};
  std::atomic<Duration::rep> scenario_ns_{0};  ///< at_scenario_time()
  std::atomic<bool> crashed_{false}, hung_{false};
  std::unique_ptr<Watchdog> watchdog_;
  bool primary_alive_ = false;  ///< set by finish()
};

}  // namespace nav::bench::detail

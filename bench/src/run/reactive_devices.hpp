// SPDX-License-Identifier: MIT
// The devices that answer the DUT: a MicroStrain GX3 that streams only once told to (and
// acknowledges the command), a polled device (the Keller) that answers requests after its
// response time, and acoustic modems, whose bytes the acoustic channel carries to the other
// modems. Each of their lines is read for what the DUT wrote; what they send is queued by
// scenario time and written when due. Private to nav_bench.
//
//   DUT --request/command/modem bytes--> poll_host_lines(t) --> Keller emulator, channel, GX3
//   send_due_answers(t) <-- queued answers and channel deliveries due by t --> DUT's lines
#pragma once

#include <atomic>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "lines/bench_line.hpp"
#include "nav/bench/scenario.hpp"
#include "nav/emulators/acoustic_modem.hpp"
#include "nav/emulators/keller_emulator.hpp"
#include "nav/protocols/microstrain_gx3.hpp"
#include "run/device_streams.hpp"
#include "run/event_loop.hpp"
#include "run/host_lines.hpp"
#include "run/run_log.hpp"
#include "run/wakeup.hpp"

namespace nav::bench::detail {

class ReactiveDevices {
 public:
  /// lines: one per device (devices order); log: captures, tally and lateness it adds to.
  /// The devices' truths (RunDevice::truth) place a Keller's sensor and each modem. The
  /// lines are read on loop, which notifies news when the DUT wrote to one (realtime).
  ReactiveDevices(const Scenario& sc, const std::vector<RunDevice>& devices,
                  std::vector<BenchLine>& lines, RunLog& log, EventLoop& loop, Wakeup& news);
  ~ReactiveDevices();

  /// Scenario time 0 on CLOCK_MONOTONIC (realtime captures and lateness are stamped from it).
  void set_t0(Timestamp t0) { t0_ = t0; }

  /// Whether any line must be read while the bench waits (a polled device or a modem).
  bool any_to_read() const { return any_to_read_; }
  /// Notified when the DUT wrote to a GX3's, polled device's or modem's line (realtime: in
  /// lockstep the lines are read only by poll_host_lines()).
  Wakeup& news() { return news_; }
  /// Sleeps until the DUT wrote to one of those lines, CLOCK_MONOTONIC time `until`, or
  /// (realtime) stop.
  void wait_for_host_bytes(Timestamp until, const std::atomic<bool>& stop);
  /// Whether device d sends its stream: a GX3 only once it got the set-continuous command
  /// (unless `continuous`), every other device always.
  bool streaming(std::uint32_t d) const { return streaming_[d] != 0; }

  /// Takes what the DUT wrote to each GX3's, polled device's and modem's line: acts on a
  /// GX3's commands, queues a polled device's answers, hands a modem's bytes to the channel.
  /// scenario_t: lockstep, the scenario time of what was taken (device timer, request time,
  /// captures); realtime stamps each read with its own time instead.
  void poll_host_lines(Duration scenario_t);
  /// Writes every queued answer and channel delivery due at or before scenario_t.
  void send_due_answers(Duration scenario_t);
  /// The earliest time an answer or a channel event is due, if any.
  std::optional<Duration> next_due() const;

  /// For the report: a polled device's answers (their times; kept only when it has
  /// measurement faults), its fault records, the channel's links.
  const std::vector<emulators::WireMessage>& answered(std::uint32_t d) const {
    return answered_[d];
  }
  bool polled(std::uint32_t d) const { return polled_[d] != nullptr; }
  std::vector<emulators::FaultRecord> polled_fault_records(std::uint32_t d) const {
    return polled_[d]->fault_records();
  }
  /// Every directed link between two modems, with the modems' device indices.
  struct Link {
    std::uint32_t from = 0, to = 0;
    emulators::LinkStats stats;
  };
  std::vector<Link> links() const;

 private:
  struct Answer {
    std::uint32_t device = 0;
    emulators::WireMessage message;
  };
  void queue_answer(std::uint32_t d, emulators::WireMessage m);
  void handle_host_command(std::uint32_t d, const protocols::gx3::HostCommand& c,
                           Duration scenario_t);
  /// Queues the channel's deliveries due by scenario_t as answers of the receiving modems.
  void poll_channel(Duration scenario_t);
  /// Writes bytes to device d's line at once, waiting briefly for room; counts them.
  void write_now(std::uint32_t d, const protocols::Bytes& bytes, Duration scenario_t);
  /// Acts on bytes the DUT wrote to device d's line, at scenario time t.
  void on_host_bytes(std::uint32_t d, std::span<const std::uint8_t> got, Duration t);

  const Scenario& sc_;
  const std::vector<RunDevice>& devices_;
  std::vector<BenchLine>& lines_;
  RunLog& log_;
  Timestamp t0_{};
  Wakeup& news_;
  std::unique_ptr<HostLines> host_lines_;  ///< null: no line to read
  bool any_to_read_ = false;
  std::vector<char> streaming_;                 ///< per device
  std::vector<protocols::Bytes> host_rx_;       ///< per GX3: command bytes not parsed yet
  std::vector<std::unique_ptr<emulators::KellerEmulator>> polled_;  ///< null: not polled
  std::vector<std::vector<emulators::WireMessage>> answered_;       ///< per device, in order
  std::deque<Answer> answers_;  ///< sorted by message.t_send (stable: equal times in order)
  std::vector<int> modem_node_;            ///< per device: its node in channel_, or -1
  std::vector<std::uint32_t> node_device_; ///< per node: its device
  std::unique_ptr<emulators::AcousticChannel> channel_;
  /// Latest time handed to the channel (on_bytes or poll) and latest poll: its times never
  /// go backwards and bytes are never stamped before a poll (acoustic_modem.hpp).
  Duration channel_time_{0}, channel_polled_{0};
};

}  // namespace nav::bench::detail

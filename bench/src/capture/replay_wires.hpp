// SPDX-License-Identifier: MIT
// `navbench replay`'s lines and its side of the wire player (run/wire_player.hpp): each
// capture line written whole at its time, a CAN line sent as its frame, the DUT (if any)
// watched every kCheckPeriod of the capture. Private to nav_bench.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "lines/bench_line.hpp"
#include "nav/bench/capture.hpp"
#include "nav/transport/can_socket.hpp"
#include "run/pacer.hpp"
#include "run/wire_player.hpp"

namespace nav::bench::detail {

/// How often a replay's DUT is watched while playing [ns].
inline constexpr Duration kReplayCheckPeriod = std::chrono::milliseconds(50);

/// One replayed line: the bench's end of it and what went through it.
struct Port {
  std::string name;
  BenchLine line;
  std::size_t bytes = 0, dropped = 0, lines = 0;
  std::string send_error{};  // the first CAN send failure other than a full queue
};

/// Sends one frame; a full transmit queue is waited for briefly, then the frame is dropped.
void send_frame(Port& p, const transport::CanFrame& f);

/// The replay's side of the wire player: each capture line written whole at its time (a CAN
/// line sent as its frame), the DUT (if any) watched every kReplayCheckPeriod of the capture.
class ReplayWires final : public PlayHost {
 public:
  ReplayWires(const std::vector<CaptureLine>& lines, const std::vector<transport::CanFrame>& frames,
              std::vector<Port>& ports, const std::vector<std::uint32_t>& port_of,
              const RealtimePacer& pacer, std::function<bool()> dut_alive, bool with_dut)
      : lines_(lines), frames_(frames), ports_(ports), port_of_(port_of), pacer_(pacer),
        dut_alive_(std::move(dut_alive)), with_dut_(with_dut) {}

  bool go_on(Duration t) override {
    const Timestamp deadline = pacer_.deadline(t);
    if (with_dut_ && deadline >= next_check_) {
      if (!dut_alive_()) return false;
      next_check_ = deadline + kReplayCheckPeriod;
    }
    return true;
  }
  bool alive() override { return true; }
  Begin begin(std::uint32_t) override { return Begin::kWrite; }
  void skipped(std::uint32_t) override {}
  std::size_t size(std::uint32_t k) const override { return lines_[k].bytes.size(); }
  std::size_t write(std::uint32_t k, std::uint32_t, std::uint32_t, bool) override {
    Port& p = ports_[port_of_[k]];
    if (p.line.can()) {
      send_frame(p, frames_[k]);
      return 0;
    }
    const auto& bytes = lines_[k].bytes;
    const ssize_t n = bytes.empty() ? 0 : ::write(p.line.fd(), bytes.data(), bytes.size());
    // A serial line never blocks: bytes the reader does not take are lost.
    const std::size_t written = n > 0 ? static_cast<std::size_t>(n) : 0;
    p.bytes += written;
    p.dropped += bytes.size() - written;
    return written;
  }
  void wrote(const Chunk& c, std::size_t, Timestamp start) override {
    ++ports_[port_of_[c.message]].lines;
    ++played_;
    lateness_.push_back(to_seconds(start - pacer_.deadline(c.t)));
  }
  bool done(std::uint32_t, Timestamp, Timestamp) override { return true; }

  const std::vector<double>& lateness() const { return lateness_; }
  std::size_t played() const { return played_; }

 private:
  const std::vector<CaptureLine>& lines_;
  const std::vector<transport::CanFrame>& frames_;
  std::vector<Port>& ports_;
  const std::vector<std::uint32_t>& port_of_;
  const RealtimePacer& pacer_;
  std::function<bool()> dut_alive_;
  bool with_dut_;
  Timestamp next_check_{};
  std::vector<double> lateness_;
  std::size_t played_ = 0;
};

}  // namespace nav::bench::detail

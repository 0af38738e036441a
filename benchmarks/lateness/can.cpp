// SPDX-License-Identifier: MIT
// `lateness_benchmark can` (inside scripts/with-vcan): one CAN trace (a lockstep run's
// capture-can.log) played onto vcan0 by canplayer (can-utils) and by `navbench replay`,
// alternately; a candump listener's kernel receive times (SO_TIMESTAMP) against each frame's
// scheduled time measure both alike.
#include <cstdio>
#include <fstream>
#include <string>
#include <thread>

#include "benchmark.hpp"
#include "child.hpp"
#include "lateness_stats.hpp"
#include "nav/protocols/candump_log.hpp"

namespace nav::benchmarks {
namespace {

namespace cd = protocols::candump;

/// The times [s] of the frames of a candump log, in order; throws on a line that is not one.
std::vector<double> frame_times(const std::filesystem::path& p, std::size_t* interfaces = nullptr) {
  std::ifstream in(p);
  std::vector<double> t;
  std::string line, first_iface;
  std::size_t n_iface = 0;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const auto r = cd::parse_line(line);
    if (!r.record || !r.record->time) {
      throw std::runtime_error(p.string() + ": not a candump log line: " + line.substr(0, 60));
    }
    if (r.record->interface != first_iface) {
      if (first_iface.empty()) first_iface = r.record->interface;
      ++n_iface;
    }
    t.push_back(r.record->time->to_seconds());
  }
  if (interfaces) *interfaces = n_iface;
  return t;
}

/// Plays the trace with argv while candump listens on vcan0; the frames' lateness.
Stats play(const Common& c, const std::vector<double>& scheduled,
           const std::vector<std::string>& argv, const std::string& name) {
  const auto heard = c.out / (name + ".log");
  const Child listener = start({"candump", "-L", "-n", std::to_string(scheduled.size()), "-T",
                                "10000", "vcan0"},
                               heard, c.out / (name + "-candump.err"));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // candump's socket is bound
  run(argv, c.out / name);
  if (wait(listener).exit_code != 0) throw std::runtime_error("candump failed: " + name);
  const auto rx = frame_times(heard);
  if (rx.size() != scheduled.size()) {
    throw std::runtime_error(name + ": candump heard " + std::to_string(rx.size()) + " of " +
                             std::to_string(scheduled.size()) + " frames");
  }
  return reports::summarize(aligned_lateness(scheduled, rx));
}

void print(const char* what, const Stats& s) {
  std::printf("  %-16s p50 %8.1f  p99 %8.1f  max %9.1f us  (%zu)\n", what, s.p50_s * 1e6,
              s.p99_s * 1e6, s.max_s * 1e6, s.count);
}

}  // namespace

int run_can(const Common& c, const std::string& scenario) {
  std::printf("trace: %s in lockstep ...\n", scenario.c_str());
  std::fflush(stdout);
  const auto trace_dir = c.out / "can-trace";
  run({c.navbench, "run", scenario, "--mode", "lockstep", "--quiet", "--out", trace_dir.string()},
      c.out / "can-trace", {0, 1});
  const auto trace = trace_dir / "capture-can.log";
  std::size_t interfaces = 0;
  const std::vector<double> scheduled = frame_times(trace, &interfaces);
  if (scheduled.empty() || interfaces != 1) {
    throw std::runtime_error(trace.string() + ": expected frames on one interface (vcan0)");
  }
  std::printf("%zu frames, %.1f s\n", scheduled.size(), scheduled.back() - scheduled.front());
  std::vector<Stats> player, nb;
  for (int i = 1; i <= c.pairs; ++i) {
    const auto n = std::to_string(i);
    player.push_back(play(c, scheduled, {"canplayer", "-I", trace.string()}, "can-canplayer-" + n));
    nb.push_back(play(c, scheduled, {c.navbench, "replay", trace.string()}, "can-navbench-" + n));
    std::printf("pair %d, candump kernel time - scheduled [us]:\n", i);
    print("canplayer", player.back());
    print("navbench replay", nb.back());
    std::fflush(stdout);
  }
  const PairRatio m = median_ratio(pair_ratios(nb, player));
  std::printf("median over %d pairs of canplayer / navbench:  p50 %.2f  p99 %.2f  max %.2f\n",
              c.pairs, m.p50, m.p99, m.max);
  return 0;
}

}  // namespace nav::benchmarks

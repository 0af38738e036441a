// SPDX-License-Identifier: MIT
// `lateness_benchmark serial`: one serial trace (a lockstep run's capture-tx.log) played by
// `navbench replay` and by a plain sleep-paced writer (what a hand-rolled replay script does:
// sleep the gap to the next message, write it whole), alternately; `navbench witness` on the
// far side of the ptys stamps what arrives, for both alike.
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "benchmark.hpp"
#include "child.hpp"
#include "judge/witness_timing.hpp"
#include "lateness_stats.hpp"
#include "nav/bench/capture.hpp"
#include "nav/transport/pty.hpp"

namespace nav::benchmarks {
namespace {

using json = nlohmann::json;

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::vector<bench::CaptureLine> read_capture(const std::filesystem::path& p) {
  auto lines = bench::parse_capture(slurp(p), p.string());
  if (!lines) throw std::runtime_error(lines.error().detail);
  return std::move(*lines);
}

struct Trace {
  std::vector<bench::CaptureLine> lines;
  std::map<std::string, int> baud;  // by port
};

/// The lateness of every message of the trace as the witness's capture shows it, each
/// player's times aligned alike (lateness_stats.hpp); throws when a byte did not arrive.
Stats witnessed(const Trace& trace, const std::filesystem::path& capture) {
  std::map<std::string, std::vector<bench::detail::WitnessRead>> reads;
  const auto seen = read_capture(capture);
  for (const auto& c : seen) reads[c.port].push_back({to_seconds(c.t), c.bytes});
  std::vector<double> scheduled, arrived;
  for (const auto& [port, baud] : trace.baud) {
    std::vector<bench::detail::WitnessSent> sent;
    for (const auto& l : trace.lines) {
      if (l.port == port) sent.push_back({to_seconds(l.t), to_seconds(l.t), l.bytes});
    }
    const auto line = bench::detail::witness_line(port, baud, sent, reads[port]);
    if (line.row.bytes_matched != line.row.bytes_sent) {
      throw std::runtime_error(capture.string() + ": '" + port + "': " +
                               std::to_string(line.row.bytes_matched) + " of " +
                               std::to_string(line.row.bytes_sent) + " bytes arrived as written");
    }
    for (std::size_t k = 0; k < sent.size(); ++k) {
      scheduled.push_back(sent[k].scheduled_s);
      arrived.push_back(*line.arrived_s[k]);
    }
  }
  return reports::summarize(aligned_lateness(scheduled, arrived));
}

std::vector<std::string> witness_argv(const Common& c, const std::filesystem::path& out) {
  return {c.navbench, "witness", "--quiet", "--t0-ns", "0", "-o", out.string()};
}

/// `navbench replay` with the witness as its DUT.
Stats play_navbench(const Common& c, const Trace& trace, const std::filesystem::path& tx, int i) {
  const auto out = c.out / ("serial-navbench-" + std::to_string(i) + ".log");
  std::vector<std::string> argv = {c.navbench, "replay", tx.string(), "--startup", "1",
                                   "--out-capture", (c.out / "replay-rx.log").string(),
                                   "--dut-log", (c.out / "replay-dut.log").string(), "--dut", "--"};
  for (const auto& a : witness_argv(c, out)) argv.push_back(a);
  for (const auto& [port, baud] : trace.baud) {
    argv.push_back(port + "={port:" + port + "}@" + std::to_string(baud));
  }
  // Exit 4: the witness wrote no solution (it never does); whether every byte reached it is
  // what witnessed() checks.
  run(argv, c.out / ("serial-navbench-" + std::to_string(i)), {0, 4});
  return witnessed(trace, out);
}

/// A plain writer: its own ptys, the witness on their slaves, a relative sleep before each
/// message, the message written whole.
Stats play_plain(const Common& c, const Trace& trace, int i) {
  const auto out = c.out / ("serial-plain-" + std::to_string(i) + ".log");
  std::map<std::string, transport::Pty> ptys;
  auto argv = witness_argv(c, out);
  for (const auto& [port, baud] : trace.baud) {
    auto p = transport::Pty::open();
    if (!p) throw std::runtime_error(p.error().detail);
    argv.push_back(port + "=" + p->slave_path() + "@" + std::to_string(baud));
    ptys.emplace(port, std::move(*p));
  }
  const auto stem = c.out / ("serial-plain-" + std::to_string(i));
  const Child witness = start(argv, stem.string() + ".out", stem.string() + ".err");
  std::this_thread::sleep_for(std::chrono::seconds(1));  // as replay's --startup
  Duration previous = trace.lines.front().t;
  for (const auto& l : trace.lines) {
    std::this_thread::sleep_for(l.t - previous);
    previous = l.t;
    const int fd = ptys.at(l.port).master();
    (void)!::write(fd, l.bytes.data(), l.bytes.size());
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  if (stop(witness, SIGTERM).exit_code != 0) throw std::runtime_error("witness failed: " + stem.string() + ".err");
  return witnessed(trace, out);
}

void print(const char* what, const Stats& s) {
  std::printf("  %-24s p50 %8.1f  p99 %8.1f  max %9.1f us  (%zu)\n", what, s.p50_s * 1e6,
              s.p99_s * 1e6, s.max_s * 1e6, s.count);
}

}  // namespace

int run_serial(const Common& c, const std::string& scenario) {
  std::printf("trace: %s in lockstep ...\n", scenario.c_str());
  std::fflush(stdout);
  const auto trace_dir = c.out / "serial-trace";
  run({c.navbench, "run", scenario, "--mode", "lockstep", "--quiet", "--out", trace_dir.string()},
      c.out / "serial-trace", {0, 1});
  Trace trace;
  trace.lines = read_capture(trace_dir / "capture-tx.log");
  const json summary = json::parse(slurp(trace_dir / "summary.json"));
  for (const auto& d : summary.at("devices")) {
    const auto name = d.at("name").get<std::string>();
    const bool in_trace = std::any_of(trace.lines.begin(), trace.lines.end(),
                                      [&](const auto& l) { return l.port == name; });
    if (in_trace && !d.value("can", false)) trace.baud[name] = d.value("baud", 115200);
  }
  if (trace.lines.empty()) throw std::runtime_error(scenario + ": no serial message in its trace");
  std::printf("%zu messages on %zu lines, %.1f s\n", trace.lines.size(), trace.baud.size(),
              to_seconds(trace.lines.back().t - trace.lines.front().t));
  std::vector<Stats> nb, plain;
  for (int i = 1; i <= c.pairs; ++i) {
    nb.push_back(play_navbench(c, trace, trace_dir / "capture-tx.log", i));
    plain.push_back(play_plain(c, trace, i));
    std::printf("pair %d, arrival lateness at the witness [us]:\n", i);
    print("navbench replay", nb.back());
    print("sleep-paced writer", plain.back());
    std::fflush(stdout);
  }
  const PairRatio m = median_ratio(pair_ratios(nb, plain));
  std::printf("median over %d pairs of sleep-paced / navbench:  p50 %.2f  p99 %.2f  max %.2f\n",
              c.pairs, m.p50, m.p99, m.max);
  return 0;
}

}  // namespace nav::benchmarks

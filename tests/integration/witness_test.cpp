// SPDX-License-Identifier: MIT
// `navbench witness` against a writer with known timing, and `navbench run --witness`, the
// timing audit, end to end.
#include <signal.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "judge/witness_timing.hpp"
#include "nav/bench/capture.hpp"
#include "nav/common/time.hpp"
#include "nav/transport/pty.hpp"
#include "navbench_cli.hpp"
#include "source_paths.hpp"

namespace nav::testing {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

TEST(NavbenchWitness, StampsEachArrivalWithin100UsOfAKnownWriteOnTheMedian) {
  const auto dir = fresh_dir("witness-known");
  auto pty = transport::Pty::open();
  ASSERT_TRUE(pty) << pty.error().detail;
  const pid_t pid = start_navbench({"witness", "--t0-ns", "0", "-o", "w.log",
                                    "line=" + pty->slave_path() + "@115200"},
                                   dir);
  ASSERT_GT(pid, 0);
  // The witness opens the line (and flushes it) within its startup; then 200 messages of 24
  // bytes, each written whole at a known CLOCK_MONOTONIC time, 5 ms apart.
  ::usleep(500'000);
  std::vector<std::vector<std::uint8_t>> messages;
  std::vector<bench::detail::WitnessSent> sent;
  messages.reserve(200);
  const Timestamp start = monotonic_now() + std::chrono::milliseconds(10);
  for (int k = 0; k < 200; ++k) {
    std::vector<std::uint8_t> m(24);
    for (std::size_t i = 0; i < m.size(); ++i) m[i] = static_cast<std::uint8_t>(k * 7 + i);
    messages.push_back(std::move(m));
    const timespec at = to_timespec(start + std::chrono::milliseconds(5 * k));
    ::clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &at, nullptr);
    const double t = to_seconds(monotonic_now());
    ASSERT_EQ(::write(pty->master(), messages.back().data(), 24), 24);
    sent.push_back({t, t, messages.back()});
  }
  ::usleep(100'000);
  ::kill(pid, SIGTERM);
  const auto r = finish_navbench(pid, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_FALSE(fs::exists(dir / "w.log.partial"));
  auto capture = bench::parse_capture(slurp(dir / "w.log"), "w.log");
  ASSERT_TRUE(capture) << capture.error().detail;
  std::vector<bench::detail::WitnessRead> reads;
  for (const auto& c : *capture) {
    EXPECT_EQ(c.port, "line");
    reads.push_back({to_seconds(c.t), c.bytes});
  }
  const auto line = bench::detail::witness_line("line", 115200, sent, reads);
  EXPECT_EQ(line.row.bytes_matched, 200u * 24u);
  EXPECT_EQ(line.row.bytes_seen, 200u * 24u);
  ASSERT_EQ(line.row.messages_seen, 200u);
  // Stamped before the read that returned the bytes, after they were written.
  for (const auto& a : line.arrived_s) ASSERT_TRUE(a.has_value());
  for (std::size_t k = 0; k < sent.size(); ++k) EXPECT_GE(*line.arrived_s[k], sent[k].written_s);
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_UNDEFINED__)
  // scripts/test --sanitize: every instrumented program is slower; the bound is about the
  // witness's design, which the plain build tests.
  constexpr double kMedianBound = 1e-3;
#else
  constexpr double kMedianBound = 100e-6;
#endif
  EXPECT_LT(line.row.arrival_lateness.p50_s, kMedianBound)
      << "p99 " << line.row.arrival_lateness.p99_s * 1e3 << " ms";
  std::printf("witness arrival p50 %.1f us p99 %.1f us\n", line.row.arrival_lateness.p50_s * 1e6, line.row.arrival_lateness.p99_s * 1e6);
}

TEST(NavbenchWitness, RefusesBadArgumentsWithExitTwoAndAMissingLineWithThree) {
  const auto dir = fresh_dir("witness-bad");
  auto r = run_navbench({"witness", "-o", "w.log", "nonsense"}, dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("NAME=PATH"), std::string::npos) << r.err;
  r = run_navbench({"witness", "-o", "w.log", "a=/dev/null@115200", "a=/dev/null@9600"}, dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("given twice"), std::string::npos) << r.err;
  r = run_navbench({"witness", "-o", "w.log", "a=/nonexistent/tty@115200"}, dir);
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("port 'a'"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "w.log"));
}

TEST(NavbenchWitness, RunWitnessAuditsEveryStreamingLine) {
  const auto dir = fresh_dir("witness-run");
  const std::string scenario = nav::test_paths::source_dir() +
                               "/tests/integration/scenarios/witness.yaml";
  const auto r = run_navbench({"run", scenario, "--witness", "--out", "run", "--quiet"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("witness arrival lateness"), std::string::npos) << r.out;
  const fs::path run = dir / "run";
  const json s = json::parse(slurp(run / "summary.json"));
  EXPECT_EQ(s["verdict"], "PASS");
  EXPECT_TRUE(s["checks"].empty());  // no DUT: no DUT checks
  ASSERT_TRUE(s.contains("witness"));
  std::vector<std::string> audited;
  for (const auto& l : s["witness"]["lines"]) {
    audited.push_back(l["device"]);
    EXPECT_GT(l["messages"].get<int>(), 0) << l;
    EXPECT_EQ(l["messages_seen"], l["messages"]) << l;
    EXPECT_EQ(l["bytes_matched"], l["bytes_sent"]) << l;
    EXPECT_EQ(l["bytes_seen"], l["bytes_sent"]) << l;
    // The bytes of a message read in several reads came at the baud, within a few percent.
    if (!l["pacing_median"].is_null()) {
      EXPECT_NEAR(l["pacing_median"].get<double>(), 1.0, 0.05) << l;
    }
  }
  // The GX3 streamed without a start command; the Keller only answers, so it is not audited.
  EXPECT_EQ(audited, (std::vector<std::string>{"ahrs", "gps", "dvl"}));
  EXPECT_GT(s["witness"]["arrival_lateness"]["count"].get<int>(), 400);
  EXPECT_TRUE(fs::exists(run / "capture-witness.log"));
  const std::string csv = slurp(run / "lateness.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "device,scheduled_s,actual_s,lateness_us,arrived_s,arrival_lateness_us");
  const std::string html = slurp(run / "report.html");
  EXPECT_NE(html.find("Timing audit"), std::string::npos);
  EXPECT_NE(html.find("plot-arrival-hist"), std::string::npos);
}

TEST(NavbenchWitness, RunWitnessRefusesLockstep) {
  const auto dir = fresh_dir("witness-lockstep");
  const std::string scenario = nav::test_paths::source_dir() +
                               "/tests/integration/scenarios/witness.yaml";
  const auto r = run_navbench({"run", scenario, "--witness", "--mode", "lockstep", "--out", "run"}, dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("realtime"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "run"));
}

}  // namespace
}  // namespace nav::testing

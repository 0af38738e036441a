// SPDX-License-Identifier: MIT
// DUTs that misbehave in ways navd does not (tests/support/lying_dut): solutions naming a
// trigger never sent, a crash at a given scenario time in lockstep, ports opened late, a line
// it never reads, a DUT (and its child) that ignores SIGTERM and SIGHUP.
#include <signal.h>
#include <sys/wait.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>
#include <algorithm>
#include <regex>
#include <string>
#include <vector>

#include "navbench_cli.hpp"

namespace nav::testing {
namespace {

namespace fs = std::filesystem;

// A DUT that answers every trigger with a solution naming one never sent used to keep a
// lockstep run waiting forever (the watchdog saw answers arriving): it is hung.
TEST(NavbenchRun, LockstepDutWhoseSolutionsNameNoSentTriggerIsReportedHung) {
  const auto dir = fresh_dir("lies");
  const auto r = run_navbench(
      {"run", source_path("tests/integration/scenarios/dut_lies.yaml"), "--out", "run"}, dir);
  EXPECT_EQ(r.exit_code, 4) << r.out << r.err;
  EXPECT_NE(r.out.find("VERDICT: DUT hung"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("hung: no solution naming trigger"), std::string::npos) << r.out;
  EXPECT_LT(r.wall_s, 9.0);
}

// A lockstep crash is reported at the scenario time the run had reached, not at the
// wall-clock time since t0 (lockstep runs faster than real time).
TEST(NavbenchRun, LockstepCrashIsReportedAtItsScenarioTime) {
  const auto dir = fresh_dir("crash-lockstep");
  const auto r = run_navbench(
      {"run", source_path("tests/integration/scenarios/dut_crashes_lockstep.yaml"), "--out",
       "run"},
      dir);
  EXPECT_EQ(r.exit_code, 4) << r.out << r.err;
  const std::regex crashed(R"(crashed: exited with status 3 at t=3\.0[0-9]{2} s)");
  EXPECT_TRUE(std::regex_search(r.out, crashed)) << r.out;
}

TEST(NavbenchRun, PortsTheDutHadNotOpenedAtTimeZeroAreNamedInAWarning) {
  const auto dir = fresh_dir("late-open");
  const auto r = run_navbench(
      {"run", source_path("tests/integration/scenarios/late_open.yaml"), "--out", "run"}, dir);
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;  // it answers once it opened them
  for (const char* device : {"ahrs", "gps"}) {
    const std::regex warning(std::string("navbench: warning: device '") + device +
                             "': the DUT had not opened /dev/pts/[0-9]+ at scenario time 0; "
                             "what is sent before it does is lost \\(give it more "
                             "dut.startup\\)\n");
    EXPECT_TRUE(std::regex_search(r.err, warning)) << device << ": " << r.err;
  }
  // A DUT that opens its ports in time (navd) gets no warning.
  const auto fine = run_navbench(
      {"run", source_path("tests/integration/scenarios/open_in_time.yaml"), "--out", "fine"}, dir);
  EXPECT_EQ(fine.exit_code, 0) << fine.out << fine.err;
  EXPECT_EQ(fine.err.find("warning"), std::string::npos) << fine.err;
}

// A device the DUT never reads filled its line once; a lockstep run used to wait a watchdog
// period for every later message of it (hours for a minute of scenario). Now it waits one
// period, warns, and drops that line's bytes while the DUT does not read it.
TEST(NavbenchRun, LockstepDoesNotWaitForALineTheDutNeverReads) {
  const auto dir = fresh_dir("unread-line");
  const auto r = run_navbench(
      {"run", source_path("tests/integration/scenarios/unread_line.yaml"), "--out", "run"}, dir);
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  const std::regex warning(
      "navbench: warning: device 'spare': the DUT read nothing of its line for 1\\.0 s "
      "\\(dut.watchdog\\) at t=[0-9.]+ s; its bytes are dropped while the DUT does not read "
      "it\n");
  EXPECT_TRUE(std::regex_search(r.err, warning)) << r.err;
  EXPECT_EQ(r.err.find("device 'ahrs'"), std::string::npos) << r.err;  // read: no warning
  EXPECT_LT(r.wall_s, 120.0);  // one watchdog wait, not one per message (3000 s)
}

/// Whether process `pid` is gone (or a zombie: it ended, and nobody reaped it yet).
bool ended(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!std::getline(stat, line)) return true;
  const auto paren = line.rfind(')');
  return paren != std::string::npos && line.size() > paren + 2 && line[paren + 2] == 'Z';
}

/// Starts navbench on the stubborn DUT's scenario in dir, waits until the DUT wrote its
/// and its child's pids, ends navbench with `signal`; returns the two pids (empty when the
/// DUT never started).
std::vector<pid_t> end_bench_of_stubborn_dut(const fs::path& dir, int signal) {
  const pid_t bench = start_navbench(
      {"run", source_path("tests/integration/scenarios/stubborn_dut.yaml"), "--out", "run"}, dir);
  if (bench < 0) return {};
  const auto pid_file = dir / "dut-pids";
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(15);
  while (!fs::exists(pid_file) && std::chrono::steady_clock::now() < give_up) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the bench's guard is up
  ::kill(bench, signal);
  ::waitpid(bench, nullptr, 0);
  std::ifstream in(pid_file);
  pid_t dut = 0, child = 0;
  if (!(in >> dut >> child)) return {};
  return {dut, child};
}

/// Whether every pid ended within `within`.
bool all_end(const std::vector<pid_t>& pids, std::chrono::seconds within) {
  const auto give_up = std::chrono::steady_clock::now() + within;
  while (std::chrono::steady_clock::now() < give_up) {
    if (std::all_of(pids.begin(), pids.end(), ended)) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

// ^C: the bench stops its DUT, and the whole of the DUT's process group with it.
TEST(NavbenchRun, InterruptedBenchEndsTheDutsWholeProcessGroup) {
  const auto dir = fresh_dir("stubborn-int");
  const auto pids = end_bench_of_stubborn_dut(dir, SIGINT);
  ASSERT_EQ(pids.size(), 2u) << slurp(dir / "stdout.txt") << slurp(dir / "stderr.txt");
  EXPECT_TRUE(ended(pids[0])) << "the DUT outlived the bench";
  EXPECT_TRUE(ended(pids[1])) << "the DUT's child outlived the bench";
}

// kill -9 of the bench: its guard (nav-group-guard) ends the DUT's group.
TEST(NavbenchRun, BenchKilledWithSigkillTakesTheDutsProcessGroupWithIt) {
  const auto dir = fresh_dir("stubborn-kill");
  const auto pids = end_bench_of_stubborn_dut(dir, SIGKILL);
  ASSERT_EQ(pids.size(), 2u) << slurp(dir / "stdout.txt") << slurp(dir / "stderr.txt");
  EXPECT_TRUE(all_end(pids, std::chrono::seconds(10)))
      << "the DUT or its child outlived the bench by 10 s";
}

}  // namespace
}  // namespace nav::testing

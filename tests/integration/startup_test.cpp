// SPDX-License-Identifier: MIT
// The DUT's startup in lockstep: navd says READY=1 (sd_notify) once its ports are open, and
// the run starts then instead of after its whole dut.startup, its times counted from then; a
// DUT that cannot say so gets the whole startup. As root, a lockstep DUT runs at SCHED_RR.
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include "navbench_cli.hpp"
#include "source_paths.hpp"

namespace nav::testing {
namespace {

namespace fs = std::filesystem;

/// The time of the first line of a capture ("(<sec>.<nsec>) output <hex>"), or -1e9.
double first_capture_time(const fs::path& capture) {
  std::ifstream in(capture);
  std::string line;
  double t = -1e9;
  if (std::getline(in, line)) (void)std::sscanf(line.c_str(), "(%lf)", &t);
  return t;
}

/// ready_lockstep.yaml with navd started by a script that first writes its own scheduling
/// policy to dut.log (`chrt -p`): in lockstep once it is SCHED_RR (or after 5 s), in realtime
/// after 0.5 s.
std::string policy_reporting_scenario(const std::string& mode) {
  std::string text = slurp(source_path("tests/integration/scenarios/ready_lockstep.yaml"));
  const std::string wait =
      mode == "lockstep"
          ? "for i in $(seq 50); do chrt -p $$ | grep -q SCHED_RR && break; sleep 0.1; done; "
          : "sleep 0.5; ";
  // Not regex_replace: its replacement text gives '$' a meaning.
  const std::string navd = "command: [navd,";
  const auto at = text.find(navd);
  if (at == std::string::npos) return {};
  text.replace(at, navd.size(),
               "command: [sh, -c, '" + wait + "chrt -p $$ >&2; exec " +
                   nav::test_paths::binary_dir() + "/navd \"$@\"', sh,");
  text = std::regex_replace(text, std::regex("mode: lockstep"), "mode: " + mode);
  // Lockstep starts when navd says it is ready; realtime waits the whole startup.
  text = std::regex_replace(text, std::regex("startup: 60 s"),
                            mode == "lockstep" ? "startup: 8 s" : "startup: 2 s");
  return text;
}

// As root, a lockstep run's DUT runs at SCHED_RR 10, its own children as usual; a realtime
// run's DUT is left alone (docs/dut-contract.md §1, "Scheduling").
TEST(NavbenchStartup, ALockstepDutRunsAtRoundRobinPriorityARealtimeOneAsItIs) {
  if (::geteuid() != 0) GTEST_SKIP() << "setting a real-time policy needs root";
  for (const std::string mode : {"lockstep", "realtime"}) {
    const auto dir = fresh_dir("policy-" + mode);
    const std::string scenario = policy_reporting_scenario(mode);
    ASSERT_NE(scenario.find("chrt -p"), std::string::npos);
    std::ofstream(dir / "policy.yaml") << scenario;
    const auto r = run_navbench({"run", (dir / "policy.yaml").string(), "--out", "run"}, dir);
    EXPECT_EQ(r.exit_code, 0) << mode << r.out << r.err;
    const std::string log = slurp(dir / "run" / "dut.log");
    if (mode == "lockstep") {
      EXPECT_NE(log.find("scheduling policy: SCHED_RR|SCHED_RESET_ON_FORK"), std::string::npos)
          << log;
      EXPECT_NE(log.find("scheduling priority: 10"), std::string::npos) << log;
    } else {
      EXPECT_NE(log.find("scheduling policy: SCHED_OTHER"), std::string::npos) << log;
    }
  }
}

// dut.startup is 60 s; navd is ready within a fraction of a second.
TEST(NavbenchStartup, LockstepStartsWhenTheDutSaysItIsReady) {
  const auto dir = fresh_dir("ready");
  const auto r = run_navbench(
      {"run", source_path("tests/integration/scenarios/ready_lockstep.yaml"), "--out", "run"},
      dir);
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_LT(r.wall_s, 30.0) << r.out;
  EXPECT_NE(r.out.find("300 solutions for 300 triggers"), std::string::npos) << r.out;
  // Times count from the moment the run started: the first solution came just after it.
  const double first = first_capture_time(dir / "run" / "capture-rx.log");
  EXPECT_GE(first, 0.0);
  EXPECT_LT(first, 30.0);
}

// The same navd without NOTIFY_SOCKET (env -u) cannot say it is ready: the run waits its
// dut.startup, here 1.5 s.
TEST(NavbenchStartup, ADutThatDoesNotSayItIsReadyGetsItsWholeStartup) {
  const auto dir = fresh_dir("not-ready");
  std::string text = slurp(source_path("tests/integration/scenarios/ready_lockstep.yaml"));
  text = std::regex_replace(text, std::regex(R"(command: \[navd,)"),
                            "command: [env, -u, NOTIFY_SOCKET, " + nav::test_paths::binary_dir() +
                                "/navd,");
  text = std::regex_replace(text, std::regex("startup: 60 s"), "startup: 1500 ms");
  ASSERT_NE(text.find("env, -u"), std::string::npos);
  std::ofstream(dir / "quiet.yaml") << text;
  const auto r = run_navbench({"run", (dir / "quiet.yaml").string(), "--out", "run"}, dir);
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_GE(r.wall_s, 1.5) << r.out;
  EXPECT_NE(r.out.find("300 solutions for 300 triggers"), std::string::npos) << r.out;
  EXPECT_GE(first_capture_time(dir / "run" / "capture-rx.log"), 0.0);
}

}  // namespace
}  // namespace nav::testing

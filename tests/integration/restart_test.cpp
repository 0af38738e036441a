// SPDX-License-Identifier: MIT
// The DUT restart fault (dut.faults: restart): navd killed mid-run and started again, in
// lockstep (reproducible, its recovery in scenario time) and in realtime (the gap not counted
// as deadline misses, a recovery bound that fails); a lockstep restart goes on once the new
// DUT says it is ready.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include <nlohmann/json.hpp>

#include "navbench_cli.hpp"
#include "run_summary.hpp"

namespace nav::testing {
namespace {

namespace fs = std::filesystem;

const std::string kScenario = "tests/integration/scenarios/dut_restart.yaml";

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(NavbenchRestart, InLockstepTheDutIsKilledStartedAgainAndItsRecoveryReproduces) {
  const auto dir = fresh_dir("restart-lockstep");
  const auto r = run_navbench({"run", source_path(kScenario), "--out", "a"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("restart: off at t=6.00 s (killed by signal 9"), std::string::npos) << r.out;
  const auto s = summary(dir / "a");
  const auto& restarts = s["dut"]["restarts"];
  ASSERT_EQ(restarts.size(), 1u) << s["dut"].dump();
  const auto& rs = restarts[0];
  EXPECT_EQ(rs["off_s"], 6.0);
  EXPECT_EQ(rs["on_s"], 7.5);
  EXPECT_EQ(rs["ended"], "killed by signal 9 (Killed)");
  // navd answers every trigger from its first packet (ALIGNING), and has a position at the
  // first GPS fix after it started: the 1 Hz GPS of t=8 s.
  EXPECT_EQ(rs["first_solution_s"], 7.5);
  ASSERT_TRUE(rs["recovery_s"].is_number()) << rs.dump();
  EXPECT_GT(rs["recovery_s"].get<double>(), 0.5);
  EXPECT_LT(rs["recovery_s"].get<double>(), 1.5);
  // The 150 GX3 packets of [6 s, 7.5 s) had nobody to answer them.
  EXPECT_EQ(rs["triggers_in_gap"], 150);
  EXPECT_EQ(s["dut"]["triggers_sent"].get<int>() - s["dut"]["answers"].get<int>(), 150);
  const auto* recovery = check(s, "restart_recovery");
  ASSERT_NE(recovery, nullptr);
  EXPECT_TRUE((*recovery)["passed"].get<bool>()) << recovery->dump();
  EXPECT_EQ((*recovery)["value"], rs["recovery_s"]);
  // The restart is a fault of the run: in the fault table (and the plots' fault windows).
  bool listed = false;
  for (const auto& f : s["faults"]) {
    listed |= f["device"] == "dut" && f["kind"] == "restart" && f["start_s"] == 6.0;
  }
  EXPECT_TRUE(listed) << s["faults"].dump();
  // Two navd processes wrote to one dut.log, the bench's line between them.
  const std::string log = slurp(dir / "a" / "dut.log");
  EXPECT_EQ(count(log, "navd: running"), 2u) << log;
  EXPECT_EQ(count(log, "navd: stopped (SIGTERM)"), 1u) << log;  // the first got SIGKILL
  EXPECT_NE(log.find("navbench: restart fault: the DUT was killed (SIGKILL to its process "
                     "group) at t=6.000 s and is started again at t=7.500 s"),
            std::string::npos) << log;
  // Lockstep reproduces through a restart: the same solutions, bit for bit.
  const auto again = run_navbench({"run", source_path(kScenario), "--out", "b"}, dir);
  ASSERT_EQ(again.exit_code, 0) << again.out << again.err;
  EXPECT_EQ(slurp(dir / "a" / "estimate.tum"), slurp(dir / "b" / "estimate.tum"));
  EXPECT_EQ(summary(dir / "b")["dut"]["restarts"], restarts);
}

// With dut.startup 60 s, a lockstep restart goes on once the new navd says READY=1 (as at the
// first start), not a minute later, and the run is the same bit for bit.
TEST(NavbenchRestart, InLockstepTheRunGoesOnOnceTheRestartedDutSaysItIsReady) {
  const auto dir = fresh_dir("restart-ready");
  std::string text = slurp(source_path(kScenario));
  text = std::regex_replace(text, std::regex("  trigger: ahrs\n"),
                            "  trigger: ahrs\n  startup: 60 s\n");
  ASSERT_NE(text.find("startup: 60 s"), std::string::npos);
  std::ofstream(dir / "slow-start.yaml") << text;
  const auto r = run_navbench({"run", (dir / "slow-start.yaml").string(), "--out", "slow"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_LT(r.wall_s, 30.0) << r.out;  // neither the first start nor the restart waited 60 s
  const auto plain = run_navbench({"run", source_path(kScenario), "--out", "plain"}, dir);
  ASSERT_EQ(plain.exit_code, 0) << plain.out << plain.err;
  EXPECT_EQ(slurp(dir / "slow" / "estimate.tum"), slurp(dir / "plain" / "estimate.tum"));
  EXPECT_EQ(summary(dir / "slow")["dut"]["restarts"], summary(dir / "plain")["dut"]["restarts"]);
  EXPECT_EQ(count(slurp(dir / "slow" / "dut.log"), "navd: running"), 2u);
}

TEST(NavbenchRestart, InRealtimeTheGapIsNoDeadlineMissAndATightRecoveryBoundFails) {
  const auto dir = fresh_dir("restart-realtime");
  // The same scenario with a recovery bound navd cannot meet: it waits for a GPS fix.
  std::string text = slurp(source_path(kScenario));
  text = std::regex_replace(text, std::regex("restart_recovery, max: 3 s"),
                            "restart_recovery, max: 100 ms, req: NAV-REQ-031");
  std::ofstream(dir / "tight.yaml") << text;
  const auto r = run_navbench({"run", "tight.yaml", "--mode", "realtime", "--out", "run"}, dir);
  ASSERT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("VERDICT: FAIL"), std::string::npos) << r.out;
  const auto s = summary(dir / "run");
  const auto* recovery = check(s, "restart_recovery");
  ASSERT_NE(recovery, nullptr);
  EXPECT_FALSE((*recovery)["passed"].get<bool>());
  EXPECT_GT((*recovery)["value"].get<double>(), 0.1);
  EXPECT_EQ((*recovery)["worst_t_s"], 7.5);
  // Everything else held: the gap's triggers are not deadline misses, navd is alive.
  for (const char* name : {"horizontal_error", "deadline", "dut_alive"}) {
    ASSERT_NE(check(s, name), nullptr) << name;
    EXPECT_TRUE((*check(s, name))["passed"].get<bool>()) << check(s, name)->dump();
  }
  const std::string deadline = (*check(s, "deadline"))["detail"];
  EXPECT_TRUE(std::regex_search(deadline, std::regex(", 1[0-9][0-9] sent while the DUT "
                                                     "restarted not counted")))
      << deadline;
  EXPECT_NE(s["dut"]["status"].get<std::string>().find("started again 1 time"),
            std::string::npos);
}

}  // namespace
}  // namespace nav::testing

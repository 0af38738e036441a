// SPDX-License-Identifier: MIT
// DUTs that misbehave in ways navd does not (tests/support/lying_dut): solutions naming a
// trigger never sent, a crash at a given scenario time in lockstep, ports opened late.
#include <filesystem>
#include <regex>
#include <string>

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

}  // namespace
}  // namespace nav::testing

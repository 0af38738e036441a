// SPDX-License-Identifier: MIT
// A run folder belongs to one run: a second run given the same --out while the first writes
// it is refused at once and touches nothing; a .partial folder left by a run that died is
// taken over; an --out that cannot be made is a usage error; an interrupted run leaves a
// complete folder that says when it stopped.
#include <signal.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <future>
#include <thread>

#include <nlohmann/json.hpp>

#include "navbench_cli.hpp"

namespace nav::testing {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

TEST(NavbenchRunFolder, ASecondRunIntoTheSameFolderIsRefusedAndTouchesNothing) {
  const auto dir = fresh_dir("same-out");
  fs::create_directories(dir / "a");
  fs::create_directories(dir / "b");
  const fs::path out = dir / "run";
  auto first = std::async(std::launch::async, [&] {
    return run_navbench({"run", source_path("tests/integration/scenarios/open_in_time.yaml"),
                         "--out", out.string(), "--quiet"},
                        dir / "a");
  });
  // Once the first run holds its folder, start the second.
  for (auto give_up = std::chrono::steady_clock::now() + 20s;
       !fs::exists(fs::path(out.string() + ".partial")) && std::chrono::steady_clock::now() < give_up;) {
    std::this_thread::sleep_for(10ms);
  }
  const auto second = run_navbench({"run", source_path("tests/integration/scenarios/late_open.yaml"),
                                    "--out", out.string(), "--quiet"},
                                   dir / "b");
  EXPECT_EQ(second.exit_code, 2) << second.err;
  EXPECT_EQ(second.err, "navbench: run folder " + out.string() +
                            " is being written by another run (" + out.string() +
                            ".partial is locked); choose another --out\n");
  const auto a = first.get();
  EXPECT_EQ(a.exit_code, 0) << a.out << a.err;
  // The folder is the first run's, whole: its scenario, one DUT log.
  EXPECT_NE(slurp(out / "scenario.yaml").find("it-open-in-time"), std::string::npos);
  EXPECT_TRUE(fs::exists(out / "summary.json"));
  EXPECT_FALSE(fs::exists(fs::path(out.string() + ".partial")));
  // And now that it is complete, a third run into it is refused too.
  const auto third = run_navbench({"run", source_path("tests/integration/scenarios/late_open.yaml"),
                                   "--out", out.string(), "--quiet"},
                                  dir / "b");
  EXPECT_EQ(third.exit_code, 2);
  EXPECT_EQ(third.err, "navbench: run folder " + out.string() +
                           " exists already; choose another --out\n");
}

TEST(NavbenchRunFolder, APartialFolderLeftByARunThatDiedIsTakenOver) {
  const auto dir = fresh_dir("stale-partial");
  fs::create_directories(dir / "run.partial");
  { std::ofstream(dir / "run.partial" / "leftover.txt") << "from a run killed with -9\n"; }
  const auto r = run_navbench({"run", source_path("tests/integration/scenarios/open_in_time.yaml"),
                               "--out", "run", "--quiet"},
                              dir);
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_TRUE(fs::exists(dir / "run" / "summary.json"));
  EXPECT_FALSE(fs::exists(dir / "run" / "leftover.txt"));
}

// A run folder that cannot be made where --out says is the user's to change: exit 2, one
// line naming it, before anything runs.
TEST(NavbenchRunFolder, AnOutThatCannotBeCreatedIsAUsageError) {
  const auto dir = fresh_dir("bad-out");
  { std::ofstream(dir / "a-file") << "in the way\n"; }
  for (const std::string out : {"/proc/navbench-run", "a-file/run"}) {
    const auto r = run_navbench(
        {"run", source_path("tests/integration/scenarios/open_in_time.yaml"), "--out", out}, dir);
    EXPECT_EQ(r.exit_code, 2) << out << ": " << r.err;
    EXPECT_EQ(r.err.rfind("navbench: cannot create ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find("; choose another --out\n"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
}

// ^C part-way: a complete folder that says when the run was stopped, and checks that need the
// rest of the run (an 'after' not reached, the end point) not judged rather than failed.
TEST(NavbenchRunFolder, AnInterruptedRunSaysWhenItStoppedAndJudgesOnlyWhatItReached) {
  const auto dir = fresh_dir("interrupted");
  const pid_t bench = start_navbench(
      {"run", source_path("scenarios/smoke.yaml"), "--out", "run", "--quiet"}, dir);
  ASSERT_GT(bench, 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(2500));  // startup 0.5 s, then ~2 s
  ::kill(bench, SIGINT);
  const auto r = finish_navbench(bench, dir);
  ASSERT_EQ(r.exit_code, 3) << r.out << r.err;
  const auto s = nlohmann::json::parse(slurp(dir / "run/summary.json"));
  EXPECT_EQ(s.at("verdict"), "INTERRUPTED");
  EXPECT_EQ(s.at("duration_s").dump(), "60.0");  // not 60.00000000000001
  const double stopped = s.at("stopped_at_s").get<double>();
  EXPECT_GT(stopped, 0.5);
  EXPECT_LT(stopped, 4.9);  // before the smoke scenario's after: 5 s (a loaded VM: margin)
  EXPECT_NE(s.at("dut").at("status").get<std::string>().find("alive when the run was stopped at t="),
            std::string::npos);
  for (const auto& c : s.at("checks")) {
    const std::string name = c.at("name");
    if (name == "horizontal_error" || name == "vertical_error" || name == "endpoint_error") {
      EXPECT_FALSE(c.at("judged").get<bool>()) << c;
      EXPECT_EQ(c.at("detail").get<std::string>().rfind("not judged: the run was stopped at t=", 0),
                0u)
          << c;
    }
  }
  EXPECT_NE(r.out.find("  stopped by a signal at t="), std::string::npos) << r.out;
}

}  // namespace
}  // namespace nav::testing

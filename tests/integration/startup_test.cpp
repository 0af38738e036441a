// SPDX-License-Identifier: MIT
// The DUT's startup in lockstep: navd says READY=1 (sd_notify) once its ports are open, and
// the run starts then instead of after its whole dut.startup, its times counted from then; a
// DUT that cannot say so gets the whole startup.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include "navbench_cli.hpp"

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
                            "command: [env, -u, NOTIFY_SOCKET, " + std::string(NAV_BINARY_DIR) +
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

// SPDX-License-Identifier: MIT
// Paper P3 on vcan0 (through scripts/with-vcan): navd's P3 navigator answers every EBIMU line
// with the wheel encoders on CAN and the Keller depth, and two runs on one CAN interface at
// once do not mix their frames: the second waits for the first and both give the same
// estimate, byte for byte.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "navbench_cli.hpp"

namespace nav::testing {
namespace {

namespace fs = std::filesystem;

// 5 minutes of lockstep: several seconds of wall time, so the second run comes while the first
// holds the bus.
const std::string kSim = "scenarios/p3-sim.yaml";

TEST(P3Run, TwoRunsOnOneCanInterfaceTakeTurnsAndAgree) {
  const auto dir = fresh_dir("p3-two");
  const auto a_cwd = dir / "a";
  const auto b_cwd = dir / "b";
  fs::create_directories(a_cwd);
  fs::create_directories(b_cwd);
  const pid_t a = start_navbench(
      {"run", source_path(kSim), "--variant", "ekf-kr", "-q", "-o", (dir / "run-a").string()},
      a_cwd);
  ASSERT_GT(a, 0);
  // The first run holds vcan0 before it makes its run folder.
  for (int i = 0; i < 600 && !fs::exists(dir / "run-a.partial"); ++i) {
    ::usleep(50'000);
  }
  const auto b = run_navbench(
      {"run", source_path(kSim), "--variant", "ekf-kr", "-q", "-o", (dir / "run-b").string()},
      b_cwd);
  const auto ra = finish_navbench(a, a_cwd);
  ASSERT_TRUE(ra.exit_code == 0 || ra.exit_code == 1) << ra.err;
  ASSERT_TRUE(b.exit_code == 0 || b.exit_code == 1) << b.err;
  EXPECT_NE(b.err.find("navbench: CAN interface vcan0 is in use by another run"),
            std::string::npos)
      << b.err;
  EXPECT_EQ(slurp(dir / "run-a" / "estimate.tum"), slurp(dir / "run-b" / "estimate.tum"));
  EXPECT_EQ(slurp(dir / "run-a" / "capture-tx.log"), slurp(dir / "run-b" / "capture-tx.log"));

  // Every EBIMU line answered; the wheels, depths and updates counted in navd's summary.
  const auto summary = nlohmann::json::parse(slurp(dir / "run-a" / "summary.json"));
  const std::string dut_log = slurp(dir / "run-a" / "dut.log");
  EXPECT_NE(dut_log.find("p3-ekf-kr steps=6000 "), std::string::npos) << dut_log;
  // 6000 frames of each wheel, but the last pair is due with no EBIMU line after it to wait for.
  EXPECT_NE(dut_log.find("wheel_samples=11998 wheel_invalid=0"), std::string::npos) << dut_log;
  EXPECT_NE(dut_log.find("ebimu_wrong_length=0"), std::string::npos) << dut_log;
  bool judged = false;
  for (const auto& c : summary["checks"]) {
    if (c["name"] != "final_horizontal_error") continue;
    judged = true;
    EXPECT_EQ(c["kind"], "horizontal_error_at");
    EXPECT_LT(c["value"].get<double>(), 1.0) << c.dump();  // the kinematic x holds it
  }
  EXPECT_TRUE(judged) << summary["checks"].dump();
  fs::remove_all(dir);
}

}  // namespace
}  // namespace nav::testing

// SPDX-License-Identifier: MIT
// A CAN trigger end to end on vcan0 (docs/dut-contract.md sections 4, 5 and 8):
// tests/integration/scenarios/can_trigger.yaml in lockstep, NMEA 2000 heading frames as the
// triggers, GPS sentences on a pty and N2K position frames as aiding inputs, answered by
// tests/support/can_trigger_dut.cpp.
//
//   every heading frame is a trigger, answered once by its tag (PGN * 256 + SID), and the run
//   passes (no hang: the barrier after each trigger frame was met);
//   when the DUT answered the k-th trigger it had received exactly the CAN frames up to that
//   frame (capture-can.log) and the LF bytes of exactly the serial messages whose first byte's
//   wire time precedes the frame's (capture-tx.log): serial and CAN reached it in wire-time
//   order, and nothing after a trigger was written before its answer.
//
// ctest runs this binary through scripts/with-vcan (label vcan); run directly without vcan0
// the case skips, except under CI (CI=true).
#include <net/if.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "nav/protocols/candump_log.hpp"
#include "can_test_support.hpp"
#include "navbench_cli.hpp"

namespace nav::testing {
namespace {

namespace fs = std::filesystem;
namespace candump = protocols::candump;

/// Scenario time of a capture line's "(sec.frac)" stamp [ns].
std::int64_t stamp_ns(const std::string& line) {
  const auto dot = line.find('.');
  const auto close = line.find(')');
  std::string frac = line.substr(dot + 1, close - dot - 1);
  frac.resize(9, '0');
  return std::stoll(line.substr(1, dot - 1)) * 1'000'000'000LL + std::stoll(frac);
}

struct SerialMessage {
  std::int64_t start_ns = 0;
  std::size_t lfs = 0;
};

/// capture-tx.log: every serial message with its first byte's wire time.
std::vector<SerialMessage> read_tx(const fs::path& p) {
  std::vector<SerialMessage> out;
  std::ifstream f(p);
  std::string line;
  while (std::getline(f, line)) {
    std::istringstream in(line);
    std::string stamp, port, hex;
    in >> stamp >> port >> hex;
    SerialMessage m{stamp_ns(stamp), 0};
    for (std::size_t i = 0; i + 1 < hex.size(); i += 2) {
      m.lfs += hex.compare(i, 2, "0A") == 0 || hex.compare(i, 2, "0a") == 0 ? 1 : 0;
    }
    out.push_back(m);
  }
  return out;
}

struct Frame {
  std::int64_t due_ns = 0;  ///< to the microsecond (candump's six decimals)
  std::uint64_t tag = 0;    ///< PGN * 256 + SID for a heading frame, else 0
};

std::vector<Frame> read_can(const fs::path& p) {
  std::vector<Frame> out;
  std::ifstream f(p);
  std::string line;
  while (std::getline(f, line)) {
    const auto r = candump::parse_line(line);
    if (!r.record) continue;
    const auto& fr = r.record->frame;
    Frame x{stamp_ns(line), 0};
    const std::uint32_t pgn = (fr.id >> 8) & 0x3FFFFu;
    if (pgn == 127250 && (fr.id & 0xFFu) == 35) x.tag = std::uint64_t{pgn} * 256 + fr.data[0];
    out.push_back(x);
  }
  return out;
}

struct Answered {
  std::uint64_t tag = 0, serial_lines = 0, can_frames = 0;
};

std::vector<Answered> read_dut_log(const fs::path& p) {
  std::vector<Answered> out;
  std::ifstream f(p);
  std::string line;
  const std::regex re(R"(trigger tag=(\d+) serial_lines=(\d+) can_frames=(\d+))");
  while (std::getline(f, line)) {
    std::smatch m;
    if (!std::regex_search(line, m, re)) continue;
    out.push_back({std::stoull(m[1]), std::stoull(m[2]), std::stoull(m[3])});
  }
  return out;
}

TEST(CanTrigger, LockstepHoldsEveryLineUntilEachTriggerFrameIsAnsweredInWireTimeOrder) {
  REQUIRE_VCAN();
  const auto cwd = fresh_dir("can-trigger");
  const auto r = run_navbench(
      {"run", source_path("tests/integration/scenarios/can_trigger.yaml"), "--out", "run"}, cwd);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err << slurp(cwd / "run" / "dut.log");
  const fs::path run = cwd / "run";

  const auto frames = read_can(run / "capture-can.log");
  const auto serial = read_tx(run / "capture-tx.log");
  const auto answered = read_dut_log(run / "dut.log");
  std::vector<std::size_t> trigger_frames;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (frames[i].tag != 0) trigger_frames.push_back(i);
  }
  ASSERT_EQ(trigger_frames.size(), 40u);  // 127250 at 10 Hz for 4 s
  ASSERT_EQ(answered.size(), trigger_frames.size()) << slurp(run / "dut.log");
  ASSERT_GT(serial.size(), 10u);

  const auto summary = nlohmann::json::parse(slurp(run / "summary.json"));
  EXPECT_EQ(summary["dut"]["triggers_sent"], trigger_frames.size());
  EXPECT_EQ(summary["dut"]["answers"], trigger_frames.size());
  EXPECT_EQ(summary["dut"]["unmatched_answers"], 0);

  for (std::size_t k = 0; k < answered.size(); ++k) {
    const Frame& tf = frames[trigger_frames[k]];
    EXPECT_EQ(answered[k].tag, tf.tag) << k;
    // Every frame up to the trigger, none after it.
    EXPECT_EQ(answered[k].can_frames, trigger_frames[k] + 1) << k;
    // The serial messages whose first byte comes before the frame's due time (a tie goes to
    // the frame); the log has the due time to the microsecond, so allow that microsecond.
    std::uint64_t before = 0, upto = 0;
    for (const auto& m : serial) {
      if (m.start_ns < tf.due_ns) before += m.lfs;
      if (m.start_ns < tf.due_ns + 1000) upto += m.lfs;
    }
    EXPECT_GE(answered[k].serial_lines, before) << k;
    EXPECT_LE(answered[k].serial_lines, upto) << k;
  }
}

}  // namespace
}  // namespace nav::testing

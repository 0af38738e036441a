// SPDX-License-Identifier: MIT
// Golden lockstep regression of what the bench puts on the wire (tests/golden/CMakeLists.txt):
// every byte the bench transmitted (capture-tx.log), every CAN frame (capture-can.log) and the
// estimate of every vehicle (estimate.tum, estimate-<peer>.tum) of the multi-device scenarios,
// summarised by golden_support.hpp's text_digest. These hold the bench's output fixed while
// its run engine is rebuilt. capture-rx.log carries wall-clock receive times: not a golden.
//
// Built twice: wire_golden_test (serial scenarios, label golden) and, with NAV_WIRE_GOLDEN_CAN,
// wire_golden_can_test (scenarios with a CAN bus, on vcan0 through scripts/with-vcan).
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "golden_support.hpp"

namespace nav::testing {
namespace {

namespace fs = std::filesystem;

#ifdef NAV_WIRE_GOLDEN_CAN
const std::vector<std::string> kScenarios{"mixed-can-serial"};
#else
const std::vector<std::string> kScenarios{"all-devices", "faults-gps-ahrs", "faults-measurement"};
#endif

/// The golden text of one lockstep run folder.
std::string wire_text(const std::string& scenario, const fs::path& run) {
  std::string o = "# Golden lockstep wire output of scenarios/" + scenario + ".yaml: the bench's\n"
                  "# transmit captures and every vehicle's estimate. Regenerate with\n"
                  "# scripts/update-golden after a deliberate change, in the same commit.\n"
                  "scenario " + scenario + "\n";
  o += text_digest("capture_tx", slurp(run / "capture-tx.log"), 500);
  if (fs::exists(run / "capture-can.log")) {
    o += text_digest("capture_can", slurp(run / "capture-can.log"), 500);
  }
  o += text_digest("estimate", slurp(run / "estimate.tum"), 500);
  std::vector<std::string> peers;
  for (const auto& e : fs::directory_iterator(run)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("estimate-", 0) == 0 && e.path().extension() == ".tum") peers.push_back(name);
  }
  std::sort(peers.begin(), peers.end());
  for (const auto& name : peers) {
    // The primary's own file is a link to estimate.tum: only the peers' add anything.
    if (slurp(run / name) == slurp(run / "estimate.tum")) continue;
    o += text_digest(name.substr(0, name.size() - 4), slurp(run / name), 500);
  }
  return o;
}

class WireGolden : public ::testing::TestWithParam<std::string> {};

TEST_P(WireGolden, LockstepWireOutputMatchesTheGoldenFile) {
  const std::string scenario = GetParam();
  const fs::path dir = fresh_dir("wire-golden-" + scenario);
  const fs::path run = dir / "run";
  const ProcessResult r =
      run_navbench({"run", source_path("scenarios/" + scenario + ".yaml"), "--mode", "lockstep",
                    "-q", "-o", run.string()},
                   dir);
  ASSERT_TRUE(r.exit_code == 0 || r.exit_code == 1) << r.out << r.err;
  expect_golden("tests/golden/wire/" + scenario + ".golden", wire_text(scenario, run),
                scenario + ": the lockstep wire output");
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Scenarios, WireGolden, ::testing::ValuesIn(kScenarios),
                         [](const ::testing::TestParamInfo<std::string>& i) {
                           std::string n = i.param;
                           for (char& c : n) {
                             if (c == '-') c = '_';
                           }
                           return n;
                         });

}  // namespace
}  // namespace nav::testing

// SPDX-License-Identifier: MIT
// Golden lockstep regression of the paper scenarios (tests/golden/CMakeLists.txt).
//
// Each scenario runs once in lockstep (bit-reproducible); the DUT's output line is taken from
// the run's capture-rx.log and summarised as: the number of solutions, a 64-bit FNV-1a digest
// of every output byte, and every 200th $PNVBSOL line plus the last, so a reviewer sees where
// a change shows. With NAV_UPDATE_GOLDEN=1 in the environment the test writes the golden file
// instead of comparing (scripts/update-golden does that for every scenario).
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "golden_support.hpp"
#include "nav/bench/decode.hpp"

namespace nav::testing {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kEvery = 200;  // solutions between two quoted lines

/// The paper scenarios, by name (scenarios/p0-*.yaml: p0-pool-* and p0-paper-*;
/// scenarios/p1-*.yaml), sorted.
std::vector<std::string> golden_scenarios() {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(source_path("scenarios"))) {
    const std::string stem = e.path().stem().string();
    const bool paper = stem.rfind("p0-", 0) == 0 || stem.rfind("p1-", 0) == 0;
    if (e.path().extension() == ".yaml" && paper) names.push_back(stem);
  }
  std::sort(names.begin(), names.end());
  return names;
}

/// The golden text of one run's DUT output.
std::string golden_text(const std::string& scenario, const std::string& output) {
  std::vector<std::string> lines;
  std::istringstream in(output);
  for (std::string l; std::getline(in, l);) {
    if (!l.empty() && l.back() == '\r') l.pop_back();
    if (l.rfind("$PNVBSOL,", 0) == 0) lines.push_back(l);
  }
  std::ostringstream o;
  o << "# Golden lockstep output of scenarios/" << scenario << ".yaml (navd's $PNVBSOL lines).\n"
    << "# Regenerate with scripts/update-golden after a deliberate change, in the same commit.\n"
    << "scenario " << scenario << "\n"
    << "solutions " << lines.size() << "\n"
    << "output_bytes " << output.size() << "\n"
    << "output_fnv1a64 " << hex64(fnv1a64(output)) << "\n";
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (i % kEvery == 0 || i + 1 == lines.size()) o << i << ' ' << lines[i] << '\n';
  }
  return o.str();
}

class Golden : public ::testing::TestWithParam<std::string> {};

TEST_P(Golden, LockstepOutputMatchesTheGoldenFile) {
  const std::string scenario = GetParam();
  const fs::path dir = fresh_dir("golden-" + scenario);
  const fs::path run = dir / "run";
  const ProcessResult r =
      run_navbench({"run", source_path("scenarios/" + scenario + ".yaml"), "--mode", "lockstep",
                    "-q", "-o", run.string()},
                   dir);
  ASSERT_TRUE(r.exit_code == 0 || r.exit_code == 1) << r.err;  // a check may fail; not a crash
  const std::string capture = slurp(run / "capture-rx.log");
  const auto bytes = bench::bytes_from_capture(capture, "output", (run / "capture-rx.log").string());
  ASSERT_TRUE(bytes.has_value()) << bytes.error().detail;
  const std::string now = golden_text(scenario, std::string(bytes->begin(), bytes->end()));

  expect_golden("tests/golden/" + scenario + ".golden", now, scenario + ": navd's lockstep output");
  // A run that does not match is kept, captures, DUT log and all, to see why.
  if (HasFailure()) {
    ADD_FAILURE() << "the run is kept in " << run.string();
  } else {
    fs::remove_all(dir);
  }
}

INSTANTIATE_TEST_SUITE_P(Paper, Golden, ::testing::ValuesIn(golden_scenarios()),
                         [](const ::testing::TestParamInfo<std::string>& i) {
                           std::string n = i.param;
                           for (char& c : n) {
                             if (c == '-') c = '_';
                           }
                           return n;
                         });

}  // namespace
}  // namespace nav::testing

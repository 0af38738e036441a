// SPDX-License-Identifier: MIT
// Golden lockstep regression of the paper scenarios (tests/golden/CMakeLists.txt).
//
// Each scenario runs once in lockstep (bit-reproducible); with NAV_GOLDEN_P3 (the vcan test
// golden_p3_test) the paper P3 scenarios instead, scenarios/p3-*.yaml with each navd method
// (--variant dr, ekf, ekf-kr), whose wheel encoders are on vcan0: their output also shows
// that CAN frames and serial lines reach navd in the same order on every run; with
// NAV_GOLDEN_P4 (golden_p4_test) the paper P4 scenarios, scenarios/p4-*.yaml with each navd
// method (--variant ukf, dwt-ukf), a beacon INS and a GPS on two ptys. The DUT's output line is taken from
// the run's capture-rx.log and summarised as: the number of solutions, a 64-bit FNV-1a digest
// of every output byte, and every 200th $PNVBSOL line plus the last, so a reviewer sees where
// a change shows. With NAV_UPDATE_GOLDEN=1 in the environment the test writes the golden file
// instead of comparing (scripts/update-golden does that for every scenario).
#include <algorithm>
#include <iterator>
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

#if defined(NAV_GOLDEN_P3)
constexpr const char* kPapers[] = {"p3-"};
constexpr const char* kVariants[] = {"dr", "ekf", "ekf-kr"};  // scenarios/navd/p3-<variant>.yaml
#elif defined(NAV_GOLDEN_P4)
constexpr const char* kPapers[] = {"p4-"};
constexpr const char* kVariants[] = {"ukf", "dwt-ukf"};  // scenarios/navd/p4-<variant>.yaml
#else
constexpr const char* kPapers[] = {"p0-", "p1-"};
constexpr const char* kVariants[] = {""};  // none
#endif

/// The paper scenarios, by name (scenarios/p0-*.yaml: p0-pool-* and p0-paper-*;
/// scenarios/p1-*.yaml; or scenarios/p3-*.yaml; or scenarios/p4-*.yaml), each as "<name>" or "<name>@<variant>",
/// sorted.
std::vector<std::string> golden_scenarios() {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(source_path("scenarios"))) {
    const std::string stem = e.path().stem().string();
    const bool paper = std::any_of(std::begin(kPapers), std::end(kPapers),
                                   [&](const char* p) { return stem.rfind(p, 0) == 0; });
    if (e.path().extension() != ".yaml" || !paper) continue;
    for (const char* v : kVariants) names.push_back(*v ? stem + "@" + v : stem);
  }
  std::sort(names.begin(), names.end());
  return names;
}

/// The golden text of one run's DUT output; `run` names it ("p0-pool-circle-ekf",
/// "p3-sim-ekf"), `how` says how it was run ("scenarios/p3-sim.yaml --variant ekf").
std::string golden_text(const std::string& run, const std::string& how,
                        const std::string& output) {
  std::vector<std::string> lines;
  std::istringstream in(output);
  for (std::string l; std::getline(in, l);) {
    if (!l.empty() && l.back() == '\r') l.pop_back();
    if (l.rfind("$PNVBSOL,", 0) == 0) lines.push_back(l);
  }
  std::ostringstream o;
  o << "# Golden lockstep output of " << how << " (navd's $PNVBSOL lines).\n"
    << "# Regenerate with scripts/update-golden after a deliberate change, in the same commit.\n"
    << "scenario " << run << "\n"
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
  const std::string param = GetParam();
  const std::size_t at = param.find('@');
  const std::string file = param.substr(0, at);
  const std::string variant = at == std::string::npos ? "" : param.substr(at + 1);
  const std::string scenario = variant.empty() ? file : file + "-" + variant;
  const fs::path dir = fresh_dir("golden-" + scenario);
  const fs::path run = dir / "run";
  std::vector<std::string> args{"run", source_path("scenarios/" + file + ".yaml"), "--mode",
                                "lockstep", "-q", "-o", run.string()};
  if (!variant.empty()) args.insert(args.end(), {"--variant", variant});
  const ProcessResult r = run_navbench(args, dir);
  ASSERT_TRUE(r.exit_code == 0 || r.exit_code == 1) << r.err;  // a check may fail; not a crash
  const std::string capture = slurp(run / "capture-rx.log");
  const auto bytes = bench::bytes_from_capture(capture, "output", (run / "capture-rx.log").string());
  ASSERT_TRUE(bytes.has_value()) << bytes.error().detail;
  const std::string how =
      "scenarios/" + file + ".yaml" + (variant.empty() ? "" : " --variant " + variant);
  const std::string now = golden_text(scenario, how, std::string(bytes->begin(), bytes->end()));

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
                             if (c == '-' || c == '@') c = '_';
                           }
                           return n;
                         });

}  // namespace
}  // namespace nav::testing

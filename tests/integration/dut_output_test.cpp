// SPDX-License-Identifier: MIT
// What a DUT writes that the bench cannot use: a flood of random bytes (the logs it fills are
// cut at navbench run --log-limit, and the run says so) and solutions with wrong checksums
// (the verdict and summary.json name the first ones, when they came and why).
#include <filesystem>
#include <regex>
#include <string>

#include <nlohmann/json.hpp>

#include "navbench_cli.hpp"

namespace nav::testing {
namespace {

namespace fs = std::filesystem;

TEST(NavbenchRun, LogsOfADutThatFloodsItsOutputAreCutAtTheLimitAndTheRunSaysSo) {
  const auto dir = fresh_dir("flood");
  const auto r = run_navbench({"run", source_path("tests/integration/scenarios/flood.yaml"),
                               "--out", "run", "--log-limit", "1"},
                              dir);
  ASSERT_TRUE(fs::exists(dir / "run/summary.json")) << r.out << r.err;
  constexpr std::uintmax_t kLimit = 1 << 20;
  EXPECT_LE(fs::file_size(dir / "run/capture-rx.log"), kLimit);
  // dut.log: the limit, then the bench's line saying what it cut.
  EXPECT_LE(fs::file_size(dir / "run/dut.log"), kLimit + 200);
  EXPECT_GE(fs::file_size(dir / "run/dut.log"), kLimit);
  const std::string log = slurp(dir / "run/dut.log");
  EXPECT_NE(log.find("[navbench] this log was cut at its limit of 1048576 bytes"),
            std::string::npos);

  const auto summary = nlohmann::json::parse(slurp(dir / "run/summary.json"));
  std::vector<std::string> cut;
  for (const auto& c : summary.at("logs_cut")) {
    EXPECT_EQ(c.at("limit_bytes").get<std::uint64_t>(), kLimit);
    EXPECT_GT(c.at("cut_bytes").get<std::uint64_t>(), 0u);
    cut.push_back(c.at("file").get<std::string>());
  }
  EXPECT_EQ(cut, (std::vector<std::string>{"capture-rx.log", "dut.log"}));
  for (const char* file : {"capture-rx.log", "dut.log"}) {
    EXPECT_NE(r.out.find(std::string("note: ") + file + " was cut at its limit of 1 MiB: "),
              std::string::npos)
        << r.out;
  }
}

TEST(NavbenchRun, MalformedSolutionsAreNamedWithTheirTimeAndWhy) {
  const auto dir = fresh_dir("garble");
  const auto r = run_navbench(
      {"run", source_path("tests/integration/scenarios/garble.yaml"), "--out", "run"}, dir);
  ASSERT_TRUE(fs::exists(dir / "run/summary.json")) << r.out << r.err;
  const std::regex line(
      R"re(\n    malformed at t=[0-9]+\.[0-9]{3} s: checksum 0x[0-9A-F]{2} != computed )re"
      R"re(0x[0-9A-F]{2}: "\$PNVBSOL,AHRS,[0-9]+,1,[^"]*\.\.\.[^"]*\*[0-9A-F]{2}\\r\\n \([0-9]+ bytes\)"\n)re");
  EXPECT_TRUE(std::regex_search(r.out, line)) << r.out;
  const auto summary = nlohmann::json::parse(slurp(dir / "run/summary.json"));
  const auto& dut = summary.at("dut");
  EXPECT_GT(dut.at("malformed_output").get<int>(), 10);
  ASSERT_EQ(dut.at("malformed_examples").size(), 5u);
  double last = -1.0;
  for (const auto& m : dut.at("malformed_examples")) {
    EXPECT_EQ(m.at("why").get<std::string>().rfind("checksum 0x", 0), 0u) << m;
    EXPECT_EQ(m.at("text").get<std::string>().rfind("$PNVBSOL,AHRS,", 0), 0u) << m;
    EXPECT_GT(m.at("rx_s").get<double>(), last);  // the first ones, in order
    last = m.at("rx_s").get<double>();
  }
  EXPECT_TRUE(summary.at("logs_cut").empty());
}

}  // namespace
}  // namespace nav::testing

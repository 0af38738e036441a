// SPDX-License-Identifier: MIT
// Report writers: the faults of a run in summary.json, junit.xml and on the verdict screen.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "nav/reports/run_record.hpp"

namespace nav::reports {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p) {
  std::ifstream f(p);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

RunRecord small_record() {
  RunRecord r;
  r.scenario_name = "faulty";
  r.scenario_file = "faulty.yaml";
  r.mode = "realtime";
  r.run_dir = "runs/faulty";
  r.seed = 3;
  r.duration_s = 20.0;
  r.verdict = "PASS";
  r.dut_status = "alive until the end (pid 1)";
  r.checks.push_back({"dut_alive", true, true, 1.0, 1.0, "", "the DUT ran to the end"});
  r.faults.push_back({"gps", "checksum", 10.0, 15.0, 4});
  r.faults.push_back({"ahrs", "off", 2.5, 3.0, 1});
  return r;
}

TEST(Reports, FaultTextIsOneLine) {
  EXPECT_EQ(fault_text({"gps", "checksum", 10.0, 15.0, 4}), "gps checksum 10.0\u201315.0 s, 4 messages");
  EXPECT_EQ(fault_text({"ahrs", "off", 2.5, 3.0, 1}), "ahrs off 2.5\u20133.0 s, 1 message");
}

TEST(Reports, VerdictScreenListsEveryFault) {
  const std::string text = verdict_text(small_record());
  EXPECT_NE(text.find("\n  FAULT gps checksum 10.0\u201315.0 s, 4 messages\n"), std::string::npos)
      << text;
  EXPECT_NE(text.find("\n  FAULT ahrs off 2.5\u20133.0 s, 1 message\n"), std::string::npos) << text;
  // After the checks, before the timing lines.
  EXPECT_LT(text.find("PASS  dut_alive"), text.find("FAULT gps"));
  EXPECT_LT(text.find("FAULT ahrs"), text.find("bench lateness"));
}

TEST(Reports, NoFaultsNoFaultLines) {
  RunRecord r = small_record();
  r.faults.clear();
  EXPECT_EQ(verdict_text(r).find("FAULT"), std::string::npos);
}

TEST(Reports, SummaryAndJunitCarryTheFaults) {
  const fs::path dir = fs::path(::testing::TempDir()) / "navbench_report_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  write_reports(small_record(), dir.string());
  const auto j = nlohmann::json::parse(slurp(dir / "summary.json"));
  ASSERT_EQ(j["faults"].size(), 2u);
  EXPECT_EQ(j["faults"][0]["device"], "gps");
  EXPECT_EQ(j["faults"][0]["kind"], "checksum");
  EXPECT_EQ(j["faults"][0]["start_s"], 10.0);
  EXPECT_EQ(j["faults"][0]["end_s"], 15.0);
  EXPECT_EQ(j["faults"][0]["messages_affected"], 4);
  EXPECT_EQ(j["faults"][1]["device"], "ahrs");
  const std::string junit = slurp(dir / "junit.xml");
  EXPECT_NE(junit.find("<property name=\"fault\" value=\"gps checksum 10.0\u201315.0 s, 4 "
                       "messages\"/>"),
            std::string::npos)
      << junit;
  EXPECT_NE(junit.find("<property name=\"fault\" value=\"ahrs off 2.5\u20133.0 s, 1 message\"/>"),
            std::string::npos);

  RunRecord none = small_record();
  none.faults.clear();
  write_reports(none, dir.string());
  EXPECT_TRUE(nlohmann::json::parse(slurp(dir / "summary.json"))["faults"].empty());
}

}  // namespace
}  // namespace nav::reports

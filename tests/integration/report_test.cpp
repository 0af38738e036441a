// SPDX-License-Identifier: MIT
// The run folder's report.html and `navbench report`, end to end; every vehicle's track; the
// identity of a run (hashes, host, version); JSON output that survives any byte.
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "nav/reports/sha256.hpp"
#include "navbench_cli.hpp"
#include "run_summary.hpp"

namespace nav::testing {
namespace {

namespace fs = std::filesystem;

TEST(NavbenchReport, EveryRunFolderHasItsReportAndReportRebuildsItFromTheFiles) {
  const auto dir = fresh_dir("report-run");
  const auto r = run_navbench({"run", source_path("tests/integration/scenarios/rt_pass.yaml"),
                               "--mode", "lockstep", "--out", "run"},
                              dir);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("report: run/report.html"), std::string::npos) << r.out;
  const auto run = dir / "run";
  for (const char* f : {"report.html", "device-rates.csv", "truth-uuv.tum", "estimate-uuv.tum"}) {
    EXPECT_TRUE(fs::exists(run / f)) << f;
  }
  EXPECT_EQ(slurp(run / "estimate-uuv.tum"), slurp(run / "estimate.tum"));

  // The identity the report shows is in summary.json.
  const auto s = summary(run);
  EXPECT_EQ(s["scenario"]["sha256"], reports::sha256_file((run / "scenario.yaml").string()).value());
  const std::string exe = s["dut"]["executable"];
  EXPECT_EQ(fs::path(exe).filename(), "navd");
  EXPECT_EQ(s["dut"]["sha256"], reports::sha256_file(exe).value());
  EXPECT_FALSE(s["host"]["name"].get<std::string>().empty());
  EXPECT_EQ(s["host"]["kernel"].get<std::string>().rfind("Linux ", 0), 0u);
  EXPECT_FALSE(s["versions"]["navbench"].get<std::string>().empty());
  ASSERT_EQ(s["vehicles"].size(), 1u);
  EXPECT_EQ(s["vehicles"][0]["name"], "uuv");
  EXPECT_EQ(s["vehicles"][0]["primary"], true);
  EXPECT_GT(s["vehicles"][0]["solutions"].get<int>(), 1900);
  EXPECT_LT(s["vehicles"][0]["horizontal_error_m"]["max"].get<double>(), 10.0);

  // Every second of every device: 100 AHRS packets and one GPS fix a second.
  const std::string rates = slurp(run / "device-rates.csv");
  EXPECT_EQ(rates.rfind("t_s,device,messages,bytes,bytes_dropped\n", 0), 0u);
  EXPECT_NE(rates.find("\n5,ahrs,100,"), std::string::npos) << rates.substr(0, 400);
  EXPECT_NE(rates.find("\n5,gps,1,"), std::string::npos);

  // `navbench report` makes the same page from the folder's files.
  const auto again = run_navbench({"report", "run", "-o", "again.html"}, dir);
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(again.out, "again.html\n");
  EXPECT_EQ(slurp(dir / "again.html"), slurp(run / "report.html"));
  EXPECT_EQ(run_navbench({"report", "run"}, dir).exit_code, 0);
}

TEST(NavbenchReport, NotARunFolderOrADamagedOneExitsTwoAndWritesNothing) {
  const auto dir = fresh_dir("report-bad");
  fs::create_directories(dir / "empty");
  auto r = run_navbench({"report", "empty"}, dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("empty: not a run folder (no summary.json)"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_empty(dir / "empty"));

  fs::create_directories(dir / "cut");
  std::ofstream(dir / "cut" / "summary.json") << "{\"verdict\": \"PASS\", \"scen";
  r = run_navbench({"report", "cut"}, dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("summary.json: not valid JSON"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "cut" / "report.html"));

  r = run_navbench({"report", "nowhere"}, dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("nowhere: not a folder"), std::string::npos) << r.err;

  r = run_navbench({"report", "--help"}, dir);
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("Exit codes: 0 written; 2 DIR is not a run or campaign folder"),
            std::string::npos)
      << r.out;
}

TEST(NavbenchReport, EveryVehicleOfATwoVehicleRunIsRecorded) {
  const auto dir = fresh_dir("report-vehicles");
  const auto r = run_navbench({"run", source_path("scenarios/two-vehicles-modem.yaml"), "--mode",
                               "lockstep", "--out", "run"},
                              dir);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const auto run = dir / "run";
  const auto s = summary(run);
  ASSERT_EQ(s["vehicles"].size(), 2u);
  EXPECT_EQ(s["vehicles"][0]["name"], "alpha");
  EXPECT_EQ(s["vehicles"][1]["name"], "bravo");
  EXPECT_EQ(s["vehicles"][1]["primary"], false);
  EXPECT_GT(s["vehicles"][1]["solutions"].get<int>(), 100);
  EXPECT_LT(s["vehicles"][1]["endpoint_error_m"].get<double>(), 20.0);
  for (const char* f : {"truth-alpha.tum", "estimate-alpha.tum", "truth-bravo.tum",
                        "estimate-bravo.tum"}) {
    EXPECT_GT(fs::file_size(run / f), 1000u) << f;
  }
  // bravo is 750 m from alpha: its own truth, not a copy of the primary's.
  EXPECT_NE(slurp(run / "truth-bravo.tum"), slurp(run / "truth-alpha.tum"));
  EXPECT_NE(slurp(run / "report.html").find("bravo estimate"), std::string::npos);
}

TEST(NavbenchDecode, AnyByteInACandumpLineGivesValidJson) {
  const auto dir = fresh_dir("decode-bytes");
  std::ofstream(dir / "x.log", std::ios::binary) << "(1.000000) can0 09F11223#00\xff\n"
                                                 << "(1.100000) can0 \xc3\x28#11\n";
  const auto r = run_navbench({"decode", "--protocol", "nmea2000", "x.log"}, dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::istringstream lines(r.out);
  std::size_t n = 0;
  for (std::string line; std::getline(lines, line); ++n) {
    const auto j = nlohmann::json::parse(line);  // throws (fails the test) if not valid JSON
    EXPECT_EQ(j["type"], "error") << line;
  }
  EXPECT_EQ(n, 2u) << r.out;
}

}  // namespace
}  // namespace nav::testing

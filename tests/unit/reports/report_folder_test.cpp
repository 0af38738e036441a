// SPDX-License-Identifier: MIT
// Reading run folders back: older folders, damaged ones, and folders that are not run folders.
#include <gtest/gtest.h>

#include "nav/reports/html_report.hpp"
#include "report_fixture.hpp"

namespace nav::reports {
namespace {

using namespace testing;

/// Every file of dir (names), sorted.
std::vector<std::string> files_of(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

TEST(RunFolder, ReadsWhatTheWritersWrote) {
  const auto dir = fresh_dir("read");
  const RunRecord r = synthetic_run(20, 10);
  write_reports(r, dir.string());
  const auto f = read_run_folder(dir.string());
  ASSERT_TRUE(f.has_value()) << f.error().detail;
  EXPECT_EQ(f->timeseries.rows, 200u);
  EXPECT_EQ(f->latency.rows, 200u);
  EXPECT_TRUE(f->has_rates);
  EXPECT_EQ(f->rates.texts.at("device").size(), 40u);
  ASSERT_EQ(f->vehicles.size(), 1u);
  EXPECT_EQ(f->vehicles[0].name, "auv");
  EXPECT_EQ(f->vehicles[0].truth.size(), 100u);
  EXPECT_EQ(f->vehicles[0].estimate.size(), 200u);
  EXPECT_TRUE(fs::exists(dir / "truth-auv.tum"));
  EXPECT_EQ(slurp(dir / "truth-auv.tum"), slurp(dir / "truth.tum"));
}

TEST(RunTables, NumbersAreWrittenAsPrintfWritesThemWithNineDecimals) {
  const auto dir = fresh_dir("tables");
  RunRecord r = synthetic_run(2, 10);
  auto& truth = r.vehicles.front().truth;
  truth[1].p_n = Vec3(-0.0, 1e-12, -123456.0000000005);
  truth[2].p_n = Vec3(5e15, -2.5e-10, 0.1);
  r.latency.front().tag = 18446744073709551615ull;
  write_reports(r, dir.string());
  std::vector<std::string> want;
  for (const auto& t : truth) {
    char line[400];
    std::snprintf(line, sizeof line, "%.9f %.9f %.9f %.9f %.9f %.9f %.9f %.9f", t.t_s, t.p_n.x(),
                  t.p_n.y(), t.p_n.z(), t.q_nb.x(), t.q_nb.y(), t.q_nb.z(), t.q_nb.w());
    want.push_back(line);
  }
  std::istringstream tum(slurp(dir / "truth.tum"));
  std::string line;
  std::getline(tum, line);  // the header
  for (const auto& w : want) {
    ASSERT_TRUE(std::getline(tum, line));
    EXPECT_EQ(line, w);
  }
  EXPECT_FALSE(std::getline(tum, line));
  std::istringstream latency(slurp(dir / "latency.csv"));
  std::getline(latency, line);
  std::getline(latency, line);
  EXPECT_EQ(line.substr(0, line.find(',')), "18446744073709551615");
}

TEST(RunFolder, AnOlderRunFolderIsReportedWithWhatItLacksMarked) {
  const auto dir = fresh_dir("older");
  write_reports(synthetic_run(20, 10), dir.string());
  // What a run folder of the previous navbench held: no rates, no per-vehicle files, no
  // hashes, host, vehicles or check kinds in its summary.
  fs::remove(dir / "device-rates.csv");
  fs::remove(dir / "truth-auv.tum");
  fs::remove(dir / "estimate-auv.tum");
  auto j = nlohmann::json::parse(slurp(dir / "summary.json"));
  j.erase("host");
  j.erase("vehicles");
  j["scenario"].erase("sha256");
  j["dut"].erase("sha256");
  j["dut"].erase("executable");
  for (auto& c : j["checks"]) {
    for (const char* k : {"kind", "req", "title", "per_distance", "after_s", "worst_t_s"}) c.erase(k);
  }
  std::ofstream(dir / "summary.json") << j.dump(2);
  ASSERT_TRUE(write_report(dir.string()).has_value());
  const std::string html = slurp(dir / "report.html");
  EXPECT_NE(html.find("not recorded"), std::string::npos);
  EXPECT_NE(html.find("device-rates.csv not recorded"), std::string::npos);
  const auto plots = embedded_plots(html);
  EXPECT_NE(plot_by_id(plots, "plot-track"), nullptr);   // from truth.tum / estimate.tum
  EXPECT_NE(plot_by_id(plots, "plot-check-0"), nullptr); // the check found by its name
}

TEST(RunFolder, NotARunFolderIsRefusedAndNothingWritten) {
  const auto dir = fresh_dir("empty");
  const auto r = write_report(dir.string());
  ASSERT_FALSE(r.has_value());
  EXPECT_NE(r.error().detail.find("not a run folder"), std::string::npos) << r.error().detail;
  EXPECT_TRUE(files_of(dir).empty());
  const auto missing = write_report((dir / "nope").string());
  ASSERT_FALSE(missing.has_value());
  EXPECT_NE(missing.error().detail.find("not a folder"), std::string::npos);
}

TEST(RunFolder, DamagedFilesAreRefusedByNameAndLineAndNothingWritten) {
  const auto dir = fresh_dir("damaged");
  write_reports(synthetic_run(20, 10), dir.string());
  const auto before = files_of(dir);
  const std::string good = slurp(dir / "summary.json");

  std::ofstream(dir / "summary.json") << good.substr(0, good.size() / 2);  // cut short
  auto r = write_report(dir.string());
  ASSERT_FALSE(r.has_value());
  EXPECT_NE(r.error().detail.find("summary.json: not valid JSON"), std::string::npos) << r.error().detail;

  std::ofstream(dir / "summary.json") << R"({"verdict": 5, "scenario": {"name": "x"}})";
  r = write_report(dir.string());
  ASSERT_FALSE(r.has_value());
  EXPECT_NE(r.error().detail.find("no \"verdict\""), std::string::npos);

  std::ofstream(dir / "summary.json") << good;
  {
    std::ofstream csv(dir / "latency.csv", std::ios::app);
    csv << "12,1.0,garbage,,,0\n";
  }
  r = write_report(dir.string());
  ASSERT_FALSE(r.has_value());
  EXPECT_NE(r.error().detail.find("latency.csv:202: column wire_end_s"), std::string::npos)
      << r.error().detail;

  std::ofstream(dir / "latency.csv") << "tag,t_valid_s\n1,2,3\n";
  r = write_report(dir.string());
  ASSERT_FALSE(r.has_value());
  EXPECT_NE(r.error().detail.find("latency.csv:2: expected 2 fields, got 3"), std::string::npos);

  std::ofstream(dir / "latency.csv") << "tag\n";
  std::ofstream(dir / "truth.tum") << "# header\n1 2 3\n";
  r = write_report(dir.string());
  ASSERT_FALSE(r.has_value());
  EXPECT_NE(r.error().detail.find("truth"), std::string::npos);
  EXPECT_EQ(files_of(dir), before);  // no report.html, no temporary file
}

TEST(RunFolder, WrongTypesInASummaryDoNotCrashTheReport) {
  const auto dir = fresh_dir("types");
  write_reports(synthetic_run(10, 10), dir.string());
  auto j = nlohmann::json::parse(slurp(dir / "summary.json"));
  j["seed"] = "not a number";
  j["checks"][0]["value"] = "x";
  j["checks"][1] = 17;
  j["devices"] = "none";
  j["faults"][0]["start_s"] = nullptr;
  j["dut"]["command"] = {1, 2, {{"a", "b"}}};
  j["labels"] = {1, 2};
  std::ofstream(dir / "summary.json") << j.dump();
  const auto r = write_report(dir.string(), (dir / "other.html").string());
  ASSERT_TRUE(r.has_value()) << r.error().detail;
  EXPECT_EQ(*r, (dir / "other.html").string());
  EXPECT_GT(fs::file_size(dir / "other.html"), 10000u);
  EXPECT_FALSE(fs::exists(dir / "report.html"));
}

TEST(CsvAndTum, ParseTheBenchsOwnFormats) {
  const auto dir = fresh_dir("csv");
  std::ofstream(dir / "a.csv") << "device,x_s,y\r\nahrs,1.5,\r\ngps,-2e-3,7\r\n";
  const auto t = read_csv((dir / "a.csv").string(), {"device"});
  ASSERT_TRUE(t.has_value()) << t.error().detail;
  EXPECT_EQ(t->rows, 2u);
  EXPECT_EQ(t->texts.at("device")[1], "gps");
  EXPECT_EQ((*t)["x_s"][1], -2e-3);
  EXPECT_TRUE(std::isnan((*t)["y"][0]));
  EXPECT_TRUE((*t)["missing"].empty());
  std::ofstream(dir / "a.tum") << "# c\n1 2 3 4 0 0 0 1\n\n";
  const auto tum = read_tum((dir / "a.tum").string());
  ASSERT_TRUE(tum.has_value());
  ASSERT_EQ(tum->size(), 1u);
  EXPECT_EQ((*tum)[0].e, 3.0);
  std::ofstream(dir / "b.tum") << "1 2 3 4 0 0 0 nan\n";
  EXPECT_FALSE(read_tum((dir / "b.tum").string()).has_value());
  // The last line without its newline is a line; an empty file has no header.
  std::ofstream(dir / "c.csv") << "x,y\n1,2\n3,4";
  const auto c = read_csv((dir / "c.csv").string(), {});
  ASSERT_TRUE(c.has_value()) << c.error().detail;
  EXPECT_EQ(c->rows, 2u);
  EXPECT_EQ((*c)["y"][1], 4.0);
  std::ofstream(dir / "d.csv") << "";
  const auto d = read_csv((dir / "d.csv").string(), {});
  ASSERT_FALSE(d.has_value());
  EXPECT_NE(d.error().detail.find("d.csv:1: empty file"), std::string::npos) << d.error().detail;
  EXPECT_FALSE(read_csv((dir / "none.csv").string(), {}).has_value());
}

}  // namespace
}  // namespace nav::reports

// SPDX-License-Identifier: MIT
// `navbench campaign` end to end: two small lockstep scenarios (tests/integration/scenarios/
// campaign/, navd configured from beside them through {scenario_dir}) × 3 seeds, 2 at a time;
// the table checked against the runs' own summary.json; determinism of a seed; usage and
// scenario errors refused before anything is created.
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "navbench_cli.hpp"

namespace nav::testing {
namespace {

namespace fs = std::filesystem;

const std::string kStraight = "tests/integration/scenarios/campaign/straight_default.yaml";
const std::string kArc = "tests/integration/scenarios/campaign/arc_stiff.yaml";
const std::string kMalformed = "tests/integration/scenarios/campaign/malformed_label.yaml";

nlohmann::json load_json(const fs::path& p) { return nlohmann::json::parse(slurp(p)); }

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(s);
  while (std::getline(in, item, sep)) out.push_back(item);
  return out;
}

std::string three_decimals(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", v);
  return buf;
}

/// The value of the check named `name` in a summary.json.
double check_value(const nlohmann::json& summary, const std::string& name) {
  for (const auto& c : summary["checks"]) {
    if (c["name"] == name) return c["value"].get<double>();
  }
  ADD_FAILURE() << "no check " << name;
  return NAN;
}

TEST(NavbenchCampaign, ComparesTwoScenariosOverThreeSeeds) {
  const auto dir = fresh_dir("campaign");
  const auto r = run_navbench({"campaign", source_path(kStraight), source_path(kArc), "--seeds",
                               "3", "-j", "2", "-o", "out"},
                              dir);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const fs::path out = dir / "out";
  for (const char* f : {"campaign.json", "comparison.csv", "comparison.md", "campaign.html"}) {
    EXPECT_TRUE(fs::exists(out / f)) << f;
  }
  for (const auto& e : fs::directory_iterator(out)) {
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
  }
  // The campaign report links every run's own report by a relative path.
  const std::string html = slurp(out / "campaign.html");
  for (const char* run : {"runs/it-campaign-straight-s1/report.html", "runs/it-campaign-arc-s3/report.html"}) {
    EXPECT_NE(html.find(std::string("<a href=\"") + run + "\">report</a>"), std::string::npos) << run;
    EXPECT_TRUE(fs::exists(out / run)) << run;
  }

  // One progress line per run on stderr.
  const std::regex progress(
      R"(\[([1-6])/6\] (it-campaign-straight|it-campaign-arc) seed ([1-3]): PASS endpoint \d+\.\d{3} m \(\d+\.\d s\)\n)");
  std::size_t lines = 0;
  for (std::sregex_iterator it(r.err.begin(), r.err.end(), progress), end; it != end; ++it) {
    ++lines;
  }
  EXPECT_EQ(lines, 6u) << r.err;

  // Every run's summary.json: the campaign's seed, the scenario's labels, {scenario_dir}
  // expanded to the folder of the scenario (navd read its configuration from there).
  const auto campaign = load_json(out / "campaign.json");
  EXPECT_EQ(campaign["seeds"]["first"], 1);
  EXPECT_EQ(campaign["seeds"]["last"], 3);
  EXPECT_EQ(campaign["mode"], "lockstep");
  EXPECT_EQ(campaign["complete"], true);
  EXPECT_EQ(campaign["exit_code"], 0);
  EXPECT_NE(campaign["command_line"].get<std::string>().find("--seeds 3 -j 2 -o out"),
            std::string::npos);
  ASSERT_EQ(campaign["runs"].size(), 6u);
  std::map<std::string, std::map<std::uint64_t, double>> endpoint;  // scenario -> seed -> m
  std::map<std::string, std::vector<double>> vertical, attitude;  // scenario -> runs' figures
  for (const auto& run : campaign["runs"]) {
    SCOPED_TRACE(run.dump());
    EXPECT_EQ(run["status"], "finished");
    EXPECT_EQ(run["exit_code"], 0);
    EXPECT_EQ(run["verdict"], "PASS");
    const fs::path folder = out / run["run_folder"].get<std::string>();
    ASSERT_TRUE(fs::exists(folder / "summary.json"));
    EXPECT_FALSE(fs::exists(folder.string() + ".partial"));
    const auto s = load_json(folder / "summary.json");
    EXPECT_EQ(s["seed"], run["seed"]);
    EXPECT_EQ(s["labels"], run["labels"]);
    const std::string name = run["scenario"];
    const bool arc = name == "it-campaign-arc";
    const double v = check_value(s, arc ? "final_position" : "endpoint_error");
    EXPECT_EQ(run["endpoint_error_m"].get<double>(), v);
    endpoint[name][run["seed"].get<std::uint64_t>()] = v;
    vertical[name].push_back(s["vehicles"][0]["vertical_error_m"]["final"].get<double>());
    attitude[name].push_back(s["vehicles"][0]["attitude_error_deg"]["mean"].get<double>());
    const std::string config = s["dut"]["command"][2];
    EXPECT_EQ(config, fs::path(source_path(arc ? kArc : kStraight)).parent_path().string() +
                          (arc ? "/navd-stiff.yaml" : "/navd-default.yaml"));
  }
  EXPECT_EQ(campaign["runs"][0]["labels"],
            nlohmann::json({{"path", "straight"}, {"gains", "default"}}));
  ASSERT_EQ(endpoint.size(), 2u);

  // Different seeds, different endpoint errors.
  for (const auto& [name, by_seed] : endpoint) {
    ASSERT_EQ(by_seed.size(), 3u) << name;
    EXPECT_NE(by_seed.at(1), by_seed.at(2)) << name;
    EXPECT_NE(by_seed.at(2), by_seed.at(3)) << name;
  }

  // The table: both rows, runs = 3, mean and sample std recomputed from the summaries.
  const auto csv = split(slurp(out / "comparison.csv"), '\n');
  ASSERT_EQ(csv.size(), 3u) << slurp(out / "comparison.csv");
  EXPECT_EQ(csv[0],
            "path,gains,motion,scenario,runs,passed,endpoint_error_mean_m,endpoint_error_std_m,"
            "endpoint_error_min_m,endpoint_error_max_m,endpoint_horizontal_mean_m,"
            "endpoint_horizontal_std_m,endpoint_vertical_mean_m,endpoint_vertical_std_m,"
            "mean_position_error_mean_m,mean_position_error_std_m,mean_attitude_error_mean_deg,"
            "mean_attitude_error_std_deg");
  const std::string md = slurp(out / "comparison.md");
  for (std::size_t row = 1; row <= 2; ++row) {
    const auto f = split(csv[row], ',');
    ASSERT_EQ(f.size(), 18u) << csv[row];
    const std::string name = f[3];
    ASSERT_TRUE(endpoint.count(name)) << csv[row];
    std::vector<double> v;
    for (const auto& [seed, value] : endpoint[name]) v.push_back(value);
    const double mean = (v[0] + v[1] + v[2]) / 3.0;
    double ss = 0.0;
    for (const double x : v) ss += (x - mean) * (x - mean);
    const double sd = std::sqrt(ss / 2.0);
    EXPECT_EQ(f[4], "3");
    EXPECT_EQ(f[5], "3");
    EXPECT_EQ(f[6], three_decimals(mean)) << name;
    EXPECT_EQ(f[7], three_decimals(sd)) << name;
    EXPECT_EQ(f[8], three_decimals(*std::min_element(v.begin(), v.end())));
    EXPECT_EQ(f[9], three_decimals(*std::max_element(v.begin(), v.end())));
    // The summaries' figures: the vertical part of the final error, the mean attitude error.
    const auto mean_of = [](const std::vector<double>& x) {
      return (x[0] + x[1] + x[2]) / 3.0;
    };
    EXPECT_EQ(f[12], three_decimals(mean_of(vertical[name]))) << name;
    EXPECT_EQ(f[16], three_decimals(mean_of(attitude[name]))) << name;
    const std::string md_row = " | " + name + " | 3 | 3 | " + three_decimals(mean) + " \u00b1 " +
                               three_decimals(sd) + " | ";
    EXPECT_NE(md.find(md_row), std::string::npos) << md_row << "\n" << md;
    EXPECT_NE(r.out.find(md_row), std::string::npos) << r.out;
  }
  EXPECT_EQ(csv[1].rfind("straight,default,,it-campaign-straight,", 0), 0u) << csv[1];
  EXPECT_EQ(csv[2].rfind("arc,stiff,rolling,it-campaign-arc,", 0), 0u) << csv[2];
  EXPECT_NE(md.find("campaign " + source_path(kStraight)), std::string::npos) << md;
  EXPECT_NE(md.find("Seeds 1\u20133 (3 per scenario)"), std::string::npos) << md;
  // Every error check's value: the straight scenario's endpoint_error row is the same figure.
  bool found = false;
  for (const auto& v : campaign["check_values"]) {
    if (v["scenario"] != "it-campaign-straight" || v["check"] != "endpoint_error") continue;
    found = true;
    EXPECT_EQ(v["unit"], "m");
    EXPECT_EQ(v["values"]["n"], 3);
    std::vector<double> e;
    for (const auto& [seed, value] : endpoint["it-campaign-straight"]) e.push_back(value);
    EXPECT_NEAR(v["values"]["mean"].get<double>(), (e[0] + e[1] + e[2]) / 3.0, 1e-12);
  }
  EXPECT_TRUE(found) << campaign["check_values"].dump();
  EXPECT_NE(md.find("| it-campaign-straight | \u2014 | endpoint_error [m] | 3 | "),
            std::string::npos) << md;
  EXPECT_NE(r.out.find("Every error check's value"), std::string::npos) << r.out;
  EXPECT_NE(html.find("<section id=\"check-values\">"), std::string::npos);

  // Determinism: seed 2 again, alone, gives the identical value.
  const auto again = run_navbench(
      {"campaign", source_path(kStraight), "--first-seed", "2", "--seeds", "1", "-o", "again", "-q"},
      dir);
  ASSERT_EQ(again.exit_code, 0) << again.out << again.err;
  EXPECT_TRUE(again.err.empty()) << again.err;  // -q: no progress lines
  const auto second = load_json(dir / "again" / "campaign.json");
  ASSERT_EQ(second["runs"].size(), 1u);
  EXPECT_EQ(second["runs"][0]["seed"], 2);
  EXPECT_EQ(second["runs"][0]["endpoint_error_m"].get<double>(),
            endpoint["it-campaign-straight"][2]);
}

TEST(NavbenchCampaign, UsageAndScenarioErrorsRunNothing) {
  const auto dir = fresh_dir("campaign-errors");
  const auto zero = run_navbench({"campaign", source_path(kStraight), "--seeds", "0", "-o", "out"},
                                 dir);
  EXPECT_EQ(zero.exit_code, 2) << zero.err;
  EXPECT_NE(zero.err.find("--seeds must be at least 1"), std::string::npos) << zero.err;
  EXPECT_FALSE(fs::exists(dir / "out"));

  const std::string missing = (dir / "no-such.yaml").string();
  const auto absent =
      run_navbench({"campaign", source_path(kStraight), missing, "--seeds", "2", "-o", "out"}, dir);
  EXPECT_EQ(absent.exit_code, 2) << absent.err;
  EXPECT_NE(absent.err.find(missing + ": cannot open"), std::string::npos) << absent.err;
  EXPECT_FALSE(fs::exists(dir / "out"));

  // Every scenario is validated before the first run: the valid one first is not run either.
  const auto bad = run_navbench(
      {"campaign", source_path(kStraight), source_path(kMalformed), "--seeds", "2", "-o", "out"},
      dir);
  EXPECT_EQ(bad.exit_code, 2) << bad.err;
  EXPECT_EQ(bad.err.rfind("navbench: " + source_path(kMalformed) + ":5:", 0), 0u) << bad.err;
  EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
  EXPECT_FALSE(fs::exists(dir / "out"));
  EXPECT_TRUE(bad.out.empty()) << bad.out;

  // The campaign folder must not exist.
  fs::create_directories(dir / "taken");
  const auto taken =
      run_navbench({"campaign", source_path(kStraight), "--seeds", "1", "-o", "taken"}, dir);
  EXPECT_EQ(taken.exit_code, 2) << taken.err;
  EXPECT_TRUE(fs::is_empty(dir / "taken"));
}

// Two campaigns in one folder at once: the second is refused while the first holds it, and
// touches nothing (here the test holds the folder's lock as a running campaign does).
TEST(NavbenchCampaign, ACampaignFolderInUseIsRefused) {
  const auto dir = fresh_dir("campaign-busy");
  const std::vector<std::string> args = {"campaign", source_path(kStraight), "--seeds", "1",
                                         "-o", "out", "-q"};
  const auto first = run_navbench(args, dir);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  const std::string table = slurp(dir / "out" / "comparison.md");
  fs::remove_all(dir / "out" / "runs" / "it-campaign-straight-s1");  // something left to run

  const int fd = ::open((dir / "out").c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
  const auto busy = run_navbench(args, dir);
  EXPECT_EQ(busy.exit_code, 2) << busy.err;
  EXPECT_NE(busy.err.find("is in use by another navbench campaign"), std::string::npos)
      << busy.err;
  EXPECT_EQ(slurp(dir / "out" / "comparison.md"), table);
  EXPECT_TRUE(fs::is_empty(dir / "out" / "runs"));
  ::close(fd);

  // Released: the same command resumes it.
  const auto again = run_navbench(args, dir);
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_TRUE(fs::exists(dir / "out" / "runs" / "it-campaign-straight-s1" / "result.json"));
}

}  // namespace
}  // namespace nav::testing

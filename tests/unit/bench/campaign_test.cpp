// SPDX-License-Identifier: MIT
// The pure parts of `navbench campaign` (statistics, comparison rows, CSV and markdown, the
// endpoint error read from a summary.json, the exit code) and of the scenario keys it relies
// on: labels and the {scenario_dir} placeholder.
#include "nav/bench/campaign.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "nav/bench/runner.hpp"
#include "nav/bench/scenario.hpp"

namespace nav::bench {
namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// sample_stats

TEST(SampleStats, EmptyIsAllUndefined) {
  const auto s = sample_stats({});
  EXPECT_EQ(s.n, 0u);
  EXPECT_TRUE(std::isnan(s.mean));
  EXPECT_TRUE(std::isnan(s.stddev));
  EXPECT_TRUE(std::isnan(s.min));
  EXPECT_TRUE(std::isnan(s.max));
}

TEST(SampleStats, OneValueHasNoStandardDeviation) {
  const auto s = sample_stats({0.412});
  EXPECT_EQ(s.n, 1u);
  EXPECT_DOUBLE_EQ(s.mean, 0.412);
  EXPECT_TRUE(std::isnan(s.stddev));
  EXPECT_DOUBLE_EQ(s.min, 0.412);
  EXPECT_DOUBLE_EQ(s.max, 0.412);
}

TEST(SampleStats, SampleStandardDeviationDividesByNMinusOne) {
  // 2, 4, 4, 4, 5, 5, 7, 9: mean 5, sum of squares 32, sample variance 32/7.
  const auto s = sample_stats({2, 4, 4, 4, 5, 5, 7, 9});
  EXPECT_EQ(s.n, 8u);
  EXPECT_DOUBLE_EQ(s.mean, 5.0);
  EXPECT_DOUBLE_EQ(s.stddev, std::sqrt(32.0 / 7.0));
  EXPECT_DOUBLE_EQ(s.min, 2.0);
  EXPECT_DOUBLE_EQ(s.max, 9.0);
  const auto two = sample_stats({1.0, 2.0});
  EXPECT_DOUBLE_EQ(two.stddev, std::sqrt(0.5));
  EXPECT_DOUBLE_EQ(sample_stats({3.0, 3.0, 3.0}).stddev, 0.0);
}

// ---------------------------------------------------------------------------------------------
// comparison rows, CSV, markdown

CampaignRun run(const std::string& scenario, std::uint64_t seed, int exit_code,
                std::optional<double> endpoint, bool finished = true) {
  CampaignRun r;
  r.scenario = scenario;
  r.seed = seed;
  r.started = true;
  r.finished = finished;
  r.exit_code = exit_code;
  r.endpoint_error_m = endpoint;
  return r;
}

const std::vector<std::pair<std::string, Labels>> kScenarios{
    {"circle-ekf", {{"path", "circle"}, {"attitude", "ekf"}}},
    {"line-cf", {{"attitude", "cf"}, {"speed", "1,5 kn"}}},
    {"bare", {}}};

TEST(ComparisonRows, OneRowPerScenarioOverItsFinishedRuns) {
  const std::vector<CampaignRun> runs{
      run("circle-ekf", 1, 0, 1.0), run("line-cf", 1, 1, 4.0), run("bare", 1, 0, std::nullopt),
      run("circle-ekf", 2, 1, 3.0), run("line-cf", 2, 4, 0.1),  // crashed: no statistics
      run("circle-ekf", 3, 0, 2.0), run("line-cf", 3, 3, std::nullopt, false)};  // interrupted
  const auto rows = comparison_rows(kScenarios, runs);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].scenario, "circle-ekf");
  EXPECT_EQ(rows[0].runs, 3u);
  EXPECT_EQ(rows[0].passed, 2u);
  EXPECT_EQ(rows[0].endpoint.n, 3u);
  EXPECT_DOUBLE_EQ(rows[0].endpoint.mean, 2.0);
  EXPECT_DOUBLE_EQ(rows[0].endpoint.stddev, 1.0);
  EXPECT_EQ(rows[1].runs, 2u);  // the interrupted run is not counted
  EXPECT_EQ(rows[1].passed, 0u);
  EXPECT_EQ(rows[1].endpoint.n, 1u);  // the crashed run's value is not a comparable endpoint
  EXPECT_DOUBLE_EQ(rows[1].endpoint.mean, 4.0);
  EXPECT_EQ(rows[2].runs, 1u);
  EXPECT_EQ(rows[2].endpoint.n, 0u);
  EXPECT_EQ(label_columns(rows), (std::vector<std::string>{"path", "attitude", "speed"}));
}

TEST(ComparisonTable, CsvHasLabelColumnsFirstAndEmptyFieldsForUndefined) {
  std::vector<CampaignRun> runs{run("circle-ekf", 1, 0, 0.412), run("circle-ekf", 2, 0, 0.5),
                                run("line-cf", 1, 1, 3.25)};
  // Figures: horizontal 0.33 and 0.47 (mean 0.4, std 0.099), vertical in one run only (no
  // std), no mean position error, mean attitude 1 and 2 deg (mean 1.5, std 0.707).
  runs[0].figures.endpoint_horizontal_m = 0.33;
  runs[1].figures.endpoint_horizontal_m = 0.47;
  runs[0].figures.endpoint_vertical_m = 0.2;
  runs[0].figures.mean_attitude_deg = 1.0;
  runs[1].figures.mean_attitude_deg = 2.0;
  const auto csv = comparison_csv(comparison_rows(kScenarios, runs));
  EXPECT_EQ(csv,
            "path,attitude,speed,scenario,runs,passed,endpoint_error_mean_m,endpoint_error_std_m,"
            "endpoint_error_min_m,endpoint_error_max_m,endpoint_horizontal_mean_m,"
            "endpoint_horizontal_std_m,endpoint_vertical_mean_m,endpoint_vertical_std_m,"
            "mean_position_error_mean_m,mean_position_error_std_m,mean_attitude_error_mean_deg,"
            "mean_attitude_error_std_deg\n"
            "circle,ekf,,circle-ekf,2,2,0.456,0.062,0.412,0.500,0.400,0.099,0.200,,,,1.500,0.707\n"
            ",cf,\"1,5 kn\",line-cf,1,0,3.250,,3.250,3.250,,,,,,,,\n"
            ",,,bare,0,0,,,,,,,,,,,,\n");
}

TEST(ComparisonTable, MarkdownShowsMeanPlusMinusStdAndDashes) {
  const std::vector<CampaignRun> runs{run("circle-ekf", 1, 0, 0.412), run("circle-ekf", 2, 0, 0.5),
                                      run("line-cf", 1, 1, 3.25)};
  const auto md = comparison_markdown(comparison_rows(kScenarios, runs));
  EXPECT_EQ(md,
            "| path | attitude | speed | scenario | runs | passed | endpoint error [m] mean \u00b1 "
            "std | min [m] | max [m] | horizontal [m] | vertical [m] | mean position error [m] |"
            " mean attitude error [deg] |\n"
            "|---|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n"
            "| circle | ekf | \u2014 | circle-ekf | 2 | 2 | 0.456 \u00b1 0.062 | 0.412 | 0.500 |"
            " \u2014 | \u2014 | \u2014 | \u2014 |\n"
            "| \u2014 | cf | 1,5 kn | line-cf | 1 | 0 | 3.250 \u00b1 \u2014 | 3.250 | 3.250 |"
            " \u2014 | \u2014 | \u2014 | \u2014 |\n"
            "| \u2014 | \u2014 | \u2014 | bare | 0 | 0 | \u2014 | \u2014 | \u2014 |"
            " \u2014 | \u2014 | \u2014 | \u2014 |\n");
}

TEST(ComparisonTable, MarkdownEscapesPipes) {
  const auto md = comparison_markdown(comparison_rows({{"a", {{"note", "x|y"}}}}, {}));
  EXPECT_NE(md.find("| x\\|y | a |"), std::string::npos) << md;
}

// ---------------------------------------------------------------------------------------------
// endpoint error from summary.json, exit codes, command line

nlohmann::json summary_with(const nlohmann::json& check) {
  return {{"verdict", "PASS"}, {"checks", nlohmann::json::array({check})}};
}

TEST(EndpointFromSummary, TakesTheNamedCheckValue) {
  const nlohmann::json c{{"name", "final"}, {"judged", true}, {"passed", true},
                         {"value", 0.75},   {"limit", 3.0},   {"unit", "m"}};
  EXPECT_EQ(endpoint_error_from_summary(summary_with(c), "final"), 0.75);
  EXPECT_FALSE(endpoint_error_from_summary(summary_with(c), "endpoint_error"));
  nlohmann::json failed = c;
  failed["passed"] = false;
  failed["value"] = 4.5;  // over the limit: measured
  EXPECT_EQ(endpoint_error_from_summary(summary_with(failed), "final"), 4.5);
}

TEST(EndpointFromSummary, NothingMeasuredWhenNotJudgedOrNoSolutions) {
  // judge.cpp with no solution to judge: failed, value 0 (within the limit).
  const nlohmann::json none{{"name", "endpoint_error"}, {"judged", true}, {"passed", false},
                            {"value", 0.0}, {"limit", 3.0}};
  EXPECT_FALSE(endpoint_error_from_summary(summary_with(none), "endpoint_error"));
  nlohmann::json skipped = none;
  skipped["judged"] = false;
  EXPECT_FALSE(endpoint_error_from_summary(summary_with(skipped), "endpoint_error"));
  EXPECT_FALSE(endpoint_error_from_summary(nlohmann::json::object(), "endpoint_error"));
}

TEST(RunFiguresFromSummary, ReadsThePrimaryVehiclesFigures) {
  const nlohmann::json s = {
      {"vehicles",
       {{{"name", "rig"},
         {"horizontal_error_m", {{"max", 3.0}, {"mean", 1.0}, {"final", 2.5}}},
         {"vertical_error_m", {{"max", 1.0}, {"mean", 0.5}, {"final", 0.75}}},
         {"position_error_m", {{"max", 3.5}, {"mean", 1.25}, {"final", 2.6}}},
         {"attitude_error_deg", nullptr}},
        {{"name", "peer"}, {"horizontal_error_m", {{"final", 99.0}}}}}}};
  const RunFigures f = run_figures_from_summary(s);
  // Every vehicle's mean position error, the ones that judged no solution left out.
  EXPECT_EQ(f.vehicle_mean_position_m,
            (std::vector<std::pair<std::string, double>>{{"rig", 1.25}}));
  EXPECT_EQ(f.endpoint_horizontal_m, 2.5);
  EXPECT_EQ(f.endpoint_vertical_m, 0.75);
  EXPECT_EQ(f.mean_position_m, 1.25);
  EXPECT_FALSE(f.mean_attitude_deg);  // no solution judged: null in the summary
  EXPECT_EQ(run_figures_from_summary(nlohmann::json::object()), RunFigures{});
  EXPECT_EQ(run_figures_from_summary(nlohmann::json{{"vehicles", 3}}), RunFigures{});
}

CampaignRun fleet_run(const std::string& cell, int exit_code,
                      std::vector<std::pair<std::string, double>> vehicles) {
  CampaignRun r = run(cell, 1, exit_code, std::nullopt);
  r.figures.vehicle_mean_position_m = std::move(vehicles);
  return r;
}

TEST(VehicleRows, EveryVehicleAndTheirMeanAgainstTheBaselineVariant) {
  const std::vector<CampaignCell> cells{{"pair-nav", "nav", ""},
                                       {"pair-fix", "fix", "pair-nav"},
                                       {"solo-nav", "nav", ""}};
  const std::vector<CampaignRun> runs{
      fleet_run("pair-nav", 1, {{"a", 10.0}, {"b", 30.0}}),
      fleet_run("pair-nav", 0, {{"a", 14.0}, {"b", 34.0}}),
      fleet_run("pair-fix", 0, {{"a", 9.0}, {"b", 11.0}}),
      fleet_run("pair-fix", 4, {{"a", 0.0}, {"b", 0.0}}),  // crashed: not counted
      fleet_run("solo-nav", 0, {{"rig", 1.0}})};           // one vehicle: no rows
  const auto rows = vehicle_rows(cells, runs);
  ASSERT_EQ(rows.size(), 6u);
  EXPECT_EQ(rows[0].vehicle, "a");
  EXPECT_DOUBLE_EQ(rows[0].mean_position.mean, 12.0);
  EXPECT_FALSE(rows[0].improvement_pct);  // the baseline itself
  EXPECT_EQ(rows[2].vehicle, "all");
  EXPECT_DOUBLE_EQ(rows[2].mean_position.mean, 22.0);  // runs' means 20 and 24
  EXPECT_EQ(rows[3].cell, "pair-fix");
  EXPECT_EQ(rows[3].mean_position.n, 1u);
  EXPECT_DOUBLE_EQ(*rows[3].improvement_pct, 100.0 * (12.0 - 9.0) / 12.0);
  EXPECT_DOUBLE_EQ(*rows[4].improvement_pct, 100.0 * (32.0 - 11.0) / 32.0);
  EXPECT_DOUBLE_EQ(*rows[5].improvement_pct, 100.0 * (22.0 - 10.0) / 22.0);
  const std::string md = vehicle_markdown(rows);
  EXPECT_NE(md.find("| pair-fix | fix | b | 1 | 11.000 ± — | +65.6 % (vs pair-nav) |"),
            std::string::npos)
      << md;
  // Single-vehicle campaigns have no such table.
  EXPECT_TRUE(vehicle_rows({{"solo-nav", "", ""}}, runs).empty());
  EXPECT_EQ(vehicle_markdown({}), "");
}

TEST(CampaignExitCode, WorstWins) {
  EXPECT_EQ(campaign_exit_code({}), kExitPass);
  EXPECT_EQ(campaign_exit_code({0, 0}), kExitPass);
  EXPECT_EQ(campaign_exit_code({0, 1, 0}), kExitFail);
  EXPECT_EQ(campaign_exit_code({1, 3, 1}), kExitBench);
  EXPECT_EQ(campaign_exit_code({3, 4, 1}), kExitDut);
  EXPECT_EQ(campaign_exit_code({4, 3}), kExitDut);
  EXPECT_EQ(campaign_exit_code({1, 2}), kExitBench);  // a run's usage error is the bench's
  EXPECT_EQ(campaign_exit_code({0, 77}), kExitBench);
}

TEST(CommandLine, QuotesWhatTheShellWouldSplit) {
  EXPECT_EQ(command_line({"navbench", "campaign", "a.yaml", "--seeds", "3", "-o", "out/x"}),
            "navbench campaign a.yaml --seeds 3 -o out/x");
  EXPECT_EQ(command_line({"navbench", "my scenario.yaml", "it's", ""}),
            "navbench 'my scenario.yaml' 'it'\\''s' ''");
}

// ---------------------------------------------------------------------------------------------
// Scenario keys: labels and {scenario_dir}

std::string write_temp(const fs::path& rel, const std::string& text) {
  const fs::path p = fs::path(::testing::TempDir()) / "navbench_campaign_test" / rel;
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
  return p.string();
}

std::string scenario_text(const std::string& extra, const std::string& command) {
  return "name: labelled\n" + extra +
         "seed: 7\n"
         "duration: 10 s\n"
         "datum: {lat: 36.38, lon: 127.36}\n"
         "vehicle:\n"
         "  path:\n"
         "    - {straight: 10 m, speed: 1 m/s}\n"
         "  devices:\n"
         "    - {name: ahrs, type: microstrain-gx3-25}\n"
         "dut:\n"
         "  command: " + command + "\n"
         "  trigger: ahrs\n";
}

const std::string kCommand = R"([navd, --ahrs, "{port:ahrs}"])";

TEST(ScenarioLabels, KeptInFileOrder) {
  const auto s = load_scenario(write_temp(
      "labels.yaml",
      scenario_text("labels: {path: circle, attitude: ekf, run.id: \"3\", k: 12}\n", kCommand)));
  ASSERT_TRUE(s) << s.error().detail;
  EXPECT_EQ(s->labels, (Labels{{"path", "circle"}, {"attitude", "ekf"}, {"run.id", "3"},
                               {"k", "12"}}));
}

TEST(ScenarioLabels, OptionalAndMayBeEmpty) {
  const auto none = load_scenario(write_temp("no-labels.yaml", scenario_text("", kCommand)));
  ASSERT_TRUE(none) << none.error().detail;
  EXPECT_TRUE(none->labels.empty());
  const auto empty =
      load_scenario(write_temp("empty-labels.yaml", scenario_text("labels: {}\n", kCommand)));
  ASSERT_TRUE(empty) << empty.error().detail;
  EXPECT_TRUE(empty->labels.empty());
}

TEST(ScenarioLabels, RefusedWithLocatedMessages) {
  struct Case {
    std::string labels, expected;
  };
  const std::vector<Case> cases{
      {"labels: [circle, ekf]\n", ":2:9: labels: expected a map of label names to values"},
      {"labels: {path: circle, path: line}\n", ":2:24: labels: duplicate label 'path' (first at line 2)"},
      {"labels: {path: }\n", ":2:10: labels.path: expected a non-empty one-line text"},
      {"labels: {path: {a: b}}\n", ":2:16: labels.path: expected a non-empty one-line text such as 'circle', got a map"},
      {"labels: {'a b': x}\n", ":2:10: labels: expected a name made of letters"},
      {"labels: {scenario: x}\n", ":2:10: labels: label name 'scenario' is reserved"},
      {"labels:\n  note: |\n    two\n    lines\n", ":3:9: labels.note: expected a non-empty one-line text"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.labels);
    const std::string path = write_temp("bad-labels.yaml", scenario_text(c.labels, kCommand));
    const auto s = load_scenario(path);
    ASSERT_FALSE(s);
    EXPECT_EQ(s.error().detail.rfind(path + c.expected, 0), 0u) << s.error().detail;
  }
}

TEST(ScenarioDir, ExpandReplacesEveryOccurrence) {
  EXPECT_EQ(expand_scenario_dir("{scenario_dir}/navd/p0-ekf.yaml", "/srv/scen"),
            "/srv/scen/navd/p0-ekf.yaml");
  EXPECT_EQ(expand_scenario_dir("--a={scenario_dir}:{scenario_dir}", "/d"), "--a=/d:/d");
  EXPECT_EQ(expand_scenario_dir("{port:ahrs}", "/d"), "{port:ahrs}");
  // A folder whose name contains the placeholder itself is not expanded again.
  EXPECT_EQ(expand_scenario_dir("{scenario_dir}", "/x/{scenario_dir}"), "/x/{scenario_dir}");
}

TEST(ScenarioDir, DutArgumentsOfPrimaryAndPeersGetTheAbsoluteFolder) {
  const std::string cmd =
      R"([navd, --config, "{scenario_dir}/navd/p0-ekf.yaml", --ahrs, "{port:ahrs}"])";
  std::string text = scenario_text("", cmd);
  text +=
      "peers:\n"
      "  - vehicle:\n"
      "      name: second\n"
      "      path:\n"
      "        - {straight: 10 m, speed: 1 m/s}\n"
      "      devices:\n"
      "        - {name: ahrs, type: microstrain-gx3-25}\n"
      "    dut:\n"
      "      command: [navd, \"--config={scenario_dir}/peer.yaml\", --ahrs, \"{port:ahrs}\"]\n"
      "      trigger: ahrs\n";
  const std::string path = write_temp("sub/dir/with-dir.yaml", text);
  const auto s = load_scenario(path);
  ASSERT_TRUE(s) << s.error().detail;
  const std::string dir = fs::absolute(fs::path(path)).lexically_normal().parent_path().string();
  EXPECT_EQ(s->dir, dir);
  EXPECT_TRUE(fs::path(s->dir).is_absolute());
  ASSERT_EQ(s->dut.command.size(), 5u);
  EXPECT_EQ(s->dut.command[2], dir + "/navd/p0-ekf.yaml");
  EXPECT_EQ(s->dut.command[4], "{port:ahrs}");  // replaced when the run opens the lines
  ASSERT_EQ(s->peers.size(), 1u);
  EXPECT_EQ(s->peers[0].dut.command[1], "--config=" + dir + "/peer.yaml");
}

TEST(ScenarioDir, RelativePathIsMadeAbsolute) {
  const std::string path = write_temp("rel/rel.yaml", scenario_text("", kCommand));
  const fs::path cwd = fs::current_path();
  fs::current_path(fs::path(path).parent_path().parent_path());
  const auto s = load_scenario("rel/../rel/rel.yaml");
  fs::current_path(cwd);
  ASSERT_TRUE(s) << s.error().detail;
  EXPECT_EQ(s->dir, fs::path(path).parent_path().lexically_normal().string());
}

}  // namespace
}  // namespace nav::bench

// SPDX-License-Identifier: MIT
// A campaign folder's outputs from its plan and results (campaign_outputs.hpp).
#include "campaign/campaign_outputs.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "campaign/campaign_nees.hpp"
#include "campaign/campaign_pairs.hpp"
#include "campaign/campaign_runs.hpp"
#include "campaign/campaign_verdicts.hpp"
#include "nav/bench/campaign.hpp"
#include "nav/bench/campaign_check_values.hpp"
#include "nav/bench/runner.hpp"
#include "nav/common/version.hpp"
#include "nav/reports/atomic_file.hpp"
#include "nav/reports/html_report.hpp"
#include "nav/reports/json_text.hpp"
#include "run/host_identity.hpp"

namespace nav::bench::detail {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

void write_atomically(const fs::path& path, const std::string& text) {
  if (auto r = reports::write_file_atomically(path.string(), text); !r) {
    throw std::runtime_error(r.error().detail);
  }
}

json labels_json(const Labels& labels) {
  json j = json::object();
  for (const auto& [k, v] : labels) j[k] = v;
  return j;
}

json number_or_null(double v) { return std::isnan(v) ? json(nullptr) : json(v); }

std::string markdown_document(const CampaignHeader& h, const CampaignPlan& plan,
                              std::size_t finished, const std::string& table,
                              const std::string& checks, const std::string& pairs,
                              const std::string& nees, const std::string& nis) {
  const std::uint64_t last = plan.first_seed + plan.seeds - 1;
  std::string doc = "# navbench campaign\n\n";
  const std::string variants_line =
      plan.variants.empty() ? std::string()
                            : ", " + std::to_string(plan.variants.size()) + " DUT variants";
  doc += "Command: `" + command_line(h.command) + "`\n\n";
  doc += "Seeds " + std::to_string(plan.first_seed) + "\u2013" + std::to_string(last) + " (" +
         std::to_string(plan.seeds) + " per scenario), " + time_mode_name(plan.mode) + ", " +
         std::to_string(plan.size()) + " runs of " + std::to_string(plan.scenarios.size()) +
         (plan.scenarios.size() == 1 ? " scenario" : " scenarios") + variants_line + ".\n\n";
  if (finished < plan.size()) {
    doc += std::string("**Incomplete") + (h.interrupted ? ": interrupted.** " : ".** ") +
           std::to_string(finished) + " of " + std::to_string(plan.size()) +
           " runs finished; the table is over those.\n\n";
  }
  doc += "Endpoint error: the value of the scenario's endpoint_error check (3-D position error "
         "of the last solution), over the runs that reached the end of the scenario (exit 0 or "
         "1); std is the sample standard deviation (n \u2212 1); \u2014 where undefined.\n\n";
  doc += table;
  if (!checks.empty()) {
    doc += "\n## Campaign checks\n\nStatements over the runs of a scenario, decided without "
           "assuming a distribution (order statistics; Clopper–Pearson for pass rates). A "
           "run whose DUT measured nothing, crashed or hung counts against them; a run in bench "
           "error is left out.\n\n" + checks;
  }
  if (!pairs.empty()) {
    doc += "\n## Variants paired by seed\n\nEach variant against the baseline (" +
           plan.variants.front().name +
           ") on the same scenario and seeds, figure by figure, by Wilcoxon's signed-rank test "
           "(one-sided; worse when p < 0.05); a difference is the candidate's value minus the "
           "baseline's.\n\n" + pairs;
  }
  if (!nees.empty()) {
    doc += "\n## Filter consistency\n\nThe NEES of the covariance the DUT stated "
           "($PNVBCOV), averaged over the runs at each whole second (Monte Carlo), against the "
           "two-sided 95 % bounds of a consistent filter [χ²₃ₙ(0.025)/N, "
           "χ²₃ₙ(0.975)/N] for N runs; reported, not judged.\n\n"
           "| scenario | block | NEES |\n|---|---|---|\n" + nees;
  }
  if (!nis.empty()) {
    doc += "\n## Innovations\n\nThe NIS νᵀS⁻¹ν of the innovations the DUT stated "
           "($PNVBINN), per measurement of m dimensions, averaged over the runs at each whole "
           "second (Monte Carlo), against [χ²ₘₙ(0.025)/N, χ²ₘₙ(0.975)/N] for N runs; "
           "reported, not judged.\n\n"
           "| scenario | measurement | m | NIS |\n|---|---|---|---|\n" + nis;
  }
  return doc;
}

}  // namespace

std::optional<int> write_campaign_outputs(const fs::path& dir, const CampaignPlan& plan,
                           const std::vector<std::optional<CampaignResult>>& results,
                           const CampaignHeader& h) {
  std::vector<CampaignRun> runs(plan.size());
  std::vector<int> codes;
  std::size_t finished = 0;
  for (std::size_t i = 0; i < plan.size(); ++i) {
    CampaignRun& r = runs[i];
    r.scenario = plan.cell_name(plan.cell_of(i));
    r.seed = plan.seed_of(i);
    r.run_folder = "runs/" + plan.run_name(i);
    r.started = std::find(h.interrupted_indices.begin(), h.interrupted_indices.end(), i) !=
                h.interrupted_indices.end();
    if (const auto& res = results[i]) {
      r.started = r.finished = true;
      r.exit_code = res->exit_code;
      r.verdict = res->verdict;
      r.endpoint_error_m = res->endpoint_error_m;
      r.figures = res->figures;
      r.wall_time_s = res->wall_time_s;
      codes.push_back(run_code_under_campaign_checks(res->exit_code,
                                                     plan.scenarios[plan.scenario_of(i)]));
      ++finished;
    }
  }
  // One row per cell: a scenario, or a scenario with a variant (its label "variant").
  std::vector<std::pair<std::string, Labels>> table_scenarios;
  for (std::size_t c = 0; c < plan.cells(); ++c) {
    Labels labels = plan.scenarios[plan.scenario_of(c)].labels;
    if (!plan.variants.empty()) labels.emplace_back("variant", plan.variant_name(c));
    table_scenarios.emplace_back(plan.cell_name(c), std::move(labels));
  }
  const auto rows = comparison_rows(table_scenarios, runs);
  // Every cell, with the first variant of its scenario as the per-vehicle baseline.
  std::vector<CampaignCell> cells;
  for (std::size_t c = 0; c < plan.cells(); ++c) {
    const std::size_t baseline = plan.scenario_of(c);  // the cell of variant 0
    cells.push_back({plan.cell_name(c), plan.variant_name(c),
                     plan.variants.size() > 1 && baseline != c ? plan.cell_name(baseline)
                                                               : std::string()});
  }
  const auto vehicles = vehicle_rows(cells, runs);
  const std::string vehicles_md = vehicle_markdown(vehicles);
  // Every error check's value, per cell.
  const auto check_values = check_value_rows(cells, results);
  const std::string check_values_md = check_value_markdown(check_values);
  const auto verdicts = judge_campaign_checks(plan, results);
  std::string checks_text, checks_md;
  for (const auto& v : verdicts) {
    if (!v.passed) codes.push_back(kExitFail);
    const char* word = v.passed ? "PASS" : "FAIL";
    checks_text += std::string(word) + "  " + v.scenario + ": " + v.statement + "\n      " +
                   v.finding + "\n";
    checks_md += std::string("- **") + word + "** " + v.scenario + " — " + v.statement +
                 (v.spec.req.empty() ? "" : " (" + v.spec.req + ")") + ": " + v.finding + ".\n";
  }
  const auto pairs = compare_variants(plan, results);
  std::string pairs_text, pairs_md;
  for (const auto& c : pairs) {
    if (c.worse) codes.push_back(kExitFail);  // the regression gate
    pairs_text += std::string(c.worse ? "WORSE " : "      ") + c.scenario + ": " + c.text + "\n";
    pairs_md += std::string("- ") + (c.worse ? "**WORSE** " : "") + c.scenario + ": " + c.text +
                ".\n";
  }
  const auto nees = campaign_nees(dir, plan, results);
  std::string nees_text, nees_md;
  for (const auto& n : nees) {
    nees_text += "      " + n.cell + ", " + n.block + ": " + n.text + "\n";
    nees_md += "| " + n.cell + " | " + n.block + " | " + n.text + " |\n";
  }
  const auto nis = campaign_nis(dir, plan, results);
  std::string nis_text, nis_md;
  for (const auto& n : nis) {
    const bool none = n.dof == 0;  // a cell that states no innovations at all
    nis_text += "      " + n.cell +
                (none ? "" : ", " + n.block + " (" + std::to_string(n.dof) + " dof)") + ": " +
                n.text + "\n";
    nis_md += "| " + n.cell + " | " + n.block + " | " + (none ? "-" : std::to_string(n.dof)) +
              " | " + n.text + " |\n";
  }
  const std::string table =
      comparison_markdown(rows) +
      (vehicles_md.empty() ? ""
                           : "\nEvery vehicle's mean position error (time average of the 3-D "
                             "error of its solutions):\n\n" + vehicles_md) +
      (check_values_md.empty() ? ""
                               : "\nEvery error check's value over the runs that reached the "
                                 "end:\n\n" + check_values_md);
  const std::string stdout_text =
      table + (checks_text.empty() ? "" : "\nCampaign checks:\n" + checks_text) +
      (pairs_text.empty() ? "" : "\nVariants paired by seed:\n" + pairs_text) +
      (nees_text.empty() ? ""
                         : "\nFilter consistency (Monte-Carlo averaged NEES, 3 dof, 95 % "
                           "bounds):\n" + nees_text) +
      (nis_text.empty() ? ""
                        : "\nInnovations (Monte-Carlo averaged NIS, 95 % bounds):\n" + nis_text);
  const int exit_code = campaign_exit_code(codes);

  json j;
  j["command"] = h.command;
  j["command_line"] = command_line(h.command);
  j["plan"] = "plan.json";
  j["seeds"] = {{"first", plan.first_seed},
                {"last", plan.first_seed + plan.seeds - 1},
                {"count", plan.seeds}};
  j["mode"] = time_mode_name(plan.mode);
  j["jobs"] = h.jobs ? json(*h.jobs) : json(nullptr);
  j["started_utc"] = h.started_utc;
  j["navbench_version"] = navbench_version();
  j["host"] = {{"name", host_identity().name}, {"kernel", host_identity().kernel}};
  j["wall_time_s"] = h.wall_time_s;
  j["complete"] = finished == plan.size();
  j["runs_finished"] = finished;
  j["exit_code"] = h.interrupted ? 130 : exit_code;
  j["variants"] = json::array();
  for (const auto& v : plan.variants) {
    j["variants"].push_back(
        {{"name", v.name}, {"program", v.program.empty() ? json(nullptr) : json(v.program)}});
  }
  j["scenarios"] = json::array();  // one per cell
  for (std::size_t c = 0; c < plan.cells(); ++c) {
    const auto& s = plan.scenarios[plan.scenario_of(c)];
    j["scenarios"].push_back(
        {{"name", table_scenarios[c].first},
         {"scenario", s.name},
         {"variant", plan.variants.empty() ? json(nullptr) : json(plan.variant_name(c))},
         {"file", s.file},
         {"sha256", s.sha256},
         {"labels", labels_json(table_scenarios[c].second)},
         {"endpoint_check", s.endpoint_check.empty() ? json(nullptr) : json(s.endpoint_check)}});
  }
  j["runs"] = json::array();
  for (std::size_t c = 0; c < plan.cells(); ++c) {
    for (std::size_t i = c; i < runs.size(); i += plan.cells()) {
      const auto& r = runs[i];
      json e;
      e["index"] = i;
      e["scenario"] = r.scenario;
      e["labels"] = labels_json(table_scenarios[c].second);
      e["seed"] = r.seed;
      e["status"] = r.finished ? "finished" : r.started ? "interrupted" : "not run";
      e["exit_code"] = r.finished ? json(r.exit_code) : nullptr;
      e["verdict"] = r.finished ? json(r.verdict) : nullptr;
      e["endpoint_error_m"] = r.endpoint_error_m ? json(*r.endpoint_error_m) : nullptr;
      e["run_folder"] = r.run_folder;
      e["wall_time_s"] = r.wall_time_s;
      if (const auto& res = results[i]) {
        e["host"] = res->host;
        e["inputs"] = result_json(*res)["inputs"];
      }
      j["runs"].push_back(std::move(e));
    }
  }
  j["comparison"] = json::array();
  const auto stats = [&](const SampleStats& s) {
    return json{{"n", s.n},
                {"mean", number_or_null(s.mean)},
                {"std", number_or_null(s.stddev)},
                {"min", number_or_null(s.min)},
                {"max", number_or_null(s.max)}};
  };
  for (const auto& row : rows) {
    j["comparison"].push_back({{"scenario", row.scenario},
                               {"labels", labels_json(row.labels)},
                               {"runs", row.runs},
                               {"passed", row.passed},
                               {"endpoint_error_m", stats(row.endpoint)},
                               {"endpoint_horizontal_m", stats(row.endpoint_horizontal)},
                               {"endpoint_vertical_m", stats(row.endpoint_vertical)},
                               {"mean_position_error_m", stats(row.mean_position)},
                               {"mean_attitude_error_deg", stats(row.mean_attitude)}});
  }
  j["vehicles"] = json::array();
  for (const auto& v : vehicles) {
    j["vehicles"].push_back(
        {{"scenario", v.cell},
         {"variant", v.variant.empty() ? json(nullptr) : json(v.variant)},
         {"vehicle", v.vehicle},
         {"mean_position_error_m", stats(v.mean_position)},
         {"baseline", v.baseline.empty() ? json(nullptr) : json(v.baseline)},
         {"improvement_pct", v.improvement_pct ? json(*v.improvement_pct) : json(nullptr)}});
  }
  j["check_values"] = json::array();
  for (const auto& v : check_values) {
    j["check_values"].push_back({{"scenario", v.cell},
                                 {"variant", v.variant.empty() ? json(nullptr) : json(v.variant)},
                                 {"check", v.check},
                                 {"unit", v.unit},
                                 {"values", stats(v.values)}});
  }
  j["campaign_checks"] = json::array();
  for (const auto& v : verdicts) j["campaign_checks"].push_back(verdict_json(v));
  j["paired_comparisons"] = json::array();
  for (const auto& c : pairs) j["paired_comparisons"].push_back(paired_json(c));
  j["nees"] = json::array();
  for (const auto& n : nees) j["nees"].push_back(nees_json(n));
  j["nis"] = json::array();
  for (const auto& n : nis) j["nis"].push_back(nees_json(n));
  try {
    write_atomically(dir / "comparison.csv", comparison_csv(rows));
    write_atomically(dir / "comparison.md", markdown_document(h, plan, finished, table, checks_md, pairs_md, nees_md, nis_md));
    write_atomically(dir / "campaign.json", reports::dump_json(j, 2) + "\n");
    // The campaign report from the files just written, as `navbench report DIR` makes it.
    if (const auto report = reports::write_report(dir.string()); !report) {
      throw std::runtime_error("campaign.html: " + report.error().detail);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "navbench: campaign: %s\n", e.what());
    std::fputs(stdout_text.c_str(), stdout);
    return std::nullopt;
  }
  std::fputs(stdout_text.c_str(), stdout);
  std::fflush(stdout);
  return exit_code;
}

}  // namespace nav::bench::detail

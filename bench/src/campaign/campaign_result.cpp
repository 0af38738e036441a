// SPDX-License-Identifier: MIT
// result.json of a campaign's result folder (campaign_result.hpp).
#include "nav/bench/campaign_result.hpp"

#include <fstream>

#include "campaign/json_at.hpp"
#include "nav/common/version.hpp"

namespace nav::bench {
namespace {

constexpr const char* kResultFormat = "navbench-campaign-result/2";

using detail::json_at;

}  // namespace

nlohmann::ordered_json result_json(const CampaignResult& r) {
  nlohmann::ordered_json j;
  j["format"] = kResultFormat;
  j["index"] = r.index;
  j["scenario"] = r.scenario;
  j["run_name"] = r.run_name;
  j["inputs"] = {{"scenario_sha256", r.inputs.scenario_sha256},
                 {"seed", r.inputs.seed},
                 {"mode", r.inputs.mode},
                 {"variant", r.inputs.variant.empty() ? nlohmann::ordered_json(nullptr)
                                                      : nlohmann::ordered_json(r.inputs.variant)},
                 {"dut_sha256", r.inputs.dut_sha256},
                 {"dut_files_sha256", r.inputs.dut_files_sha256},
                 {"navbench_version", r.inputs.navbench_version}};
  j["exit_code"] = r.exit_code;
  j["verdict"] = r.verdict;
  j["endpoint_error_m"] =
      r.endpoint_error_m ? nlohmann::ordered_json(*r.endpoint_error_m) : nullptr;
  const auto opt = [](const std::optional<double>& v) {
    return v ? nlohmann::ordered_json(*v) : nlohmann::ordered_json(nullptr);
  };
  j["figures"] = {{"endpoint_horizontal_m", opt(r.figures.endpoint_horizontal_m)},
                  {"endpoint_vertical_m", opt(r.figures.endpoint_vertical_m)},
                  {"mean_position_error_m", opt(r.figures.mean_position_m)},
                  {"mean_attitude_error_deg", opt(r.figures.mean_attitude_deg)}};
  auto& per_vehicle = j["figures"]["vehicle_mean_position_error_m"];
  per_vehicle = nlohmann::ordered_json::array();
  for (const auto& [name, value] : r.figures.vehicle_mean_position_m) {
    per_vehicle.push_back({{"vehicle", name}, {"m", value}});
  }
  j["checks"] = nlohmann::ordered_json::array();
  for (const auto& c : r.checks) {
    j["checks"].push_back({{"name", c.name},
                           {"passed", c.passed},
                           {"value", c.value ? nlohmann::ordered_json(*c.value) : nullptr},
                           {"unit", c.unit}});
  }
  j["wall_time_s"] = r.wall_time_s;
  j["host"] = r.host;
  j["finished_utc"] = r.finished_utc;
  return j;
}

RunFigures run_figures_from_summary(const nlohmann::json& summary) {
  RunFigures f;
  const auto& vehicles = json_at(summary, "vehicles");
  if (!vehicles.is_array() || vehicles.empty()) return f;
  const auto& v = vehicles.front();
  const auto figure = [&](const char* block, const char* key, std::optional<double>& out) {
    if (const auto& x = json_at(json_at(v, block), key); x.is_number()) out = x.get<double>();
  };
  figure("horizontal_error_m", "final", f.endpoint_horizontal_m);
  figure("vertical_error_m", "final", f.endpoint_vertical_m);
  figure("position_error_m", "mean", f.mean_position_m);
  figure("attitude_error_deg", "mean", f.mean_attitude_deg);
  for (const auto& each : vehicles) {
    const auto& name = json_at(each, "name");
    const auto& mean = json_at(json_at(each, "position_error_m"), "mean");
    if (name.is_string() && mean.is_number()) {
      f.vehicle_mean_position_m.emplace_back(name.get<std::string>(), mean.get<double>());
    }
  }
  return f;
}

Result<CampaignResult> result_from_json(const nlohmann::json& j, const std::string& where) {
  const auto bad = [&](const std::string& what) {
    return fail(ErrorCode::kParse, where + ": not a navbench campaign result: " + what);
  };
  if (json_at(j, "format") != kResultFormat) {
    return bad(std::string("\"format\" is not \"") + kResultFormat + "\"");
  }
  const auto& in = json_at(j, "inputs");
  if (!json_at(j, "index").is_number_unsigned() || !json_at(j, "scenario").is_string() ||
      !json_at(j, "run_name").is_string() || !json_at(j, "exit_code").is_number_integer() ||
      !json_at(j, "verdict").is_string() || !json_at(in, "scenario_sha256").is_string() ||
      !json_at(in, "seed").is_number_unsigned() || !json_at(in, "mode").is_string() ||
      !json_at(in, "dut_sha256").is_array() || !json_at(in, "navbench_version").is_string()) {
    return bad("a field is missing or of the wrong type");
  }
  CampaignResult r;
  r.index = json_at(j, "index").get<std::size_t>();
  r.scenario = json_at(j, "scenario").get<std::string>();
  r.run_name = json_at(j, "run_name").get<std::string>();
  r.inputs.scenario_sha256 = json_at(in, "scenario_sha256").get<std::string>();
  r.inputs.seed = json_at(in, "seed").get<std::uint64_t>();
  r.inputs.mode = json_at(in, "mode").get<std::string>();
  if (const auto& v = json_at(in, "variant"); v.is_string()) r.inputs.variant = v.get<std::string>();
  for (const auto& d : json_at(in, "dut_sha256")) {
    if (!d.is_string()) return bad("\"dut_sha256\" holds a non-string");
    r.inputs.dut_sha256.push_back(d.get<std::string>());
  }
  // Absent from results written before the DUTs' files were hashed: none (such a result then
  // differs from one that names files, and is run again).
  if (const auto& files = json_at(in, "dut_files_sha256"); !files.is_null()) {
    if (!files.is_array()) return bad("\"dut_files_sha256\" is not an array");
    for (const auto& per_dut : files) {
      if (!per_dut.is_array()) return bad("\"dut_files_sha256\" holds a non-array");
      auto& hashes = r.inputs.dut_files_sha256.emplace_back();
      for (const auto& h : per_dut) {
        if (!h.is_string()) return bad("\"dut_files_sha256\" holds a non-string");
        hashes.push_back(h.get<std::string>());
      }
    }
  }
  r.inputs.navbench_version = json_at(in, "navbench_version").get<std::string>();
  r.exit_code = json_at(j, "exit_code").get<int>();
  r.verdict = json_at(j, "verdict").get<std::string>();
  if (const auto& e = json_at(j, "endpoint_error_m"); e.is_number()) r.endpoint_error_m = e.get<double>();
  const auto& fig = json_at(j, "figures");  // absent in results of older navbench versions
  const auto figure = [&](const char* key, std::optional<double>& out) {
    if (const auto& v = json_at(fig, key); v.is_number()) out = v.get<double>();
  };
  figure("endpoint_horizontal_m", r.figures.endpoint_horizontal_m);
  figure("endpoint_vertical_m", r.figures.endpoint_vertical_m);
  figure("mean_position_error_m", r.figures.mean_position_m);
  figure("mean_attitude_error_deg", r.figures.mean_attitude_deg);
  // Absent in results of older navbench versions: none.
  for (const auto& v : json_at(fig, "vehicle_mean_position_error_m")) {
    if (!json_at(v, "vehicle").is_string() || !json_at(v, "m").is_number()) {
      return bad("\"vehicle_mean_position_error_m\" needs \"vehicle\" and \"m\"");
    }
    r.figures.vehicle_mean_position_m.emplace_back(json_at(v, "vehicle").get<std::string>(),
                                                   json_at(v, "m").get<double>());
  }
  for (const auto& c : json_at(j, "checks")) {
    if (!json_at(c, "name").is_string() || !json_at(c, "passed").is_boolean()) {
      return bad("a check needs \"name\" and \"passed\"");
    }
    RunCheck rc{json_at(c, "name").get<std::string>(), json_at(c, "passed").get<bool>(), {}, {}};
    if (const auto& v = json_at(c, "value"); v.is_number()) rc.value = v.get<double>();
    if (const auto& u = json_at(c, "unit"); u.is_string()) rc.unit = u.get<std::string>();
    r.checks.push_back(std::move(rc));
  }
  if (const auto& w = json_at(j, "wall_time_s"); w.is_number()) r.wall_time_s = w.get<double>();
  if (const auto& h = json_at(j, "host"); h.is_string()) r.host = h.get<std::string>();
  if (const auto& f = json_at(j, "finished_utc"); f.is_string()) r.finished_utc = f.get<std::string>();
  return r;
}

Result<CampaignResult> read_result(const std::filesystem::path& folder) {
  const auto path = folder / "result.json";
  std::ifstream in(path);
  if (!in) return fail(ErrorCode::kNotFound, path.string() + ": no result");
  const auto j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded()) return fail(ErrorCode::kParse, path.string() + ": not JSON");
  return result_from_json(j, path.string());
}

bool same_result(const CampaignResult& a, const CampaignResult& b) {
  return a.index == b.index && a.run_name == b.run_name && a.inputs == b.inputs &&
         a.exit_code == b.exit_code && a.verdict == b.verdict &&
         a.endpoint_error_m == b.endpoint_error_m && a.figures == b.figures &&
         a.checks == b.checks;
}

RunInputs current_inputs(const CampaignPlan& plan, std::size_t i,
                         const std::string& scenario_sha256,
                         const std::vector<std::string>& dut_sha256,
                         const std::vector<std::vector<std::string>>& dut_files_sha256) {
  RunInputs in;
  in.scenario_sha256 = scenario_sha256;
  in.seed = plan.seed_of(i);
  in.mode = time_mode_name(plan.mode);
  in.variant = plan.variant_name(i);
  in.dut_sha256 = dut_sha256;
  in.dut_files_sha256 = dut_files_sha256;
  in.navbench_version = navbench_version();
  return in;
}

}  // namespace nav::bench

// SPDX-License-Identifier: MIT
// summary.json: everything a machine (a campaign, a CI dashboard, `navbench report`) needs to
// know of a run, in one JSON document (nlohmann-json).
#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "nav/common/units.hpp"
#include "nav/common/version.hpp"
#include "nav/reports/json_text.hpp"
#include "nav/reports/text.hpp"
#include "output_file.hpp"
#include "writers.hpp"

namespace nav::reports::detail {
namespace {

using json = nlohmann::json;

json stats_json(const Stats& s) {
  return {{"count", s.count}, {"p50_ms", s.p50_s * 1e3}, {"p99_ms", s.p99_s * 1e3},
          {"max_ms", s.max_s * 1e3}};
}

json string_or_null(const std::string& s) { return s.empty() ? json(nullptr) : json(s); }

/// A DUT's configuration files: [{"path", "sha256"}, ...] in the order its arguments name them.
json files_json(const std::vector<DutFile>& files) {
  json out = json::array();
  for (const auto& f : files) out.push_back({{"path", f.path}, {"sha256", string_or_null(f.sha256)}});
  return out;
}

/// max, mean, rms and final value of an error over a vehicle's aligned samples (one per
/// solution with a valid position: at the DUT's solution rate, the mean is the time average);
/// null when none.
template <typename Value>
json error_figures(const std::vector<AlignedSample>& a, Value value) {
  if (a.empty()) return nullptr;
  double max = 0.0, sum = 0.0, sum_sq = 0.0;
  for (const auto& s : a) {
    const double v = value(s);
    max = std::max(max, v);
    sum += v;
    sum_sq += v * v;
  }
  const auto n = static_cast<double>(a.size());
  return {{"max", max}, {"mean", sum / n}, {"rms", std::sqrt(sum_sq / n)}, {"final", value(a.back())}};
}

json vehicle_json(const VehicleTrack& v, bool primary) {
  const auto& a = v.aligned;
  json j = {{"name", v.name},
            {"primary", primary},
            {"truth", truth_file_name(v.name)},
            {"estimate", estimate_file_name(v.name)},
            {"dut", {{"status", v.dut_status},
                     {"triggers_sent", v.triggers_sent},
                     {"answers", v.answers}}},
            {"solutions", a.size()},
            {"distance_m", v.truth.empty() ? json(nullptr) : json(v.truth.back().distance_m)}};
  j["position_error_m"] =
      error_figures(a, [](const AlignedSample& s) { return (s.est_p_n - s.truth_p_n).norm(); });
  j["horizontal_error_m"] = error_figures(
      a, [](const AlignedSample& s) { return (s.est_p_n - s.truth_p_n).head<2>().norm(); });
  j["vertical_error_m"] = error_figures(
      a, [](const AlignedSample& s) { return std::abs(s.est_p_n.z() - s.truth_p_n.z()); });
  j["attitude_error_deg"] = error_figures(a, [](const AlignedSample& s) {
    return units::rad_to_deg(attitude_error_angle(s.truth_q_nb, s.est_q_nb));
  });
  j["endpoint_error_m"] =
      a.empty() ? json(nullptr) : json((a.back().est_p_n - a.back().truth_p_n).norm());
  return j;
}

json check_json(const CheckResult& c) {
  json j = {{"name", c.name},
          {"kind", string_or_null(c.kind)},
          {"req", string_or_null(c.req)},
          {"title", string_or_null(c.title)},
          {"judged", c.judged},
          {"passed", c.passed},
          {"value", c.value},
          {"limit", c.limit},
          {"per_distance", c.per_distance},
          {"after_s", c.after_s},
          {"unit", c.unit},
          {"worst_t_s", c.worst_t_s ? json(*c.worst_t_s) : json(nullptr)},
          {"detail", c.detail},
          {"vehicle", string_or_null(c.vehicle)}};
  if (c.max_latency_s > 0) j["max_latency_ms"] = c.max_latency_s * 1e3;
  return j;
}

json device_json(const DeviceRow& d) {
  if (d.can) {
    return {{"name", d.name},     {"type", d.type},
            {"can", d.port},      {"bitrate", d.baud},
            {"seed", d.seed},     {"frames", d.messages},
            {"frames_dropped", d.frames_dropped}, {"bytes", d.bytes}};
  }
  return {{"name", d.name},          {"type", d.type},   {"port", d.port},
          {"baud", d.baud},          {"seed", d.seed},   {"messages", d.messages},
          {"bytes", d.bytes},        {"bytes_dropped", d.bytes_dropped},
          {"suppressed", d.suppressed}};
}

}  // namespace

void write_summary(const RunRecord& r, const std::string& dir) {
  json j;
  j["versions"] = {{"navbench", r.navbench_version.empty() ? std::string(navbench_version())
                                                          : r.navbench_version},
                   {"compiler", __VERSION__},
                   {"eigen", std::to_string(EIGEN_WORLD_VERSION) + "." +
                                 std::to_string(EIGEN_MAJOR_VERSION) + "." +
                                 std::to_string(EIGEN_MINOR_VERSION)},
                   {"nlohmann_json", std::to_string(NLOHMANN_JSON_VERSION_MAJOR) + "." +
                                         std::to_string(NLOHMANN_JSON_VERSION_MINOR) + "." +
                                         std::to_string(NLOHMANN_JSON_VERSION_PATCH)}};
  j["scenario"] = {{"name", r.scenario_name},
                   {"file", r.scenario_file},
                   {"sha256", string_or_null(r.scenario_sha256)},
                   {"description", r.scenario_description}};
  j["host"] = {{"name", string_or_null(r.host)}, {"kernel", string_or_null(r.kernel)}};
  if (r.wall) {
    j["wall"] = {{"slope_deg", r.wall->slope_deg},
                 {"azimuth_deg", r.wall->azimuth_deg},
                 {"origin_ned_m", r.wall->origin_ned_m}};
  }
  j["labels"] = json::object();
  for (const auto& [name, value] : r.labels) j["labels"][name] = value;
  j["seed"] = r.seed;
  j["mode"] = r.mode;
  j["duration_s"] = r.duration_s;
  j["stopped_at_s"] = r.stopped_at_s ? json(*r.stopped_at_s) : json(nullptr);
  j["started_utc"] = r.started_utc;
  j["wall_time_s"] = r.wall_time_s;
  j["bench_cpu_s"] = r.bench_cpu_s;
  j["verdict"] = r.verdict;
  j["exit_code"] = r.exit_code;
  j["dut"] = {{"command", r.dut_command},
              {"executable", string_or_null(r.dut_executable)},
              {"sha256", string_or_null(r.dut_sha256)},
              {"files", files_json(r.dut_files)},
              {"status", r.dut_status},
              {"triggers_sent", r.triggers_sent},
              {"answers", r.answers},
              {"unmatched_answers", r.unmatched_answers},
              {"malformed_output", r.malformed_output},
              {"malformed_examples", json::array()}};
  for (const auto& m : r.malformed_examples) {
    j["dut"]["malformed_examples"].push_back({{"rx_s", m.rx_s}, {"text", m.text}, {"why", m.why}});
  }
  j["dut"]["restarts"] = json::array();
  for (const auto& rs : r.restarts) {
    const auto opt = [](const std::optional<double>& v) { return v ? json(*v) : json(nullptr); };
    j["dut"]["restarts"].push_back({{"off_s", rs.off_s},
                                    {"on_s", rs.on_s},
                                    {"ended", rs.ended},
                                    {"started_again", rs.started_again},
                                    {"first_solution_s", opt(rs.first_solution_s)},
                                    {"first_valid_s", opt(rs.first_valid_s)},
                                    {"recovery_s", opt(rs.recovery_s)},
                                    {"triggers_in_gap", rs.triggers_in_gap}});
  }
  j["logs_cut"] = json::array();
  for (const auto& c : r.logs_cut) {
    j["logs_cut"].push_back(
        {{"file", c.file}, {"limit_bytes", c.limit_bytes}, {"cut_bytes", c.cut_bytes}});
  }
  j["checks"] = json::array();
  for (const auto& c : r.checks) j["checks"].push_back(check_json(c));
  j["bench_lateness"] = stats_json(r.bench_lateness);
  j["bench_lateness"]["budget_p99_ms"] = r.lateness_budget_p99_s * 1e3;
  j["bench_lateness"]["over_budget"] = r.lateness_over_budget;
  j["bench_lateness"]["judged"] = r.bench_lateness.count < kMinMessagesForP99 ? "p50" : "p99";
  j["bench_lateness"]["late"] = r.bench_late;
  j["notes"] = r.notes;
  j["dut_latency"] = stats_json(r.dut_latency);
  j["devices"] = json::array();
  for (const auto& d : r.devices) j["devices"].push_back(device_json(d));
  for (const auto& b : r.can_buses) {
    j["can_buses"].push_back({{"interface", b.interface},
                              {"bitrate", b.bitrate_bps},
                              {"frames_sent", b.frames_sent},
                              {"frames_dropped", b.frames_dropped},
                              {"error_reports", b.error_reports},
                              {"frames_withheld", b.frames_withheld},
                              {"frame_bits", b.frame_bits},
                              {"bus_load", b.bus_load},
                              {"queueing_delay", stats_json(b.queueing_delay)},
                              {"write_lateness", stats_json(b.write_lateness)}});
  }
  j["faults"] = json::array();
  for (const auto& fr : r.faults) {
    j["faults"].push_back({{"device", fr.device},
                           {"kind", fr.kind},
                           {"start_s", fr.start_s},
                           {"end_s", fr.end_s},
                           {"messages_affected", fr.messages_affected}});
  }
  j["vehicles"] = json::array();
  for (std::size_t v = 0; v < r.vehicles.size(); ++v) {
    j["vehicles"].push_back(vehicle_json(r.vehicles[v], v == 0));
  }
  // Only multi-vehicle or modem scenarios have these (single-vehicle summaries unchanged).
  for (const auto& p : r.peers) {
    j["peers"].push_back({{"name", p.name},
                          {"dut", {{"command", p.dut_command},
                                   {"executable", string_or_null(p.dut_executable)},
                                   {"sha256", string_or_null(p.dut_sha256)},
                                   {"files", files_json(p.dut_files)},
                                   {"status", p.dut_status},
                                   {"triggers_sent", p.triggers_sent},
                                   {"answers", p.answers}}}});
  }
  for (const auto& l : r.modem_links) {
    j["acoustic_links"].push_back({{"from", l.from},
                                   {"to", l.to},
                                   {"packets_sent", l.packets_sent},
                                   {"packets_delivered", l.packets_delivered},
                                   {"packets_lost", l.packets_lost},
                                   {"packets_out_of_range", l.packets_out_of_range},
                                   {"bytes_delivered", l.bytes_delivered},
                                   {"min_propagation_s", l.min_propagation_s},
                                   {"max_propagation_s", l.max_propagation_s}});
  }
  if (r.witness_run) {
    json w = {{"arrival_lateness", stats_json(witness_arrival_lateness(r))},
              {"lines", json::array()}};
    for (const auto& l : r.witness) {
      w["lines"].push_back({{"device", l.device},
                            {"baud", l.baud},
                            {"messages", l.messages},
                            {"messages_seen", l.messages_seen},
                            {"bytes_sent", l.bytes_sent},
                            {"bytes_seen", l.bytes_seen},
                            {"bytes_matched", l.bytes_matched},
                            {"write_lateness", stats_json(l.write_lateness)},
                            {"arrival_lateness", stats_json(l.arrival_lateness)},
                            {"pacing_median", l.pacing_median ? json(*l.pacing_median) : json(nullptr)},
                            {"pacing_messages", l.pacing_messages}});
    }
    j["witness"] = std::move(w);
  }
  OutputFile f(dir, "summary.json");
  f << dump_json(j, 2) << '\n';
}

}  // namespace nav::reports::detail

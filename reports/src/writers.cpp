// SPDX-License-Identifier: MIT
// Report writers: summary.json (nlohmann-json), junit.xml, TUM trajectories, CSV tables.
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "nav/common/units.hpp"
#include "nav/reports/run_record.hpp"

namespace nav::reports {
namespace {

using units::rad_to_deg;

class File {
 public:
  File(const std::string& dir, const std::string& name) : path_(dir + "/" + name), out_(path_) {
    if (!out_) throw std::runtime_error("cannot write " + path_);
    out_.precision(9);
    out_ << std::fixed;
  }
  ~File() noexcept(false) {
    out_.flush();
    if (!out_ && std::uncaught_exceptions() == 0) throw std::runtime_error("write failed: " + path_);
  }
  File(const File&) = delete;
  File& operator=(const File&) = delete;
  std::ofstream& operator*() { return out_; }

 private:
  std::string path_;
  std::ofstream out_;
};

nlohmann::json stats_json(const Stats& s) {
  return {{"count", s.count}, {"p50_ms", s.p50_s * 1e3}, {"p99_ms", s.p99_s * 1e3},
          {"max_ms", s.max_s * 1e3}};
}

std::string xml_escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      default: o += c;
    }
  }
  return o;
}

void write_summary(const RunRecord& r, const std::string& dir) {
  nlohmann::json j;
  j["versions"] = {{"navbench", NAV_VERSION},
                   {"compiler", __VERSION__},
                   {"eigen", std::to_string(EIGEN_WORLD_VERSION) + "." +
                                 std::to_string(EIGEN_MAJOR_VERSION) + "." +
                                 std::to_string(EIGEN_MINOR_VERSION)},
                   {"nlohmann_json", std::to_string(NLOHMANN_JSON_VERSION_MAJOR) + "." +
                                         std::to_string(NLOHMANN_JSON_VERSION_MINOR) + "." +
                                         std::to_string(NLOHMANN_JSON_VERSION_PATCH)}};
  j["scenario"] = {{"name", r.scenario_name}, {"file", r.scenario_file}};
  j["labels"] = nlohmann::json::object();
  for (const auto& [name, value] : r.labels) j["labels"][name] = value;
  j["seed"] = r.seed;
  j["mode"] = r.mode;
  j["duration_s"] = r.duration_s;
  j["started_utc"] = r.started_utc;
  j["wall_time_s"] = r.wall_time_s;
  j["verdict"] = r.verdict;
  j["exit_code"] = r.exit_code;
  j["dut"] = {{"command", r.dut_command},       {"status", r.dut_status},
              {"triggers_sent", r.triggers_sent}, {"answers", r.answers},
              {"unmatched_answers", r.unmatched_answers},
              {"malformed_output", r.malformed_output}};
  for (const auto& c : r.checks) {
    j["checks"].push_back({{"name", c.name},   {"judged", c.judged}, {"passed", c.passed},
                           {"value", c.value}, {"limit", c.limit},   {"unit", c.unit},
                           {"detail", c.detail}});
  }
  j["bench_lateness"] = stats_json(r.bench_lateness);
  j["bench_lateness"]["budget_p99_ms"] = r.lateness_budget_p99_s * 1e3;
  j["dut_latency"] = stats_json(r.dut_latency);
  for (const auto& d : r.devices) {
    if (d.can) {
      j["devices"].push_back({{"name", d.name},
                              {"type", d.type},
                              {"can", d.port},
                              {"bitrate", d.baud},
                              {"seed", d.seed},
                              {"frames", d.messages},
                              {"frames_dropped", d.frames_dropped},
                              {"bytes", d.bytes}});
      continue;
    }
    j["devices"].push_back({{"name", d.name},        {"type", d.type},
                            {"port", d.port},        {"baud", d.baud}, {"seed", d.seed},
                            {"messages", d.messages}, {"bytes", d.bytes},
                            {"bytes_dropped", d.bytes_dropped},
                            {"suppressed", d.suppressed}});
  }
  for (const auto& b : r.can_buses) {
    j["can_buses"].push_back({{"interface", b.interface},
                              {"bitrate", b.bitrate_bps},
                              {"frames_sent", b.frames_sent},
                              {"frames_dropped", b.frames_dropped},
                              {"frame_bits", b.frame_bits},
                              {"bus_load", b.bus_load},
                              {"queueing_delay", stats_json(b.queueing_delay)},
                              {"write_lateness", stats_json(b.write_lateness)}});
  }
  j["faults"] = nlohmann::json::array();
  for (const auto& fr : r.faults) {
    j["faults"].push_back({{"device", fr.device},
                           {"kind", fr.kind},
                           {"start_s", fr.start_s},
                           {"end_s", fr.end_s},
                           {"messages_affected", fr.messages_affected}});
  }
  // Only multi-vehicle or modem scenarios have these (single-vehicle summaries unchanged).
  for (const auto& p : r.peers) {
    j["peers"].push_back({{"name", p.name},
                          {"dut", {{"command", p.dut_command},
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
  File f(dir, "summary.json");
  *f << j.dump(2) << '\n';
}

void write_junit(const RunRecord& r, const std::string& dir) {
  std::size_t failures = 0, skipped = 0;
  for (const auto& c : r.checks) {
    if (!c.judged) ++skipped;
    else if (!c.passed) ++failures;
  }
  File f(dir, "junit.xml");
  auto& o = *f;
  o << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<testsuites>\n<testsuite name=\"" << xml_escape(r.scenario_name) << "\" tests=\""
    << r.checks.size() << "\" failures=\"" << failures << "\" skipped=\"" << skipped
    << "\" time=\"" << r.wall_time_s << "\">\n"
    << "  <properties><property name=\"seed\" value=\"" << r.seed << "\"/>"
    << "<property name=\"mode\" value=\"" << r.mode << "\"/>"
    << "<property name=\"verdict\" value=\"" << xml_escape(r.verdict) << "\"/>";
  for (const auto& fr : r.faults) {
    o << "<property name=\"fault\" value=\"" << xml_escape(fault_text(fr)) << "\"/>";
  }
  o << "</properties>\n";
  for (const auto& c : r.checks) {
    o << "  <testcase classname=\"" << xml_escape(r.scenario_name) << "\" name=\""
      << xml_escape(c.name) << "\">";
    if (!c.judged) o << "<skipped message=\"" << xml_escape(c.detail) << "\"/>";
    else if (!c.passed) o << "<failure message=\"" << xml_escape(c.detail) << "\"/>";
    o << "</testcase>\n";
  }
  o << "</testsuite>\n</testsuites>\n";
}

void write_tum_line(std::ostream& o, double t, const Vec3& p, const Quat& q) {
  o << t << ' ' << p.x() << ' ' << p.y() << ' ' << p.z() << ' ' << q.x() << ' ' << q.y() << ' '
    << q.z() << ' ' << q.w() << '\n';
}

void write_trajectories(const RunRecord& r, const std::string& dir) {
  {
    File f(dir, "truth.tum");
    *f << "# timestamp[s] north[m] east[m] down[m] qx qy qz qw (q_nb, body FRD -> NED)\n";
    for (const auto& t : r.truth) write_tum_line(*f, t.t_s, t.p_n, t.q_nb);
  }
  File f(dir, "estimate.tum");
  *f << "# timestamp[s] north[m] east[m] down[m] qx qy qz qw (q_nb, body FRD -> NED)\n";
  for (const auto& a : r.aligned) write_tum_line(*f, a.t_s, a.est_p_n, a.est_q_nb);
}

void write_timeseries(const RunRecord& r, const std::string& dir) {
  File f(dir, "timeseries.csv");
  auto& o = *f;
  o << "t_s,truth_n_m,truth_e_m,truth_d_m,est_n_m,est_e_m,est_d_m,err_horizontal_m,"
       "err_vertical_m,truth_roll_deg,truth_pitch_deg,truth_yaw_deg,est_roll_deg,"
       "est_pitch_deg,est_yaw_deg,err_attitude_deg,distance_m\n";
  for (const auto& a : r.aligned) {
    const Vec3 e = a.est_p_n - a.truth_p_n;
    const Euler et = euler_from_quat(a.truth_q_nb);
    const Euler ee = euler_from_quat(a.est_q_nb);
    o << a.t_s << ',' << a.truth_p_n.x() << ',' << a.truth_p_n.y() << ',' << a.truth_p_n.z()
      << ',' << a.est_p_n.x() << ',' << a.est_p_n.y() << ',' << a.est_p_n.z() << ','
      << e.head<2>().norm() << ',' << std::abs(e.z()) << ',' << rad_to_deg(et.roll) << ','
      << rad_to_deg(et.pitch) << ',' << rad_to_deg(et.yaw) << ',' << rad_to_deg(ee.roll) << ','
      << rad_to_deg(ee.pitch) << ',' << rad_to_deg(ee.yaw) << ','
      << rad_to_deg(attitude_error_angle(a.truth_q_nb, a.est_q_nb)) << ',' << a.distance_m
      << '\n';
  }
}

void write_latency(const RunRecord& r, const std::string& dir) {
  {
    File f(dir, "latency.csv");
    *f << "tag,t_valid_s,wire_end_s,rx_s,latency_ms,missed\n";
    for (const auto& l : r.latency) {
      *f << l.tag << ',' << l.t_valid_s << ',' << l.wire_end_s << ',';
      if (l.rx_s) *f << *l.rx_s << ',' << (*l.rx_s - l.wire_end_s) * 1e3;
      else *f << ',';
      *f << ',' << (l.missed ? 1 : 0) << '\n';
    }
  }
  File f(dir, "lateness.csv");
  *f << "device,scheduled_s,actual_s,lateness_us\n";
  for (const auto& l : r.lateness) {
    *f << l.device << ',' << l.scheduled_s << ',' << l.actual_s << ','
       << (l.actual_s - l.scheduled_s) * 1e6 << '\n';
  }
}

}  // namespace

void write_reports(const RunRecord& r, const std::string& dir) {
  write_summary(r, dir);
  write_junit(r, dir);
  write_trajectories(r, dir);
  write_timeseries(r, dir);
  write_latency(r, dir);
}

std::string fault_text(const FaultRow& f) {
  char line[256];
  std::snprintf(line, sizeof line, "%s %s %.1f\u2013%.1f s, %zu message%s", f.device.c_str(),
                f.kind.c_str(), f.start_s, f.end_s, f.messages_affected,
                f.messages_affected == 1 ? "" : "s");
  return line;
}

std::string verdict_text(const RunRecord& r) {
  std::ostringstream o;
  char line[256];
  std::snprintf(line, sizeof line, "navbench run %s  (seed %llu, %s, %.1f s, wall %.1f s)\n",
                r.scenario_name.c_str(), static_cast<unsigned long long>(r.seed), r.mode.c_str(),
                r.duration_s, r.wall_time_s);
  o << line;
  o << "  DUT: " << r.dut_status << "; " << r.answers << " solutions for " << r.triggers_sent
    << " triggers";
  if (r.unmatched_answers) o << ", " << r.unmatched_answers << " naming no trigger";
  if (r.malformed_output) o << ", " << r.malformed_output << " malformed lines";
  o << '\n';
  for (const auto& p : r.peers) {
    o << "  peer " << p.name << ": DUT " << p.dut_status << "; " << p.answers
      << " solutions for " << p.triggers_sent << " triggers\n";
  }
  for (const auto& l : r.modem_links) {
    o << "  acoustic " << l.from << " -> " << l.to << ": " << l.packets_delivered << " of "
      << l.packets_sent << " packets delivered, " << l.packets_lost << " lost, "
      << l.packets_out_of_range << " out of range\n";
  }
  for (const auto& b : r.can_buses) {
    std::snprintf(line, sizeof line,
                  "  CAN %s %g kbit/s: %zu frames (%zu dropped), bus load %.2f %%, queueing "
                  "p50 %.3f ms p99 %.3f ms max %.3f ms\n",
                  b.interface.c_str(), b.bitrate_bps / 1e3, b.frames_sent, b.frames_dropped,
                  b.bus_load * 100.0, b.queueing_delay.p50_s * 1e3, b.queueing_delay.p99_s * 1e3,
                  b.queueing_delay.max_s * 1e3);
    o << line;
    if (b.write_lateness.count > 0) {
      std::snprintf(line, sizeof line,
                    "  CAN %s write lateness  p50 %.3f ms  p99 %.3f ms  max %.3f ms  (%zu frames)\n",
                    b.interface.c_str(), b.write_lateness.p50_s * 1e3,
                    b.write_lateness.p99_s * 1e3, b.write_lateness.max_s * 1e3,
                    b.write_lateness.count);
      o << line;
    }
  }
  for (const auto& c : r.checks) {
    const char* tag = !c.judged ? "SKIP" : c.passed ? "PASS" : "FAIL";
    std::snprintf(line, sizeof line, "  %s  %-17s %s\n", tag, c.name.c_str(), c.detail.c_str());
    o << line;
  }
  for (const auto& f : r.faults) o << "  FAULT " << fault_text(f) << '\n';
  const auto ms = [](double s) { return s * 1e3; };
  if (r.bench_lateness.count > 0) {
    std::snprintf(line, sizeof line,
                  "  bench lateness  p50 %.3f ms  p99 %.3f ms  max %.3f ms  (%zu messages, "
                  "budget p99 %.1f ms)\n",
                  ms(r.bench_lateness.p50_s), ms(r.bench_lateness.p99_s),
                  ms(r.bench_lateness.max_s), r.bench_lateness.count,
                  ms(r.lateness_budget_p99_s));
  } else {
    std::snprintf(line, sizeof line, "  bench lateness  n/a (lockstep: virtual time)\n");
  }
  o << line;
  std::snprintf(line, sizeof line, "  %-14s  p50 %.3f ms  p99 %.3f ms  max %.3f ms  (%zu)\n",
                r.mode == "lockstep" ? "DUT compute" : "DUT latency", ms(r.dut_latency.p50_s),
                ms(r.dut_latency.p99_s), ms(r.dut_latency.max_s), r.dut_latency.count);
  o << line;
  o << "VERDICT: " << r.verdict << "   report: " << r.run_dir << "/\n";
  return o.str();
}

}  // namespace nav::reports

// SPDX-License-Identifier: MIT
// A synthetic finished run (a RunRecord), written to a temporary run folder, for the report
// tests.
#pragma once

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "nav/reports/run_record.hpp"

namespace nav::reports::testing {

namespace fs = std::filesystem;

inline std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

inline fs::path fresh_dir(const std::string& name) {
  const fs::path d = fs::path(::testing::TempDir()) / ("navbench-report-" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// A run of `seconds` at `rate_hz`: a circle of 20 m radius, an estimate drifting north,
/// one trigger per sample, two devices, one fault, checks of every kind.
inline RunRecord synthetic_run(double seconds, double rate_hz) {
  RunRecord r;
  r.scenario_name = "synthetic";
  r.scenario_file = "scenarios/synthetic.yaml";
  r.scenario_description = "a synthetic run";
  r.scenario_sha256 = std::string(64, 'a');
  r.navbench_version = "test";
  r.host = "testhost";
  r.kernel = "Linux 6.1.0 x86_64";
  r.mode = "realtime";
  r.run_dir = "runs/synthetic";
  r.seed = 7;
  r.duration_s = seconds;
  r.started_utc = "2026-12-01T00:00:00Z";
  r.verdict = "FAIL";
  r.exit_code = 1;
  r.dut_command = {"navd", "--ahrs", "/dev/pts/3"};
  r.dut_executable = "/usr/bin/navd";
  r.dut_sha256 = std::string(64, 'b');
  r.dut_status = "alive until the end (pid 1)";
  const auto n = static_cast<std::size_t>(seconds * rate_hz);
  VehicleTrack v;
  v.name = "auv";
  v.dut_status = r.dut_status;
  for (std::size_t k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) / rate_hz;
    const double a = 0.05 * t;
    AlignedSample s;
    s.t_s = t;
    s.truth_p_n = Vec3(20 * std::sin(a), 20 * (1 - std::cos(a)), 2.0);
    s.est_p_n = s.truth_p_n + Vec3(0.002 * t, 0.0, 0.1);
    s.truth_q_nb = s.est_q_nb = Quat::Identity();
    s.distance_m = 20 * a;
    v.aligned.push_back(s);
    if (k % 2 == 0) v.truth.push_back({t, s.truth_p_n, s.truth_q_nb, s.distance_m});
    LatencyRow l;
    l.tag = k;
    l.t_valid_s = t;
    l.wire_end_s = t + 0.001;
    if (k % 100 != 99) l.rx_s = t + 0.001 + 0.0005 + 0.0001 * std::sin(t);
    l.missed = !l.rx_s;
    r.latency.push_back(l);
    r.lateness.push_back({"ahrs", t, t + 60e-6});
    if (k % 10 == 0) r.lateness.push_back({"gps", t + 0.0003, t + 0.0003 + 90e-6});
  }
  v.triggers_sent = v.answers = n;
  r.vehicles.push_back(v);
  r.triggers_sent = r.answers = n;
  CheckResult h{"horizontal_error", true, false, 1.2, 1.0, "m", "max 1.2 m over the limit"};
  h.kind = "horizontal_error";
  h.req = "NAV-REQ-012";
  h.title = "horizontal error within 1 m after alignment";
  h.per_distance = 0.001;
  h.after_s = 5.0;
  h.worst_t_s = seconds - 1;
  CheckResult d{"deadline", true, true, 0, 5, "misses", "0 misses"};
  d.kind = "deadline";
  d.max_latency_s = 0.01;
  CheckResult e{"endpoint_error", true, true, 0.5, 3, "m", "0.5 m"};
  e.kind = "endpoint_error";
  e.worst_t_s = seconds;
  CheckResult alive{"dut_alive", true, true, 1, 1, "", "alive"};
  alive.kind = "dut_alive";
  r.checks = {h, d, e, alive};
  for (const char* name : {"ahrs", "gps"}) {
    DeviceRow dev{name, "microstrain-gx3-25", "/dev/pts/4", 115200, 1, 100, 1000, 0, 0};
    for (std::size_t s = 0; s < static_cast<std::size_t>(std::ceil(seconds)); ++s) {
      dev.per_second.push_back({static_cast<std::uint32_t>(rate_hz), 60, s == 3 ? 40u : 0u});
    }
    r.devices.push_back(dev);
  }
  r.faults.push_back({"gps", "checksum", 2.0, 4.0, 3});
  r.bench_lateness = summarize({60e-6, 90e-6});
  r.lateness_budget_p99_s = 0.005;
  r.dut_latency = summarize({0.0005, 0.0006});
  return r;
}

/// The plot specifications embedded in a report.
inline nlohmann::json embedded_plots(const std::string& html) {
  const std::string open = "<script type=\"application/json\" id=\"nav-plots\">";
  const auto a = html.find(open);
  if (a == std::string::npos) return nullptr;
  const auto b = html.find("</script>", a);
  return nlohmann::json::parse(html.substr(a + open.size(), b - a - open.size()));
}

inline const nlohmann::json* plot_by_id(const nlohmann::json& plots, const std::string& id) {
  for (const auto& p : plots) {
    if (p.value("id", "") == id) return &p;
  }
  return nullptr;
}

}  // namespace nav::reports::testing

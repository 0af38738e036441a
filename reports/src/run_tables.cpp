// SPDX-License-Identifier: MIT
// The run's tables: TUM trajectories (evo-compatible) and the CSV files behind the plots.
#include <filesystem>

#include "nav/common/units.hpp"
#include "output_file.hpp"
#include "writers.hpp"

namespace nav::reports::detail {
namespace {

namespace fs = std::filesystem;
using units::rad_to_deg;

constexpr const char* kTumHeader =
    "# timestamp[s] north[m] east[m] down[m] qx qy qz qw (q_nb, body FRD -> NED)\n";

void write_tum_line(OutputFile& o, double t, const Vec3& p, const Quat& q) {
  o << t << ' ' << p.x() << ' ' << p.y() << ' ' << p.z() << ' ' << q.x() << ' ' << q.y() << ' '
    << q.z() << ' ' << q.w() << '\n';
}

void write_truth(const VehicleTrack& v, const std::string& dir, const std::string& name) {
  OutputFile f(dir, name);
  f << kTumHeader;
  for (const auto& t : v.truth) write_tum_line(f, t.t_s, t.p_n, t.q_nb);
}

void write_estimate(const VehicleTrack& v, const std::string& dir, const std::string& name) {
  OutputFile f(dir, name);
  f << kTumHeader;
  for (const auto& a : v.aligned) write_tum_line(f, a.t_s, a.est_p_n, a.est_q_nb);
}

/// dir/alias as the same file as dir/name: a hard link, or a copy where links cannot be made.
void alias(const std::string& dir, const std::string& name, const std::string& alias) {
  const fs::path from = fs::path(dir) / name, to = fs::path(dir) / alias;
  std::error_code ec;
  fs::remove(to, ec);
  fs::create_hard_link(from, to, ec);
  if (ec) fs::copy_file(from, to, fs::copy_options::overwrite_existing);
}

}  // namespace

void write_trajectories(const RunRecord& r, const std::string& dir) {
  static const VehicleTrack kNone;
  const VehicleTrack& primary = r.vehicles.empty() ? kNone : r.vehicles.front();
  // The primary's under the names evo users and older tools know; every vehicle's by name.
  write_truth(primary, dir, "truth.tum");
  write_estimate(primary, dir, "estimate.tum");
  for (std::size_t v = 0; v < r.vehicles.size(); ++v) {
    const auto& veh = r.vehicles[v];
    if (v == 0) {
      alias(dir, "truth.tum", truth_file_name(veh.name));
      alias(dir, "estimate.tum", estimate_file_name(veh.name));
      continue;
    }
    write_truth(veh, dir, truth_file_name(veh.name));
    write_estimate(veh, dir, estimate_file_name(veh.name));
  }
}

void write_timeseries(const RunRecord& r, const std::string& dir) {
  OutputFile f(dir, "timeseries.csv");
  auto& o = f;
  o << "t_s,truth_n_m,truth_e_m,truth_d_m,est_n_m,est_e_m,est_d_m,err_horizontal_m,"
       "err_vertical_m,truth_roll_deg,truth_pitch_deg,truth_yaw_deg,est_roll_deg,"
       "est_pitch_deg,est_yaw_deg,err_attitude_deg,distance_m,nees_position,nees_attitude\n";
  if (r.vehicles.empty()) return;
  for (const auto& a : r.vehicles.front().aligned) {
    const Vec3 e = a.est_p_n - a.truth_p_n;
    const Euler et = euler_from_quat(a.truth_q_nb);
    const Euler ee = euler_from_quat(a.est_q_nb);
    o << a.t_s << ',' << a.truth_p_n.x() << ',' << a.truth_p_n.y() << ',' << a.truth_p_n.z()
      << ',' << a.est_p_n.x() << ',' << a.est_p_n.y() << ',' << a.est_p_n.z() << ','
      << e.head<2>().norm() << ',' << std::abs(e.z()) << ',' << rad_to_deg(et.roll) << ','
      << rad_to_deg(et.pitch) << ',' << rad_to_deg(et.yaw) << ',' << rad_to_deg(ee.roll) << ','
      << rad_to_deg(ee.pitch) << ',' << rad_to_deg(ee.yaw) << ','
      << rad_to_deg(attitude_error_angle(a.truth_q_nb, a.est_q_nb)) << ',' << a.distance_m
      << ',';
    // The NEES of the covariance the DUT stated (empty: none; nan: not positive definite).
    if (a.nees_p) o << *a.nees_p;
    o << ',';
    if (a.nees_att) o << *a.nees_att;
    o << '\n';
  }
}

void write_innovations(const RunRecord& r, const std::string& dir) {
  // Only when the DUT stated innovations ($PNVBINN): most DUTs state none.
  if (r.vehicles.empty() || r.vehicles.front().innovations.empty()) return;
  OutputFile f(dir, "innovations.csv");
  auto& o = f;
  o << "t_s,source,dof,nis\n";
  for (const auto& i : r.vehicles.front().innovations) {
    o << i.t_s << ',' << i.source << ',' << i.dof << ',' << i.nis << '\n';
  }
}

void write_latency(const RunRecord& r, const std::string& dir) {
  {
    OutputFile f(dir, "latency.csv");
    f << "tag,t_valid_s,wire_end_s,rx_s,latency_ms,missed\n";
    for (const auto& l : r.latency) {
      f << l.tag << ',' << l.t_valid_s << ',' << l.wire_end_s << ',';
      if (l.rx_s) f << *l.rx_s << ',' << (*l.rx_s - l.wire_end_s) * 1e3;
      else f << ',';
      f << ',' << (l.missed ? 1 : 0) << '\n';
    }
  }
  OutputFile f(dir, "lateness.csv");
  // A timing audit adds when the witness read each message (empty: not seen intact).
  f << "device,scheduled_s,actual_s,lateness_us"
     << (r.witness_run ? ",arrived_s,arrival_lateness_us\n" : "\n");
  for (const auto& l : r.lateness) {
    f << l.device << ',' << l.scheduled_s << ',' << l.actual_s << ','
       << (l.actual_s - l.scheduled_s) * 1e6;
    if (r.witness_run) {
      f << ',';
      if (l.arrived_s) f << *l.arrived_s << ',' << (*l.arrived_s - l.scheduled_s) * 1e6;
      else f << ',';
    }
    f << '\n';
  }
}

void write_device_rates(const RunRecord& r, const std::string& dir) {
  OutputFile f(dir, "device-rates.csv");
  auto& o = f;
  o << "t_s,device,messages,bytes,bytes_dropped\n";
  o.precision(0);
  for (const auto& d : r.devices) {
    for (std::size_t k = 0; k < d.per_second.size(); ++k) {
      const auto& s = d.per_second[k];
      o << k << ',' << d.name << ',' << s.messages << ',' << s.bytes << ',' << s.bytes_dropped
        << '\n';
    }
  }
}

}  // namespace nav::reports::detail

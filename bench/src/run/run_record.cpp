// SPDX-License-Identifier: MIT
#include "run/run_record.hpp"

#include <algorithm>
#include <filesystem>
#include <optional>

#include "nav/bench/judge.hpp"
#include "nav/common/units.hpp"
#include "nav/bench/runner.hpp"

namespace nav::bench::detail {
namespace {

reports::DeviceRow device_row(const RunFacts& f, std::uint32_t d) {
  const auto& dev = f.devices[d].spec;
  const auto& total = f.log.tally.total(d);
  reports::DeviceRow row{dev.name, dev.type, f.lines[d].path(), dev.baud,
                         emulators::device_seed(f.sc.seed, dev.name), total.messages,
                         total.bytes, total.bytes_dropped, f.suppressed[d]};
  if (dev.on_can()) {
    row.port = f.sc.can_buses[dev.can_bus].interface;
    row.baud = static_cast<int>(f.sc.can_buses[dev.can_bus].bitrate_bps);
    row.messages = f.can.frames_sent(d);
    row.bytes = f.can.bytes_sent(d);
    row.suppressed = 0;
    row.can = true;
    row.frames_dropped = f.can.frames_dropped(d);
  }
  row.per_second = f.log.tally.per_second(d);
  return row;
}

reports::CanBusRow can_bus_row(const RunFacts& f, std::uint32_t b) {
  reports::CanBusRow bus;
  bus.interface = f.sc.can_buses[b].interface;
  bus.bitrate_bps = f.sc.can_buses[b].bitrate_bps;
  std::vector<double> queueing, lateness;
  for (std::size_t k = 0; k < f.can.frames().size(); ++k) {
    const CanTxFrame& tx = f.can.frames()[k];
    if (tx.bus != b) continue;
    if (tx.device == kNoCanDevice) {  // a report of the DUT's controller: no bus time
      ++bus.error_reports;
      continue;
    }
    if (tx.delivery == CanTxFrame::Delivery::kErrorReport) ++bus.error_reports;
    if (tx.delivery == CanTxFrame::Delivery::kWithheld) ++bus.frames_withheld;
    bus.frame_bits += tx.slot.bits;
    queueing.push_back(to_seconds(tx.slot.start - tx.f.t_ready));
  }
  for (std::uint32_t d = 0; d < f.devices.size(); ++d) {
    if (!f.devices[d].spec.on_can() || f.devices[d].spec.can_bus != b) continue;
    bus.frames_sent += f.can.frames_sent(d);
    bus.frames_dropped += f.can.frames_dropped(d);
  }
  for (const auto& l : f.log.can_lateness) {
    if (l.bus == b) lateness.push_back(l.lateness_s);
  }
  bus.bus_load = can_bus_load(f.streams.can_slots[b], f.sc.duration);
  bus.queueing_delay = reports::summarize(std::move(queueing));
  bus.write_lateness = reports::summarize(std::move(lateness));
  return bus;
}

void add_faults(const RunFacts& f, reports::RunRecord& rec) {
  for (std::uint32_t d = 0; d < f.devices.size(); ++d) {
    const auto& dev = f.devices[d].spec;
    const bool polled = f.reactive.polled(d);
    auto records = polled ? f.reactive.polled_fault_records(d) : f.streams.stream_faults[d];
    // Measurement faults affect the messages whose time of validity is in their window.
    const auto& sent = polled         ? f.reactive.answered(d)
                       : dev.on_can() ? f.streams.can_times[d]
                                      : f.streams.serial[d];
    for (const auto& m : measurement_faults(dev)) {
      records.push_back(emulators::measurement_fault_record(m, sent));
    }
    for (const auto& r : records) {
      rec.faults.push_back({dev.name, r.kind, r.start_s, r.end_s, r.messages_affected});
    }
  }
  for (std::size_t b = 0; b < f.streams.can_bus_faults.size(); ++b) {  // the DUT's controller
    for (const auto& r : f.streams.can_bus_faults[b]) {
      rec.faults.push_back(
          {f.sc.can_buses[b].interface, r.kind, r.start_s, r.end_s, r.messages_affected});
    }
  }
}

/// Every log a DUT filled past the limit: the receive captures and the DUT logs.
void add_logs_cut(const RunFacts& f, reports::RunRecord& rec) {
  const auto note = [&](const std::filesystem::path& file, std::uint64_t limit,
                        std::uint64_t cut) {
    if (cut > 0) rec.logs_cut.push_back({file.filename().string(), limit, cut});
  };
  note(f.log.rx->path(), f.log.rx->limit(), f.log.rx->cut_bytes());
  for (const auto& veh : f.watch.vehicles()) {
    if (veh.output_capture) {
      note(veh.output_capture->path(), veh.output_capture->limit(),
           veh.output_capture->cut_bytes());
    }
    if (veh.log_limit) {
      note(veh.log_limit->path(), veh.log_limit->limit(), veh.log_limit->cut_bytes());
    }
  }
}

}  // namespace

reports::RunRecord make_run_record(const RunFacts& f, const RunIdentity& id) {
  const Scenario& sc = f.sc;
  const auto& vehicles = f.watch.vehicles();
  const Vehicle& primary = vehicles.front();
  const std::string dut_status = f.watch.primary_status();
  const TruthTable table(*primary.truth, sc.duration, sc.truth_rate_hz);
  JudgeInput in{&sc, &table, primary.triggers, primary.reader->answers(), f.t0,
                f.watch.primary_alive(), dut_status};
  if (const auto stopped = f.watch.stopped_at()) in.stopped_at_s = to_seconds(*stopped);
  in.restarts = primary.restarts;
  const std::vector<CheckSpec> primary_checks = checks_of_vehicle(sc, 0);
  in.checks = &primary_checks;
  JudgeOutput j = judge(in);

  reports::RunRecord rec;
  rec.started_utc = id.started_utc;
  rec.scenario_name = sc.name;
  rec.scenario_file = sc.file;
  rec.scenario_description = sc.description;
  rec.scenario_sha256 = id.scenario_sha256;
  rec.navbench_version = id.navbench_version;
  rec.host = id.host;
  rec.kernel = id.kernel;
  rec.labels.assign(sc.labels.begin(), sc.labels.end());
  rec.mode = sc.mode == TimeMode::kRealtime ? "realtime" : "lockstep";
  rec.seed = sc.seed;
  if (sc.wall) {
    const Vec3& o = sc.trajectory.start_p_n;
    rec.wall = reports::RunRecord::Wall{units::rad_to_deg(sc.wall->slope_rad),
                                        units::rad_to_deg(sc.wall->azimuth_rad),
                                        {o.x(), o.y(), o.z()}};
  }
  rec.duration_s = to_seconds_exact(sc.duration);  // 60 s is 60, not 60.00000000000001
  rec.stopped_at_s = in.stopped_at_s;
  rec.dut_command = primary.argv;
  if (!id.dut_executables.empty()) std::tie(rec.dut_executable, rec.dut_sha256) = id.dut_executables[0];
  if (!id.dut_files.empty()) rec.dut_files = id.dut_files[0];
  rec.dut_status = dut_status;
  rec.triggers_sent = primary.triggers_sent;
  rec.answers = in.answers.size();
  rec.unmatched_answers = j.unmatched_answers;
  rec.malformed_output = primary.reader->malformed();
  rec.malformed_examples = primary.reader->malformed_examples();
  add_logs_cut(f, rec);
  rec.checks = std::move(j.checks);
  for (auto& c : rec.checks) c.vehicle = sc.vehicle_name;
  std::vector<reports::CheckResult> peer_checks;  // after the primary's, vehicle by vehicle
  for (std::size_t v = 0; v < vehicles.size(); ++v) {
    const Vehicle& veh = vehicles[v];
    reports::VehicleTrack track;
    track.name = veh.name;
    std::optional<TruthTable> own;
    if (v > 0) own.emplace(*veh.truth, sc.duration, sc.truth_rate_hz);
    const TruthTable& truth = v == 0 ? table : *own;
    for (const auto& s : truth.samples()) {
      track.truth.push_back({to_seconds(s.t), s.p_n, s.q_nb, s.distance_m});
    }
    if (v == 0) {
      track.aligned = std::move(j.aligned);
      track.innovations = std::move(j.innovations);
    } else {
      // A peer is judged like the primary, by the checks that name it (or all vehicles).
      JudgeInput pin{&sc, &truth, veh.triggers, veh.reader->answers(), f.t0, !veh.failed,
                     veh.status};
      pin.stopped_at_s = in.stopped_at_s;
      pin.restarts = veh.restarts;
      const std::vector<CheckSpec> mine = checks_of_vehicle(sc, v);
      pin.checks = &mine;
      JudgeOutput pj = judge(pin);
      track.aligned = std::move(pj.aligned);
      track.innovations = std::move(pj.innovations);
      for (auto& c : pj.checks) {
        c.vehicle = veh.name;
        peer_checks.push_back(std::move(c));
      }
    }
    track.triggers_sent = veh.triggers_sent;
    track.answers = veh.reader->answer_count();
    track.dut_status = v == 0 ? dut_status : veh.status;
    rec.vehicles.push_back(std::move(track));
  }
  for (auto& c : peer_checks) rec.checks.push_back(std::move(c));
  rec.latency = std::move(j.latency);
  rec.dut_latency = j.dut_latency;
  std::vector<double> late;
  const std::vector<LatenessEntry> sent = f.log.lateness.read_all();
  for (const auto& l : sent) {
    late.push_back(l.actual_s - l.scheduled_s);
    rec.lateness.push_back({f.devices[l.device].spec.name, l.scheduled_s, l.actual_s});
  }
  if (f.witness) add_witness(f, sent, rec);
  rec.bench_lateness = reports::summarize(late);
  rec.lateness_budget_p99_s = to_seconds(sc.lateness_budget_p99);
  rec.lateness_over_budget = static_cast<std::size_t>(std::count_if(
      late.begin(), late.end(), [&](double s) { return s > rec.lateness_budget_p99_s; }));
  for (std::uint32_t d = 0; d < f.devices.size(); ++d) rec.devices.push_back(device_row(f, d));
  for (std::uint32_t b = 0; b < sc.can_buses.size(); ++b) rec.can_buses.push_back(can_bus_row(f, b));
  add_faults(f, rec);
  rec.restarts = std::move(j.restarts);
  for (const auto& r : rec.restarts) {
    rec.faults.push_back({"dut", "restart", r.off_s, r.on_s, r.triggers_in_gap});
  }
  for (std::size_t v = 1; v < vehicles.size(); ++v) {
    const auto& veh = vehicles[v];
    reports::PeerRow peer;
    peer.name = veh.name;
    peer.dut_command = veh.argv;
    if (v < id.dut_executables.size()) {
      std::tie(peer.dut_executable, peer.dut_sha256) = id.dut_executables[v];
    }
    if (v < id.dut_files.size()) peer.dut_files = id.dut_files[v];
    peer.dut_status = veh.status;
    peer.triggers_sent = veh.triggers_sent;
    peer.answers = veh.reader->answer_count();
    rec.peers.push_back(std::move(peer));
  }
  for (const auto& l : f.reactive.links()) {
    const auto& s = l.stats;
    rec.modem_links.push_back({f.devices[l.from].spec.name, f.devices[l.to].spec.name,
                               s.packets_sent, s.packets_delivered, s.packets_lost,
                               s.packets_out_of_range, s.bytes_delivered,
                               to_seconds(s.min_propagation), to_seconds(s.max_propagation)});
  }
  std::string dut_fault;
  if (primary.never_commanded) {
    dut_fault = "it never sent the start command";
  } else if (rec.malformed_output > 0) {
    dut_fault = "it wrote " + std::to_string(rec.malformed_output) + " malformed lines";
  }
  std::tie(rec.verdict, rec.exit_code) =
      verdict_of(rec, f.interrupted, f.watch.crashed(), f.watch.hung(), dut_fault);
  return rec;
}

std::pair<std::string, int> verdict_of(reports::RunRecord& r, bool interrupted, bool crashed,
                                       bool hung, const std::string& dut_fault) {
  const bool any_failed = std::any_of(r.checks.begin(), r.checks.end(),
                                      [](const auto& c) { return c.judged && !c.passed; });
  r.bench_late = reports::bench_late(r.bench_lateness, r.lateness_budget_p99_s);
  if (interrupted) return {"INTERRUPTED", kExitBench};
  if (crashed) return {"DUT crashed", kExitDut};
  if (hung) return {"DUT hung", kExitDut};
  if (r.bench_late) {
    if (!any_failed || dut_fault.empty()) return {"BENCH-LATE", kExitBench};
    r.notes.push_back("the bench was late as well (" +
                      std::to_string(r.lateness_over_budget) +
                      " messages over the lateness budget), but the DUT failed in a way no "
                      "timing explains: " + dut_fault);
  }
  // A timing audit fails when a byte the bench wrote did not reach the witness intact.
  bool lost = false;
  for (const auto& w : r.witness) {
    if (w.bytes_matched == w.bytes_sent && w.bytes_seen == w.bytes_sent) continue;
    lost = true;
    r.notes.push_back("witness: '" + w.device + "' " + std::to_string(w.bytes_sent) +
                      " bytes written, " + std::to_string(w.bytes_seen) + " read, the first " +
                      std::to_string(w.bytes_matched) + " as written");
  }
  if (any_failed || lost) return {"FAIL", kExitFail};
  return {"PASS", kExitPass};
}

}  // namespace nav::bench::detail

// SPDX-License-Identifier: MIT
// The one-screen verdict printed at the end of a run.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <sstream>

#include "nav/reports/run_record.hpp"

namespace nav::reports {

std::string fault_text(const FaultRow& f) {
  char line[256];
  std::snprintf(line, sizeof line, "%s %s %.1f\u2013%.1f s, %zu message%s", f.device.c_str(),
                f.kind.c_str(), f.start_s, f.end_s, f.messages_affected,
                f.messages_affected == 1 ? "" : "s");
  return line;
}

namespace {

/// "256 MiB", "1.5 GiB", "512 bytes".
std::string byte_size(std::uint64_t n) {
  char buf[32];
  if (n < 1024) {
    std::snprintf(buf, sizeof buf, "%llu bytes", static_cast<unsigned long long>(n));
  } else if (n < (1ull << 20)) {
    std::snprintf(buf, sizeof buf, "%.3g KiB", static_cast<double>(n) / 1024.0);
  } else if (n < (1ull << 30)) {
    std::snprintf(buf, sizeof buf, "%.3g MiB", static_cast<double>(n) / (1 << 20));
  } else {
    std::snprintf(buf, sizeof buf, "%.3g GiB", static_cast<double>(n) / (1 << 30));
  }
  return buf;
}

/// `run --witness`: what reached the witness, its arrival lateness and the lines' pacing.
std::string witness_text(const RunRecord& r) {
  std::size_t sent = 0, seen = 0;
  std::uint64_t bytes = 0;
  double pace_lo = 0.0, pace_hi = 0.0;
  bool paced = false;
  for (const auto& w : r.witness) {
    sent += w.messages;
    seen += w.messages_seen;
    bytes += w.bytes_sent;
    if (!w.pacing_median) continue;
    pace_lo = paced ? std::min(pace_lo, *w.pacing_median) : *w.pacing_median;
    pace_hi = paced ? std::max(pace_hi, *w.pacing_median) : *w.pacing_median;
    paced = true;
  }
  const Stats a = witness_arrival_lateness(r);
  char line[256];
  std::string o;
  std::snprintf(line, sizeof line,
                "  witness: %zu of %zu messages (%llu bytes) on %zu lines arrived as written\n",
                seen, sent, static_cast<unsigned long long>(bytes), r.witness.size());
  o += line;
  std::snprintf(line, sizeof line,
                "  witness arrival lateness  p50 %.3f ms  p99 %.3f ms  max %.3f ms  (%zu)\n",
                a.p50_s * 1e3, a.p99_s * 1e3, a.max_s * 1e3, a.count);
  o += line;
  if (paced) {
    std::snprintf(line, sizeof line,
                  "  witness byte pacing  median %.4f to %.4f of the baud's byte time, by line\n",
                  pace_lo, pace_hi);
    o += line;
  }
  return o;
}

}  // namespace

std::string verdict_text(const RunRecord& r) {
  std::ostringstream o;
  char line[256];
  std::snprintf(line, sizeof line,
                "navbench run %s  (seed %llu, %s, %.1f s, wall %.1f s, bench CPU %.0f %%)\n",
                r.scenario_name.c_str(), static_cast<unsigned long long>(r.seed), r.mode.c_str(),
                r.duration_s, r.wall_time_s,
                r.wall_time_s > 0 ? 100.0 * r.bench_cpu_s / r.wall_time_s : 0.0);
  o << line;
  if (r.stopped_at_s) {
    std::snprintf(line, sizeof line,
                  "  stopped by a signal at t=%.2f s of %.1f s: checks that need the rest are "
                  "not judged\n",
                  *r.stopped_at_s, r.duration_s);
    o << line;
  }
  if (r.witness_run) {
    // A timing audit: the witness stood in the DUT's place.
    o << "  timing audit: navbench witness in the DUT's place, " << r.dut_status << "; "
      << r.triggers_sent << " triggers sent\n";
  } else {
    o << "  DUT: " << r.dut_status << "; " << r.answers << " solutions for " << r.triggers_sent
      << " triggers";
  if (r.unmatched_answers) o << ", " << r.unmatched_answers << " naming no trigger";
    if (r.malformed_output) o << ", " << r.malformed_output << " malformed lines";
    o << '\n';
  }
  for (const auto& m : r.malformed_examples) {
    std::snprintf(line, sizeof line, "    malformed at t=%.3f s: ", m.rx_s);
    o << line << m.why << ": \"" << m.text << "\"\n";
  }
  for (const auto& rs : r.restarts) {
    std::snprintf(line, sizeof line, "  restart: off at t=%.2f s (%s), on at t=%.2f s: ", rs.off_s,
                  rs.ended.c_str(), rs.on_s);
    o << line;
    if (!rs.started_again) {
      std::snprintf(line, sizeof line, "the run ended before it");
    } else if (rs.recovery_s) {
      std::snprintf(line, sizeof line, "first valid solution %.3f s later", *rs.recovery_s);
    } else if (rs.first_solution_s) {
      std::snprintf(line, sizeof line, "solutions from t=%.2f s, none with a valid position",
                    *rs.first_solution_s);
    } else {
      std::snprintf(line, sizeof line, "no solution after it");
    }
    o << line << "; " << rs.triggers_in_gap << " triggers unanswered in between\n";
  }
  for (const auto& n : r.notes) o << "  note: " << n << '\n';
  for (const auto& c : r.logs_cut) {
    o << "  note: " << c.file << " was cut at its limit of " << byte_size(c.limit_bytes) << ": "
      << byte_size(c.cut_bytes) << " more the DUT wrote were not kept (navbench run "
      << "--log-limit)\n";
  }
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
    if (b.error_reports > 0 || b.frames_withheld > 0) {
      std::snprintf(line, sizeof line,
                    "  CAN %s faults: %zu error frames reported to the DUT, %zu frames it missed "
                    "while bus-off\n",
                    b.interface.c_str(), b.error_reports, b.frames_withheld);
      o << line;
    }
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
    const std::string req = c.req.empty() ? std::string() : " [" + c.req + "]";
    std::snprintf(line, sizeof line, "  %s  %-17s %s%s\n", tag, c.name.c_str(), c.detail.c_str(),
                  req.c_str());
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
    if (r.bench_lateness.count < kMinMessagesForP99) {
      o << line;
      std::snprintf(line, sizeof line,
                    "  bench lateness  fewer than %zu messages: the median judged, not the p99 "
                    "(%zu over the budget)\n",
                    kMinMessagesForP99, r.lateness_over_budget);
    }
  } else if (r.mode == "lockstep") {
    std::snprintf(line, sizeof line, "  bench lateness  n/a (lockstep: virtual time)\n");
  } else {
    std::snprintf(line, sizeof line, "  bench lateness  n/a (no message was written)\n");
  }
  o << line;
  if (r.witness_run) {
    o << witness_text(r);
  } else {
    std::snprintf(line, sizeof line, "  %-14s  p50 %.3f ms  p99 %.3f ms  max %.3f ms  (%zu)\n",
                  r.mode == "lockstep" ? "DUT compute" : "DUT latency", ms(r.dut_latency.p50_s),
                  ms(r.dut_latency.p99_s), ms(r.dut_latency.max_s), r.dut_latency.count);
    o << line;
  }
  o << "VERDICT: " << r.verdict << "   report: " << r.run_dir << "/report.html\n";
  return o.str();
}

}  // namespace nav::reports

// SPDX-License-Identifier: MIT
#include "judge/restarts.hpp"

#include <algorithm>
#include <cstdio>
#include <string>

namespace nav::bench::detail {

RestartGaps restart_gaps(const JudgeInput& in, const Alignment& al) {
  const bool lockstep = in.scenario->mode == TimeMode::kLockstep;
  const auto& triggers = in.triggers;
  RestartGaps out;
  out.in_gap.assign(triggers.size(), 0);
  for (std::size_t k = 0; k < in.restarts.size(); ++k) {
    const RestartRecord& r = in.restarts[k];
    reports::RestartRow row;
    row.off_s = to_seconds_exact(r.off_at);
    row.on_s = to_seconds_exact(r.on_at);
    row.ended = r.ended;
    const bool started = r.started != Timestamp{};
    row.started_again = started;
    // This DUT's solutions: from its start to the next power-off.
    const Timestamp until =
        k + 1 < in.restarts.size() ? in.restarts[k + 1].killed : Timestamp::max();
    // The scenario time of an answer to trigger i that arrived at rx: realtime, its arrival;
    // lockstep (answers come between two writes), its trigger's, not before the restart.
    const auto when = [&](std::size_t i, Timestamp rx) {
      return lockstep ? std::max(to_seconds_exact(triggers[i].t_valid), row.on_s)
                      : to_seconds(rx - in.t0);
    };
    for (std::size_t i = 0; started && i < triggers.size(); ++i) {
      const auto& tr = triggers[i];
      if (!tr.sent || tr.wire_end < r.started || tr.wire_end >= until) continue;
      if (al.first_rx[i] && !row.first_solution_s) row.first_solution_s = when(i, *al.first_rx[i]);
      if (al.first_valid_rx[i] && !row.first_valid_s) {
        row.first_valid_s = when(i, *al.first_valid_rx[i]);
        break;
      }
    }
    if (row.first_valid_s) row.recovery_s = *row.first_valid_s - row.on_s;
    // The gap: after its last solution before the power-off, before its first after the
    // restart (answers arrive in order).
    Timestamp gap_begin{}, gap_end = until;
    for (const auto& a : in.answers) {
      if (a.rx < r.killed) gap_begin = a.rx;
      if (started && a.rx >= r.started && a.rx < until) {
        gap_end = a.rx;
        break;
      }
    }
    for (std::size_t i = 0; i < triggers.size(); ++i) {
      const auto& tr = triggers[i];
      if (!tr.sent || al.first_rx[i] || tr.wire_end <= gap_begin || tr.wire_end >= gap_end) {
        continue;
      }
      out.in_gap[i] = 1;
      ++row.triggers_in_gap;
    }
    out.rows.push_back(row);
  }
  return out;
}

void judge_restart_recovery(reports::CheckResult& r, const std::vector<reports::RestartRow>& rows,
                            std::optional<double> stopped_at_s) {
  char buf[200];
  r.passed = true;
  std::size_t judged = 0;
  std::string missing;
  for (const auto& row : rows) {
    if (!row.recovery_s) {
      if (stopped_at_s) continue;  // the run stopped before it could recover
      std::snprintf(buf, sizeof buf, "no valid solution after the restart at t=%.2f s", row.on_s);
      if (missing.empty()) {
        missing = buf;
        r.worst_t_s = row.on_s;
      }
      r.passed = false;
      continue;
    }
    ++judged;
    if (*row.recovery_s > r.limit) r.passed = false;
    if (*row.recovery_s >= r.value) {
      r.value = *row.recovery_s;
      if (missing.empty()) r.worst_t_s = row.on_s;
    }
  }
  if (!missing.empty()) {
    r.detail = missing;
    return;
  }
  if (judged == 0) {
    r.judged = false;
    r.passed = false;
    std::snprintf(buf, sizeof buf,
                  "not judged: the run was stopped at t=%.2f s, before a valid solution after "
                  "its restart",
                  stopped_at_s.value_or(0.0));
    r.detail = buf;
    return;
  }
  std::snprintf(buf, sizeof buf, "worst %.3f s from restart to a valid solution (limit %.3f s)",
                r.value, r.limit);
  r.detail = buf;
  std::snprintf(buf, sizeof buf, ", at t=%.2f s, %zu restart%s", r.worst_t_s.value_or(0.0), judged,
                judged == 1 ? "" : "s");
  r.detail += buf;
}

}  // namespace nav::bench::detail

// SPDX-License-Identifier: MIT
// The DUT's restarts (a `restart` fault of dut.faults), judged: when it gave a solution, and a
// valid one, again; which triggers fell in the gap nobody could answer; the restart_recovery
// check. Private to nav_bench.
#pragma once

#include <optional>
#include <vector>

#include "nav/bench/judge.hpp"

namespace nav::bench::detail {

struct RestartGaps {
  std::vector<reports::RestartRow> rows;  ///< one per JudgeInput::restarts
  /// Per trigger: unanswered, and sent between the DUT's last solution before a power-off and
  /// its first solution after the restart (a deadline check does not count it).
  std::vector<char> in_gap;
};

/// The restarts of in, with the answers aligned to its triggers (align_answers).
RestartGaps restart_gaps(const JudgeInput& in, const Alignment& al);

/// Judges r (a restart_recovery check, its name and limit set): every restart is followed by
/// a valid solution within r.limit seconds.
void judge_restart_recovery(reports::CheckResult& r, const std::vector<reports::RestartRow>& rows,
                            std::optional<double> stopped_at_s);

}  // namespace nav::bench::detail

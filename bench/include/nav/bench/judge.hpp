// SPDX-License-Identifier: MIT
// Judging a run: align the DUT's solutions to truth (interpolated at each trigger's time of
// validity, never nearest-sample), compute latencies, run the scenario's checks.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "nav/bench/output_reader.hpp"
#include "nav/bench/scenario.hpp"
#include "nav/common/geodesy.hpp"
#include "nav/emulators/truth.hpp"
#include "nav/reports/run_record.hpp"

namespace nav::bench {

/// A trigger message and when it actually left.
struct TriggerRecord {
  std::uint64_t tag = 0;
  Duration t_valid{};      ///< scenario time of validity
  bool sent = false;
  Timestamp wire_end{};    ///< CLOCK_MONOTONIC when its last byte was written
};

/// A restart of the DUT (a `restart` fault of dut.faults), as it happened.
struct RestartRecord {
  Duration off_at{}, on_at{};  ///< scenario times of the power-off and of the restart
  Timestamp killed{};          ///< CLOCK_MONOTONIC when its group was killed
  Timestamp started{};         ///< CLOCK_MONOTONIC when it was started again (0: it was not)
  std::string ended;           ///< how the killed process ended
};

/// Truth sampled at a fixed rate, interpolated linearly (position, velocity, distance) and
/// by slerp (attitude) in between.
class TruthTable {
 public:
  TruthTable(const emulators::Truth& truth, Duration duration, double rate_hz);
  /// Truth at t within [0, duration].
  emulators::TruthSample at(double t_s) const;
  const std::vector<emulators::TruthSample>& samples() const { return samples_; }

 private:
  std::vector<emulators::TruthSample> samples_;
  double dt_s_;
};

struct JudgeInput {
  const Scenario* scenario = nullptr;
  const TruthTable* truth = nullptr;
  std::vector<TriggerRecord> triggers;  ///< in send order
  std::vector<Answer> answers;          ///< in arrival order
  Timestamp t0{};                       ///< CLOCK_MONOTONIC of scenario time 0
  bool dut_alive = true;                ///< DUT ran to the end and did not hang
  std::string dut_status;
  /// The scenario time a signal stopped the run at; none for a run that reached its end.
  std::optional<double> stopped_at_s{};
  std::vector<RestartRecord> restarts{};  ///< the DUT's restarts, in time order
  /// The checks judged (checks_of_vehicle() of this DUT's vehicle); null: the primary's.
  const std::vector<CheckSpec>* checks = nullptr;
};

struct JudgeOutput {
  std::vector<reports::CheckResult> checks;
  std::vector<reports::AlignedSample> aligned;
  std::vector<reports::InnovationSample> innovations;
  std::vector<reports::LatencyRow> latency;
  reports::Stats dut_latency;
  std::size_t unmatched_answers = 0;
  std::vector<reports::RestartRow> restarts;  ///< one per JudgeInput::restarts
};

JudgeOutput judge(const JudgeInput& in);

/// A vehicle's solutions matched to the triggers they name and aligned to its truth.
struct Alignment {
  std::vector<reports::AlignedSample> aligned;  ///< valid positions, by time of validity
  /// The innovations stated with every matched solution (a valid position or not), by time.
  std::vector<reports::InnovationSample> innovations;
  std::vector<std::optional<Timestamp>> first_rx;  ///< per trigger: its first answer's arrival
  /// Per trigger: the arrival of its first answer with a valid position.
  std::vector<std::optional<Timestamp>> first_valid_rx;
  std::size_t unmatched = 0;  ///< answers naming no trigger that was sent
};

/// Aligns answers to truth at their trigger's time of validity (interpolated; positions
/// from geodetic to NED at datum). Used for every vehicle; judge() uses it for the primary.
Alignment align_answers(const std::vector<TriggerRecord>& triggers,
                        const std::vector<Answer>& answers, const TruthTable& truth,
                        const geodesy::Geodetic& datum);

}  // namespace nav::bench

// SPDX-License-Identifier: MIT
// The instants at which a run began writing messages, and on which lines: read back from its
// lateness.csv, for the write floor (write_floor.hpp) to write the same bursts.
#pragma once

#include <string>
#include <vector>

#include "nav/reports/run_folder.hpp"

namespace nav::benchmarks {

/// One instant of a run's schedule: every line a message was due to begin on then, in the
/// order the run wrote them.
struct WriteInstant {
  double t_s = 0.0;        ///< scheduled wire time [s]
  std::vector<int> lines;  ///< indices into WriteSchedule::lines
};

struct WriteSchedule {
  std::vector<std::string> lines;  ///< device names, in order of first appearance
  std::vector<WriteInstant> instants;
  std::size_t messages = 0;
};

/// The rows of lateness.csv (columns device, scheduled_s) scheduled before `seconds`, grouped
/// by scheduled time, in time order (rows equal in time are one instant wherever they are).
WriteSchedule write_schedule(const reports::CsvColumns& lateness, double seconds);

}  // namespace nav::benchmarks

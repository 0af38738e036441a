// SPDX-License-Identifier: MIT
// The machine-readable files of a run folder, in one call.
#include "nav/reports/run_record.hpp"
#include "writers.hpp"

namespace nav::reports {

void write_reports(const RunRecord& r, const std::string& dir) {
  detail::write_summary(r, dir);
  detail::write_junit(r, dir);
  detail::write_trajectories(r, dir);
  detail::write_timeseries(r, dir);
  detail::write_innovations(r, dir);
  detail::write_latency(r, dir);
  detail::write_device_rates(r, dir);
}

std::string truth_file_name(const std::string& vehicle) { return "truth-" + vehicle + ".tum"; }
std::string estimate_file_name(const std::string& vehicle) {
  return "estimate-" + vehicle + ".tum";
}

}  // namespace nav::reports

// SPDX-License-Identifier: MIT
// The writers write_reports() calls, one per file family. Private to nav_reports.
#pragma once

#include <string>

#include "nav/reports/run_record.hpp"

namespace nav::reports::detail {

void write_summary(const RunRecord& r, const std::string& dir);       // summary_json.cpp
void write_junit(const RunRecord& r, const std::string& dir);         // junit_xml.cpp
void write_trajectories(const RunRecord& r, const std::string& dir);  // run_tables.cpp
void write_timeseries(const RunRecord& r, const std::string& dir);    // run_tables.cpp
void write_innovations(const RunRecord& r, const std::string& dir);   // run_tables.cpp
void write_latency(const RunRecord& r, const std::string& dir);       // run_tables.cpp
void write_device_rates(const RunRecord& r, const std::string& dir);  // run_tables.cpp

}  // namespace nav::reports::detail

// SPDX-License-Identifier: MIT
// A run folder as read back from its files: what `navbench report` and every run's
// report.html are made from, so that a run copied from another machine, or made by an older
// navbench, can be reported. summary.json is required; each other file may be missing (an
// older run did not write it: the report says so), but a file that is there must be whole.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "nav/common/result.hpp"

namespace nav::reports {

/// Named numeric columns of one CSV file (empty fields are NaN), plus its text columns.
struct CsvColumns {
  std::size_t rows = 0;
  std::map<std::string, std::vector<double>> numbers;
  std::map<std::string, std::vector<std::string>> texts;
  /// The column, or an empty vector when the file has no such column.
  const std::vector<double>& operator[](const std::string& name) const;
};

/// Reads a CSV file the bench wrote (a header line, then comma-separated fields without
/// quotes). Columns in text_columns are kept as text, all others must be numbers or empty.
/// Errors name "file:line".
Result<CsvColumns> read_csv(const std::string& path, const std::vector<std::string>& text_columns);

/// One measurement's rows of innovations.csv: the dimension of its first row, and the time
/// and NIS of each of its rows with that dimension.
struct InnovationSeries {
  int dof = 0;
  std::vector<double> t_s, nis;
};

/// innovations.csv (read with text column "source") by measurement name; rows whose dimension
/// is not 1..4, or not their measurement's first, are left out.
std::map<std::string, InnovationSeries> innovations_by_source(const CsvColumns& csv);

/// One pose of a TUM trajectory file.
struct TumPose {
  double t_s = 0.0;
  double n = 0.0, e = 0.0, d = 0.0;     ///< NED at the datum [m]
  double qx = 0.0, qy = 0.0, qz = 0.0, qw = 1.0;
};

/// Reads a TUM file (`t x y z qx qy qz qw`, '#' comments). Errors name "file:line".
Result<std::vector<TumPose>> read_tum(const std::string& path);

/// One vehicle's track (truth and estimate).
struct VehicleFiles {
  std::string name;
  bool primary = false;
  bool has_truth = false, has_estimate = false;
  std::vector<TumPose> truth, estimate;
};

struct RunFolder {
  std::string dir;
  nlohmann::json summary;          ///< summary.json
  bool has_timeseries = false, has_latency = false, has_lateness = false, has_rates = false;
  CsvColumns timeseries;           ///< timeseries.csv
  CsvColumns latency;              ///< latency.csv
  CsvColumns lateness;             ///< lateness.csv (text column: device)
  CsvColumns rates;                ///< device-rates.csv (text column: device)
  bool has_innovations = false;
  CsvColumns innovations;          ///< innovations.csv (text column: source), when stated
  std::vector<VehicleFiles> vehicles;  ///< the primary first
  bool has_dut_log = false;
  std::string dut_log_tail;        ///< the last lines of dut.log (at most kDutLogTailBytes)
  bool dut_log_cut = false;        ///< dut.log was longer than its tail
};

/// How much of the end of dut.log a report shows [bytes].
inline constexpr std::size_t kDutLogTailBytes = 24 * 1024;

/// Reads a run folder. Fails (the message names the folder or the file and line) when dir is
/// not a folder, has no readable summary.json with a verdict and a scenario, or a file in it
/// is damaged.
Result<RunFolder> read_run_folder(const std::string& dir);

}  // namespace nav::reports

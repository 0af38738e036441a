// SPDX-License-Identifier: MIT
// navd's optional YAML config file: a flat map of FilterParams fields by name, e.g.
//
//   attitude_kp_per_s: 0.8
//   gps_horizontal_std_m: 1.5
//
// Unknown keys, non-numeric values and out-of-range values are errors located as
// "file:line:col: ..." (1-based).
#pragma once

#include <string>

#include "nav/common/result.hpp"
#include "nav/estimator/filter_params.hpp"

namespace nav::dut {

/// Loads `path` over the defaults of FilterParams. The error detail is one line.
Result<estimator::FilterParams> load_config(const std::string& path);

/// One line per parameter, "name (default): description", for --help.
std::string config_keys_help();

}  // namespace nav::dut

// SPDX-License-Identifier: MIT
// The keys of navd's config file that set paper P1's navigators (navigator: ins, ekf15, upf15, mfins):
// every P1Params field by name with its unit (p1_types.hpp), the initial attitude as ZYX Euler
// angles. The seed of the particle filters comes from the command line (--seed), not here.
#pragma once

#include <span>
#include <string>

#include "nav/estimator/p1_types.hpp"

namespace nav::dut {

/// One P1Params quantity by name.
struct P1Field {
  const char* name;                                ///< e.g. "p1_gps_position_std_m"
  const char* doc;                                 ///< one line with its unit
  double (*get)(const estimator::P1Params&);       ///< its value
  void (*set)(estimator::P1Params&, double);       ///< sets it (angles in degrees as named)
};

/// Every P1 key, in the order of P1Params.
std::span<const P1Field> p1_fields();

/// The P1 field named `key`, or nullptr.
const P1Field* find_p1_field(const std::string& key);

}  // namespace nav::dut

// SPDX-License-Identifier: MIT
// The keys of navd's config file that set paper P2's cooperative navigator (navigator: p2,
// p2_navigator.hpp): the vehicles, the experiment's observation set, the joint filter's
// noises (P2Params), the own navigation's initial uncertainty and the AHRS timer at mission
// time 0.
#pragma once

#include <span>
#include <string>

#include "nav/common/result.hpp"
#include "nav/estimator/p2_types.hpp"

namespace nav::dut {

/// navigator: p2.
struct P2Config {
  estimator::P2Params filter;  ///< the joint filter's noises, gate and history
  int vehicles = 2;            ///< N: vehicle ids 1..N, 2 ≤ N ≤ kP2MaxVehicles
  int experiment = 4;          ///< the paper's observation set, 1..4 (1: none)
  /// 1-σ of the own navigation's start (the GPS fix at the surface) per axis [m].
  double initial_position_std_m = 2.0;
  double initial_heading_std_rad = 0.035;  ///< 1-σ of the start heading [rad]
  double initial_pitch_std_rad = 0.0175;   ///< 1-σ of the start pitch [rad]
  /// The GX3 timer at mission time 0 (the scenario's `timer_start`) [ticks of 1/62500 s].
  double timer_start_ticks = 0.0;
};

/// Every field in range, or an error naming the key.
Result<void> validate(const P2Config& c);

/// One P2Config quantity by name.
struct P2Field {
  const char* name;                     ///< e.g. "p2_experiment"
  const char* doc;                      ///< one line with its unit
  double (*get)(const P2Config&);       ///< its value
  void (*set)(P2Config&, double);       ///< sets it
};

/// Every P2 key.
std::span<const P2Field> p2_fields();

/// The P2 field named `key`, or nullptr.
const P2Field* find_p2_field(const std::string& key);

}  // namespace nav::dut

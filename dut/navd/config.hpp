// SPDX-License-Identifier: MIT
// navd's optional YAML config file: a flat map of FilterParams fields and of navd's own
// parameters (NavdParams) by name, plus two choices by name, e.g.
//
//   navigator: dvl            # gps-ins (default), dvl, a P1 navigator, p2, a P3 or a P4 navigator
//   attitude_filter: ekf      # mahony (default), raw, ekf, ukf, cf or eskf
//   attitude_kp_per_s: 0.8
//   gps_horizontal_std_m: 1.5
//
// Unknown keys, non-numeric values and out-of-range values are errors located as
// "file:line:col: ..." (1-based).
#pragma once

#include <string>

#include "nav/common/result.hpp"
#include "nav/estimator/attitude_filter.hpp"
#include "nav/estimator/filter_params.hpp"
#include "nav/estimator/p1_types.hpp"
#include "config_p2.hpp"
#include "config_p3.hpp"
#include "config_p4.hpp"

namespace nav::dut {

/// navd's own tunables, beside the estimator's: they time navd's I/O, not the filter.
struct NavdParams {
  /// Time between two $PNVBPOS position reports on the acoustic modem (--modem), counted
  /// on the AHRS timer, (0, 3600] [s].
  double modem_period_s = 2.0;
};

/// Which navigator navd runs.
enum class NavigatorKind {
  kGpsIns,  ///< "gps-ins": AHRS + GPS (+ depth) Kalman filter anchored at the first GPS fix
  kDvl,     ///< "dvl": DVL dead reckoning from the configured origin (paper P0)
  kP1,      ///< "ins", "ekf15", "upf15", "mfins": a paper P1 navigator (p1_driver.hpp), NavdConfig::p1_navigator
  kP2,      ///< "p2": paper P2's cooperative localisation (p2_navigator.hpp), the p2_* keys
  kP3,      ///< "p3-dr", "p3-ekf", "p3-ekf-kr": paper P3's crawler (p3_navigator.hpp), P3Config::method
  kP4,      ///< "p4-ukf", "p4-dwt-ukf": paper P4's sea-surface beacon (p4_navigator.hpp), P4Config::method
};

/// Everything a config file sets.
struct NavdConfig {
  estimator::FilterParams filter;  ///< estimator parameters
  NavdParams navd;                 ///< navd's own parameters
  NavigatorKind navigator = NavigatorKind::kGpsIns;  ///< key `navigator`
  estimator::AttitudeFilterKind attitude =
      estimator::AttitudeFilterKind::kMahony;        ///< key `attitude_filter`
  std::string p1_navigator;   ///< with kP1: the P1 navigator's name ("ins", "ekf15", "upf15", "mfins")
  estimator::P1Params p1;     ///< the p1_* keys (config_p1.hpp); seed from --seed
  P2Config p2;                ///< the p2_* keys (config_p2.hpp)
  P3Config p3;                ///< the p3_* keys and, with kP3, the method (config_p3.hpp)
  P4Config p4;                ///< the p4_* keys and, with kP4, the method (config_p4.hpp)
};

/// The navigator's name: "gps-ins", "dvl", "p2", a P3 or P4 navigator's or the P1 navigator's.
std::string navigator_name(const NavdConfig& config);

/// Checks NavdParams ranges; the error names the field and the value.
Result<void> validate(const NavdParams& p);

/// Loads `path` over the defaults of FilterParams and NavdParams. The error detail is one
/// line.
Result<NavdConfig> load_config(const std::string& path);

/// One line per parameter, "name (default): description", for --help.
std::string config_keys_help();

}  // namespace nav::dut

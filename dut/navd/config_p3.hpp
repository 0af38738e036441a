// SPDX-License-Identifier: MIT
// The keys of navd's config file that set paper P3's crawler navigators (navigator: p3-dr,
// p3-ekf, p3-ekf-kr; p3_navigator.hpp): the robot's wheels, the EKF's noises (P3Params), the
// kinematic relation's gate, the wall, the depth low-pass and the EBIMU line.
#pragma once

#include <span>
#include <string>

#include "nav/common/result.hpp"
#include "nav/estimator/p3_crawler_ekf.hpp"

namespace nav::dut {

/// Which of paper P3's three navigators runs.
enum class P3Method {
  kDeadReckoning,  ///< "p3-dr": the encoders only (eq 3)
  kEkf,            ///< "p3-ekf": the EKF with the y and θ corrections only
  kEkfKr,          ///< "p3-ekf-kr": the EKF with the kinematic x correction (eqs 10–11, 16–17)
};

/// navigator: p3-dr, p3-ekf, p3-ekf-kr.
struct P3Config {
  P3Method method = P3Method::kEkfKr;
  estimator::P3Params filter;    ///< track b, wheel noises, measurement 1-σ
  double wheel_radius_m = 0.05;  ///< R [m]
  double chi_rad = 0.0349065850398866;  ///< χ of the gate (2°: about 2σ of the roll) [rad]
  double initial_position_std_m = 0.05;  ///< 1-σ of the start on the wall, x and y [m]
  double initial_theta_std_rad = 0.0349065850398866;  ///< 1-σ of the start heading [rad]
  /// Time constant of the first-order low-pass on the depth (the paper leaves it open) [s].
  double depth_tau_s = 0.2;
  double ebimu_rate_hz = 20.0;  ///< the EBIMU's line rate: navd's clock (no time tag) [Hz]
  int ebimu_values = 3;         ///< values per line: Euler (roll, pitch, yaw) first, [3, 10]
  double wall_slope_rad = 1.5707963267948966;  ///< α, to map the wall to NED [rad]
  double wall_azimuth_rad = 0.0;               ///< β, direction of x′ (0 = North) [rad]
};

/// The navigator name of a method ("p3-dr", "p3-ekf", "p3-ekf-kr").
const char* p3_method_name(P3Method m);

/// Every field in range, or an error naming the key.
Result<void> validate(const P3Config& c);

/// One P3Config quantity by name.
struct P3Field {
  const char* name;                   ///< e.g. "p3_track_m"
  const char* doc;                    ///< one line with its unit
  double (*get)(const P3Config&);     ///< its value
  void (*set)(P3Config&, double);     ///< sets it
};

/// Every P3 key.
std::span<const P3Field> p3_fields();

/// The P3 field named `key`, or nullptr.
const P3Field* find_p3_field(const std::string& key);

}  // namespace nav::dut

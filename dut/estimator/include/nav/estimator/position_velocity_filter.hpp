// SPDX-License-Identifier: MIT
// Linear Kalman filter on x = [p_n; v_n] (model pv_model.hpp, algorithm linear_kf.hpp).
#pragma once

#include "nav/estimator/pv_model.hpp"
#include "nav/estimator/update_report.hpp"

namespace nav::estimator {

/// Position/velocity KF in the local NED plane; see pv_model.hpp for the state table.
class PositionVelocityFilter {
 public:
  /// Starts at x0 with covariance P0 (symmetric positive definite).
  PositionVelocityFilter(const pv::State& x0, const pv::Covariance& P0);

  /// Propagates by dt_s > 0 [s] with the navigation-frame acceleration a_n [m/s², NED]
  /// and acceleration error density q [m/s²/√Hz]. NaN/Inf input: rejected, no change.
  StepStatus predict(const Vec3& a_n_mps2, double dt_s, double accel_noise_density_mps2_rthz);

  /// Fuses a position p_n [m, NED] with per-axis standard deviations [m] (M7).
  /// gate_nis > 0 enables a chi-square gate (3 dof).
  UpdateReport<3> update_position(const Vec3& p_n_m, const Vec3& std_m, double gate_nis = 0.0);

  /// Fuses [v_N, v_E] [m/s] with a per-axis standard deviation [m/s] (M8).
  /// gate_nis > 0 enables a chi-square gate (2 dof).
  UpdateReport<2> update_horizontal_velocity(const Vec<2>& v_ne_mps, double std_mps,
                                             double gate_nis = 0.0);

  /// Fuses the down position p_D [m, NED] (from a depth sensor) with a standard deviation
  /// [m] (M9). No gate.
  UpdateReport<1> update_down_position(double p_d_m, double std_m);

  const pv::State& x() const { return x_; }       ///< [p_n m; v_n m/s]
  const pv::Covariance& P() const { return P_; }  ///< covariance of x
  Vec3 p_n() const { return x_.segment<3>(pv::kPos.idx); }  ///< position, NED [m]
  Vec3 v_n() const { return x_.segment<3>(pv::kVel.idx); }  ///< velocity, NED [m/s]

 private:
  pv::State x_;
  pv::Covariance P_;
};

}  // namespace nav::estimator

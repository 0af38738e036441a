// SPDX-License-Identifier: MIT
#include "nav/estimator/position_velocity_filter.hpp"

#include <cmath>

#include "nav/common/ensure.hpp"

namespace nav::estimator {

PositionVelocityFilter::PositionVelocityFilter(const pv::State& x0, const pv::Covariance& P0)
    : x_(x0), P_(P0) {
  NAV_ENSURE(x0.allFinite() && P0.allFinite(), "initial state and covariance must be finite");
  NAV_ENSURE(P0.isApprox(P0.transpose()), "initial covariance must be symmetric");
}

StepStatus PositionVelocityFilter::predict(const Vec3& a_n_mps2, double dt_s,
                                           double accel_noise_density_mps2_rthz) {
  NAV_ENSURE(dt_s > 0.0, "predict needs dt > 0; the caller filters bad intervals");
  if (!a_n_mps2.allFinite() || !std::isfinite(dt_s) ||
      !std::isfinite(accel_noise_density_mps2_rthz)) {
    return StepStatus::kRejectedInvalid;
  }
  const pv::Covariance F = pv::transition_jacobian(dt_s);                             // (M4)
  const pv::Covariance Q = pv::process_noise(accel_noise_density_mps2_rthz, dt_s);    // (M6)
  x_ = pv::propagate(x_, a_n_mps2, dt_s);  // x⁻ = f(x, a_n) (K1 with M2, M3)
  predict_covariance(P_, F, Q);            // P⁻ = F P Fᵀ + Q (K2)
  return StepStatus::kApplied;
}

UpdateReport<3> PositionVelocityFilter::update_position(const Vec3& p_n_m, const Vec3& std_m,
                                                        double gate_nis) {
  const Mat<3, pv::kStateSize> H = pv::position_jacobian();  // (M7)
  const Mat3 R = std_m.cwiseProduct(std_m).asDiagonal();     // R = diag(σ²) (M7)
  return linear_update<pv::kStateSize, 3>(x_, P_, p_n_m, H, R, gate_nis);  // (K3..K7)
}

UpdateReport<2> PositionVelocityFilter::update_horizontal_velocity(const Vec<2>& v_ne_mps,
                                                                   double std_mps,
                                                                   double gate_nis) {
  const Mat<2, pv::kStateSize> H = pv::horizontal_velocity_jacobian();  // (M8)
  const Mat<2, 2> R = Mat<2, 2>::Identity() * (std_mps * std_mps);      // R = σ_v² I₂ (M8)
  return linear_update<pv::kStateSize, 2>(x_, P_, v_ne_mps, H, R, gate_nis);  // (K3..K7)
}

UpdateReport<1> PositionVelocityFilter::update_down_position(double p_d_m, double std_m) {
  const Mat<1, pv::kStateSize> H = pv::down_position_jacobian();  // (M9)
  const Mat<1, 1> R = Mat<1, 1>::Constant(std_m * std_m);         // R = σ_d² (M9)
  const Vec<1> z = Vec<1>::Constant(p_d_m);                       // z = p_D + w (M9)
  return linear_update<pv::kStateSize, 1>(x_, P_, z, H, R);       // (K3..K7)
}

}  // namespace nav::estimator

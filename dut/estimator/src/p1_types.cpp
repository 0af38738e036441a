// SPDX-License-Identifier: MIT
#include "nav/estimator/p1_types.hpp"

#include <cmath>
#include <cstdio>
#include <string>

#include "nav/common/format.hpp"

namespace nav::estimator {
namespace {

/// A scalar field and the range it must lie in.
struct Rule {
  const char* name;
  double value;
  bool strictly_positive;  ///< > 0 (else ≥ 0)
};

}  // namespace

bool is_valid(const ImuSample& s, double max_dt_s) {
  return std::isfinite(s.dt_s) && s.dt_s > 0.0 && s.dt_s <= max_dt_s &&
         s.omega_b_radps.allFinite() && s.f_b_mps2.allFinite() && s.m_b_tesla.allFinite();
}

Result<void> validate(const P1Params& p) {
  if (!p.initial_p_n_m.allFinite()) {
    return fail(ErrorCode::kInvalidArgument, "initial_p_n_m must be finite");
  }
  if (!p.initial_v_n_mps.allFinite()) {
    return fail(ErrorCode::kInvalidArgument, "initial_v_n_mps must be finite");
  }
  if (!p.initial_q_nb.coeffs().allFinite() || std::abs(p.initial_q_nb.norm() - 1.0) > 1e-6) {
    return fail(ErrorCode::kInvalidArgument,
                "initial_q_nb must be a finite unit quaternion (got norm " +
                    format_g(p.initial_q_nb.norm()) + ")");
  }
  // The Earth's field is below 70 µT: a bound of 1 mT catches a value written in µT or G.
  if (!p.mag_field_n_tesla.allFinite() || p.mag_field_n_tesla.cwiseAbs().maxCoeff() > 1e-3) {
    return fail(ErrorCode::kInvalidArgument,
                "mag_field_n_tesla must be finite and within ±1e-3 T per axis");
  }
  const Rule rules[] = {
      {"gravity_mps2", p.gravity_mps2, true},
      {"accel_noise_mps2_rthz", p.accel_noise_mps2_rthz, true},
      {"gyro_noise_radps_rthz", p.gyro_noise_radps_rthz, true},
      {"accel_bias_walk_mps3_rthz", p.accel_bias_walk_mps3_rthz, false},
      {"gyro_bias_walk_radps2_rthz", p.gyro_bias_walk_radps2_rthz, false},
      {"initial_position_std_m", p.initial_position_std_m, true},
      {"initial_velocity_std_mps", p.initial_velocity_std_mps, true},
      {"initial_tilt_std_rad", p.initial_tilt_std_rad, true},
      {"initial_heading_std_rad", p.initial_heading_std_rad, true},
      {"initial_accel_bias_std_mps2", p.initial_accel_bias_std_mps2, true},
      {"initial_gyro_bias_std_radps", p.initial_gyro_bias_std_radps, true},
      {"gps_position_std_m", p.gps_position_std_m, true},
      {"mag_std_tesla", p.mag_std_tesla, true},
      {"gravity_std_mps2", p.gravity_std_mps2, true},
      {"gps_gate_nis", p.gps_gate_nis, false},
      {"mag_gate_nis", p.mag_gate_nis, false},
      {"gravity_gate_nis", p.gravity_gate_nis, false},
      {"max_dt_s", p.max_dt_s, true},
      {"resample_ess_fraction", p.resample_ess_fraction, true},
  };
  for (const Rule& r : rules) {
    if (!std::isfinite(r.value)) {
      return fail(ErrorCode::kInvalidArgument, std::string(r.name) + " must be finite");
    }
    const bool ok = r.strictly_positive ? r.value > 0.0 : r.value >= 0.0;
    if (!ok) {
      return fail(ErrorCode::kInvalidArgument,
                  std::string(r.name) + " must be " + (r.strictly_positive ? "> 0" : ">= 0") +
                      " (got " + format_g(r.value) + ")");
    }
  }
  if (p.resample_ess_fraction > 1.0) {
    return fail(ErrorCode::kInvalidArgument, "resample_ess_fraction must be in (0, 1] (got " +
                                                 format_g(p.resample_ess_fraction) + ")");
  }
  if (p.particle_count < 1 || p.particle_count > P1Params::kMaxParticles) {
    return fail(ErrorCode::kInvalidArgument,
                "particle_count must be in [1, " + std::to_string(P1Params::kMaxParticles) +
                    "] (got " + std::to_string(p.particle_count) + ")");
  }
  return {};
}

}  // namespace nav::estimator

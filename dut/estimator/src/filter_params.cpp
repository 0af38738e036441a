// SPDX-License-Identifier: MIT
#include "nav/estimator/filter_params.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "nav/common/format.hpp"

namespace nav::estimator {
namespace {

constexpr ParamField kFields[] = {
    {"attitude_kp_per_s", &FilterParams::attitude_kp_per_s,
     "proportional gain of the attitude complementary filter [1/s]"},
    {"attitude_ki_per_s2", &FilterParams::attitude_ki_per_s2,
     "integral (gyro bias) gain of the attitude filter [1/s^2]"},
    {"accel_weight", &FilterParams::accel_weight, "weight of the gravity-direction error [-]"},
    {"mag_weight", &FilterParams::mag_weight, "weight of the magnetic heading error [-]"},
    {"accel_gate_mps2", &FilterParams::accel_gate_mps2,
     "accel corrects attitude only while ||f|-g0| is below this [m/s^2]"},
    {"gyro_bias_limit_radps", &FilterParams::gyro_bias_limit_radps,
     "clamp of each gyro bias axis [rad/s]"},
    {"magnetic_declination_rad", &FilterParams::magnetic_declination_rad,
     "magnetic declination, east positive [rad]"},
    {"max_dt_s", &FilterParams::max_dt_s, "longest AHRS sample interval still propagated [s]"},
    {"accel_noise_density_mps2_rthz", &FilterParams::accel_noise_density_mps2_rthz,
     "acceleration error density driving the KF [m/s^2/sqrt(Hz)]"},
    {"gps_horizontal_std_m", &FilterParams::gps_horizontal_std_m,
     "GPS position std per horizontal axis [m]"},
    {"gps_vertical_std_m", &FilterParams::gps_vertical_std_m, "GPS altitude std [m]"},
    {"gps_velocity_std_mps", &FilterParams::gps_velocity_std_mps,
     "GPS velocity std per horizontal axis [m/s]"},
    {"initial_velocity_std_mps", &FilterParams::initial_velocity_std_mps,
     "velocity std when the KF starts [m/s]"},
    {"gps_position_gate_nis", &FilterParams::gps_position_gate_nis,
     "NIS gate of GPS position updates, 0 = off [-]"},
    {"gps_velocity_gate_nis", &FilterParams::gps_velocity_gate_nis,
     "NIS gate of GPS velocity updates, 0 = off [-]"},
    {"depth_poll_period_s", &FilterParams::depth_poll_period_s,
     "time between Keller depth-sensor polls, on the AHRS timer, (0, 60] [s]"},
    {"depth_atmosphere_pa", &FilterParams::depth_atmosphere_pa,
     "air pressure subtracted from P1, 0 for a gauge sensor, [0, 200000] [Pa]"},
    {"depth_density_kgpm3", &FilterParams::depth_density_kgpm3,
     "water density for depth = (P1 - p_atm) / (rho g0), [900, 1100] [kg/m^3]"},
    {"depth_std_m", &FilterParams::depth_std_m, "depth measurement std [m]"},
    {"dvl_timeout_s", &FilterParams::dvl_timeout_s,
     "a DVL velocity older than this stops the dead reckoning, (0, 60] [s]"},
    {"origin_lat_deg", &FilterParams::origin_lat_deg,
     "latitude of the dead reckoning's start, [-90, 90] [deg]"},
    {"origin_lon_deg", &FilterParams::origin_lon_deg,
     "longitude of the dead reckoning's start, [-180, 180] [deg]"},
    {"origin_depth_m", &FilterParams::origin_depth_m,
     "depth of the dead reckoning's start below MSL, + down [m]"},
    {"eskf_gyro_noise_radps_rthz", &FilterParams::eskf_gyro_noise_radps_rthz,
     "eskf: gyro noise density [rad/s/sqrt(Hz)]"},
    {"eskf_gyro_bias_walk_radps2_rthz", &FilterParams::eskf_gyro_bias_walk_radps2_rthz,
     "eskf: gyro bias random walk [rad/s^2/sqrt(Hz)]"},
    {"eskf_initial_tilt_std_rad", &FilterParams::eskf_initial_tilt_std_rad,
     "eskf: initial roll/pitch std [rad]"},
    {"eskf_initial_yaw_std_rad", &FilterParams::eskf_initial_yaw_std_rad,
     "eskf: initial yaw std [rad]"},
    {"eskf_initial_gyro_bias_std_radps", &FilterParams::eskf_initial_gyro_bias_std_radps,
     "eskf: initial gyro bias std per axis [rad/s]"},
    {"eskf_accel_std_mps2", &FilterParams::eskf_accel_std_mps2,
     "eskf: accelerometer std per axis [m/s^2]"},
    {"eskf_mag_field_north_t", &FilterParams::eskf_mag_field_north_t,
     "eskf: local Earth field North (WMM), [-1e-3, 1e-3], all three 0 = unknown [T]"},
    {"eskf_mag_field_east_t", &FilterParams::eskf_mag_field_east_t,
     "eskf: local Earth field East, [-1e-3, 1e-3] [T]"},
    {"eskf_mag_field_down_t", &FilterParams::eskf_mag_field_down_t,
     "eskf: local Earth field Down, [-1e-3, 1e-3] [T]"},
    {"eskf_initial_hard_iron_std_t", &FilterParams::eskf_initial_hard_iron_std_t,
     "eskf: initial hard-iron std per body axis, 0 = not estimated [T]"},
    {"eskf_hard_iron_walk_t_rts", &FilterParams::eskf_hard_iron_walk_t_rts,
     "eskf: hard-iron random walk [T/sqrt(s)]"},
    {"eskf_mag_std_t", &FilterParams::eskf_mag_std_t,
     "eskf: magnetometer std per axis (3-D field update) [T]"},
    {"eskf_mag_norm_gate", &FilterParams::eskf_mag_norm_gate,
     "eskf: refuse the magnetometer when |m-h| is off |m_n| by this fraction, 0 = off [-]"},
    {"eskf_mag_inclination_gate_rad", &FilterParams::eskf_mag_inclination_gate_rad,
     "eskf: refuse the magnetometer when the inclination of m-h is off by this, 0 = off [rad]"},
    {"eskf_mag_gate_nis", &FilterParams::eskf_mag_gate_nis,
     "eskf: NIS gate of magnetometer updates (3 dof), 0 = off [-]"},
};

/// A closed range a field must lie in (the open lower end of a period is checked apart).
struct RangeRule {
  const char* name;
  double value;
  double min;
  double max;
};

}  // namespace

std::span<const ParamField> param_fields() { return kFields; }

Result<void> validate(const FilterParams& p) {
  for (const ParamField& f : kFields) {
    const double v = p.*(f.member);
    if (!std::isfinite(v)) {
      return fail(ErrorCode::kInvalidArgument, std::string(f.name) + " must be finite");
    }
  }
  struct Rule {
    const char* name;
    double value;
    bool strictly_positive;
  };
  const Rule rules[] = {
      {"attitude_kp_per_s", p.attitude_kp_per_s, false},
      {"attitude_ki_per_s2", p.attitude_ki_per_s2, false},
      {"accel_weight", p.accel_weight, false},
      {"mag_weight", p.mag_weight, false},
      {"accel_gate_mps2", p.accel_gate_mps2, false},
      {"gyro_bias_limit_radps", p.gyro_bias_limit_radps, false},
      {"max_dt_s", p.max_dt_s, true},
      {"accel_noise_density_mps2_rthz", p.accel_noise_density_mps2_rthz, false},
      {"gps_horizontal_std_m", p.gps_horizontal_std_m, true},
      {"gps_vertical_std_m", p.gps_vertical_std_m, true},
      {"gps_velocity_std_mps", p.gps_velocity_std_mps, true},
      {"initial_velocity_std_mps", p.initial_velocity_std_mps, true},
      {"gps_position_gate_nis", p.gps_position_gate_nis, false},
      {"gps_velocity_gate_nis", p.gps_velocity_gate_nis, false},
      {"depth_poll_period_s", p.depth_poll_period_s, true},
      {"depth_std_m", p.depth_std_m, true},
      {"dvl_timeout_s", p.dvl_timeout_s, true},
      {"eskf_gyro_noise_radps_rthz", p.eskf_gyro_noise_radps_rthz, true},
      {"eskf_gyro_bias_walk_radps2_rthz", p.eskf_gyro_bias_walk_radps2_rthz, false},
      {"eskf_initial_tilt_std_rad", p.eskf_initial_tilt_std_rad, true},
      {"eskf_initial_yaw_std_rad", p.eskf_initial_yaw_std_rad, true},
      {"eskf_initial_gyro_bias_std_radps", p.eskf_initial_gyro_bias_std_radps, true},
      {"eskf_accel_std_mps2", p.eskf_accel_std_mps2, true},
      {"eskf_initial_hard_iron_std_t", p.eskf_initial_hard_iron_std_t, false},
      {"eskf_hard_iron_walk_t_rts", p.eskf_hard_iron_walk_t_rts, false},
      {"eskf_mag_std_t", p.eskf_mag_std_t, true},
      {"eskf_mag_norm_gate", p.eskf_mag_norm_gate, false},
      {"eskf_mag_inclination_gate_rad", p.eskf_mag_inclination_gate_rad, false},
      {"eskf_mag_gate_nis", p.eskf_mag_gate_nis, false},
  };
  for (const Rule& r : rules) {
    const bool ok = r.strictly_positive ? r.value > 0.0 : r.value >= 0.0;
    if (!ok) {
      return fail(ErrorCode::kInvalidArgument,
                  std::string(r.name) + " must be " + (r.strictly_positive ? "> 0" : ">= 0") +
                      " (got " + format_g(r.value) + ")");
    }
  }
  const RangeRule ranges[] = {
      {"depth_poll_period_s", p.depth_poll_period_s, 0.0, 60.0},
      {"depth_atmosphere_pa", p.depth_atmosphere_pa, 0.0, 200000.0},
      {"depth_density_kgpm3", p.depth_density_kgpm3, 900.0, 1100.0},
      {"dvl_timeout_s", p.dvl_timeout_s, 0.0, 60.0},
      {"origin_lat_deg", p.origin_lat_deg, -90.0, 90.0},
      {"origin_lon_deg", p.origin_lon_deg, -180.0, 180.0},
      {"origin_depth_m", p.origin_depth_m, -10000.0, 12000.0},
      // The Earth's field is below 70 uT: a bound of 1 mT catches a value written in uT.
      {"eskf_mag_field_north_t", p.eskf_mag_field_north_t, -1e-3, 1e-3},
      {"eskf_mag_field_east_t", p.eskf_mag_field_east_t, -1e-3, 1e-3},
      {"eskf_mag_field_down_t", p.eskf_mag_field_down_t, -1e-3, 1e-3},
  };
  for (const RangeRule& r : ranges) {
    if (r.value < r.min || r.value > r.max) {
      return fail(ErrorCode::kInvalidArgument,
                  std::string(r.name) + " must be in [" + format_g(r.min) + ", " +
                      format_g(r.max) + "] (got " + format_g(r.value) + ")");
    }
  }
  if (std::abs(p.magnetic_declination_rad) > std::numbers::pi) {
    return fail(ErrorCode::kInvalidArgument, "magnetic_declination_rad must be in [-pi, pi]");
  }
  return {};
}

}  // namespace nav::estimator

// SPDX-License-Identifier: MIT
#include "config_p1.hpp"

#include <array>

#include "nav/common/frames.hpp"
#include "nav/common/units.hpp"

namespace nav::dut {
namespace {

using estimator::P1Params;

/// The initial attitude's ZYX Euler angle `which` (0 roll, 1 pitch, 2 yaw) [deg].
template <int Which>
double euler_deg(const P1Params& p) {
  const Euler e = euler_from_quat(p.initial_q_nb);
  return units::rad_to_deg(Which == 0 ? e.roll : Which == 1 ? e.pitch : e.yaw);
}

template <int Which>
void set_euler_deg(P1Params& p, double deg) {
  Euler e = euler_from_quat(p.initial_q_nb);
  (Which == 0 ? e.roll : Which == 1 ? e.pitch : e.yaw) = units::deg_to_rad(deg);
  p.initial_q_nb = quat_from_euler(e);
}

// A field of a Vec3 member, one component.
#define NAV_P1_VEC(member, i) \
  [](const P1Params& p) { return p.member[i]; }, [](P1Params& p, double v) { p.member[i] = v; }
// A double member.
#define NAV_P1_SCALAR(member) \
  [](const P1Params& p) { return p.member; }, [](P1Params& p, double v) { p.member = v; }

const std::array<P1Field, 29> kFields = {{
    {"p1_initial_north_m", "initial position north of the origin [m]", NAV_P1_VEC(initial_p_n_m, 0)},
    {"p1_initial_east_m", "initial position east of the origin [m]", NAV_P1_VEC(initial_p_n_m, 1)},
    {"p1_initial_down_m", "initial position below the origin [m]", NAV_P1_VEC(initial_p_n_m, 2)},
    {"p1_initial_roll_deg", "initial roll (ZYX) [deg]", &euler_deg<0>, &set_euler_deg<0>},
    {"p1_initial_pitch_deg", "initial pitch (ZYX) [deg]", &euler_deg<1>, &set_euler_deg<1>},
    {"p1_initial_yaw_deg", "initial heading (ZYX, 0 = North) [deg]", &euler_deg<2>,
     &set_euler_deg<2>},
    {"p1_gravity_mps2", "gravity g of g_n = (0, 0, g) [m/s^2]", NAV_P1_SCALAR(gravity_mps2)},
    {"p1_mag_field_north_t", "Earth field m^n, north [T] (all zero: no magnetometer update)",
     NAV_P1_VEC(mag_field_n_tesla, 0)},
    {"p1_mag_field_east_t", "Earth field m^n, east [T]", NAV_P1_VEC(mag_field_n_tesla, 1)},
    {"p1_mag_field_down_t", "Earth field m^n, down [T]", NAV_P1_VEC(mag_field_n_tesla, 2)},
    {"p1_accel_noise_mps2_rthz", "accelerometer white noise density [m/s^2/sqrt(Hz)]",
     NAV_P1_SCALAR(accel_noise_mps2_rthz)},
    {"p1_gyro_noise_radps_rthz", "gyro white noise density [rad/s/sqrt(Hz)]",
     NAV_P1_SCALAR(gyro_noise_radps_rthz)},
    {"p1_accel_bias_walk_mps3_rthz", "accelerometer bias random walk [m/s^3/sqrt(Hz)]",
     NAV_P1_SCALAR(accel_bias_walk_mps3_rthz)},
    {"p1_gyro_bias_walk_radps2_rthz", "gyro bias random walk [rad/s^2/sqrt(Hz)]",
     NAV_P1_SCALAR(gyro_bias_walk_radps2_rthz)},
    {"p1_initial_position_std_m", "initial position std per axis [m]",
     NAV_P1_SCALAR(initial_position_std_m)},
    {"p1_initial_velocity_std_mps", "initial velocity std per axis [m/s]",
     NAV_P1_SCALAR(initial_velocity_std_mps)},
    {"p1_initial_tilt_std_rad", "initial tilt std (north, east) [rad]",
     NAV_P1_SCALAR(initial_tilt_std_rad)},
    {"p1_initial_heading_std_rad", "initial heading std [rad]",
     NAV_P1_SCALAR(initial_heading_std_rad)},
    {"p1_initial_accel_bias_std_mps2", "initial accelerometer bias std per axis [m/s^2]",
     NAV_P1_SCALAR(initial_accel_bias_std_mps2)},
    {"p1_initial_gyro_bias_std_radps", "initial gyro bias std per axis [rad/s]",
     NAV_P1_SCALAR(initial_gyro_bias_std_radps)},
    {"p1_gps_position_std_m", "GPS position std per NED axis [m]",
     NAV_P1_SCALAR(gps_position_std_m)},
    {"p1_mag_std_tesla", "magnetometer std per axis [T]", NAV_P1_SCALAR(mag_std_tesla)},
    {"p1_gravity_std_mps2", "mfins: gravity measurement std per axis [m/s^2]",
     NAV_P1_SCALAR(gravity_std_mps2)},
    {"p1_gps_gate_nis", "chi-square gate on the GPS NIS (3 dof), 0 = off",
     NAV_P1_SCALAR(gps_gate_nis)},
    {"p1_mag_gate_nis", "chi-square gate on the magnetometer NIS (3 dof), 0 = off",
     NAV_P1_SCALAR(mag_gate_nis)},
    {"p1_gravity_gate_nis", "mfins: chi-square gate on the gravity NIS (3 dof), 0 = off",
     NAV_P1_SCALAR(gravity_gate_nis)},
    {"p1_max_dt_s", "an IMU interval above this is refused [s]", NAV_P1_SCALAR(max_dt_s)},
    {"p1_particle_count", "upf15, mfins: particles, a whole number in [1, 100000]",
     [](const P1Params& p) { return static_cast<double>(p.particle_count); },
     [](P1Params& p, double v) {
       // Not a whole number in range: a value validate() refuses, naming the field.
       p.particle_count = v >= 1.0 && v <= 1e6 && v == static_cast<int>(v) ? static_cast<int>(v) : 0;
     }},
    {"p1_resample_ess_fraction", "upf15, mfins: resample when ESS < this x particles, (0, 1]",
     NAV_P1_SCALAR(resample_ess_fraction)},
}};

#undef NAV_P1_VEC
#undef NAV_P1_SCALAR

}  // namespace

std::span<const P1Field> p1_fields() { return kFields; }

const P1Field* find_p1_field(const std::string& key) {
  for (const auto& f : kFields) {
    if (key == f.name) return &f;
  }
  return nullptr;
}

}  // namespace nav::dut

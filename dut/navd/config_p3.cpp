// SPDX-License-Identifier: MIT
#include "config_p3.hpp"

#include "config_number.hpp"

#include <array>
#include <cmath>
#include <numbers>

namespace nav::dut {
namespace {

// A double member of P3Config.
#define NAV_P3_SCALAR(member) \
  [](const P3Config& c) { return c.member; }, [](P3Config& c, double v) { c.member = v; }

const std::array<P3Field, 15> kFields = {{
    {"p3_track_m", "b, the wheel base [m]", NAV_P3_SCALAR(filter.track_m)},
    {"p3_wheel_radius_m", "R, the wheel radius [m]", NAV_P3_SCALAR(wheel_radius_m)},
    {"p3_k_r", "right wheel's noise variance per metre of its travel, Q = k |d| [m]",
     NAV_P3_SCALAR(filter.k_r)},
    {"p3_k_l", "left wheel's [m]", NAV_P3_SCALAR(filter.k_l)},
    {"p3_sigma_x_m", "1-sigma of the kinematic x measurement [m]",
     NAV_P3_SCALAR(filter.sigma_x_m)},
    {"p3_sigma_y_m", "1-sigma of y from the depth [m]", NAV_P3_SCALAR(filter.sigma_y_m)},
    {"p3_sigma_theta_rad", "1-sigma of the heading from the AHRS roll [rad]",
     NAV_P3_SCALAR(filter.sigma_theta_rad)},
    {"p3_chi_rad", "gate chi: no x correction while |sin theta_m| <= sin chi, (0, pi/2) [rad]",
     NAV_P3_SCALAR(chi_rad)},
    {"p3_initial_position_std_m", "1-sigma of the start on the wall, x and y [m]",
     NAV_P3_SCALAR(initial_position_std_m)},
    {"p3_initial_theta_std_rad", "1-sigma of the start heading [rad]",
     NAV_P3_SCALAR(initial_theta_std_rad)},
    {"p3_depth_tau_s", "time constant of the depth low-pass, 0 = none, [0, 10] [s]",
     NAV_P3_SCALAR(depth_tau_s)},
    {"p3_ebimu_rate_hz", "the EBIMU's line rate, navd's P3 clock, (0, 1000] [Hz]",
     NAV_P3_SCALAR(ebimu_rate_hz)},
    {"p3_ebimu_values", "values per EBIMU line, Euler angles first, whole, [3, 10]",
     [](const P3Config& c) { return static_cast<double>(c.ebimu_values); },
     [](P3Config& c, double v) { c.ebimu_values = whole_or_invalid(v, 3, 10); }},
    {"p3_wall_slope_rad", "alpha, the wall's slope (pi/2 = vertical), (0, pi/2] [rad]",
     NAV_P3_SCALAR(wall_slope_rad)},
    {"p3_wall_azimuth_rad", "beta, direction of the wall's x' axis (0 = North) [rad]",
     NAV_P3_SCALAR(wall_azimuth_rad)},
}};

#undef NAV_P3_SCALAR

bool positive(double v) { return std::isfinite(v) && v > 0.0; }

}  // namespace

const char* p3_method_name(P3Method m) {
  switch (m) {
    case P3Method::kDeadReckoning: return "p3-dr";
    case P3Method::kEkf: return "p3-ekf";
    case P3Method::kEkfKr: return "p3-ekf-kr";
  }
  return "?";
}

Result<void> validate(const P3Config& c) {
  const auto bad = [](const std::string& what) {
    return fail(ErrorCode::kInvalidArgument, what);
  };
  if (!positive(c.filter.track_m)) return bad("p3_track_m must be finite and > 0");
  if (!positive(c.wheel_radius_m)) return bad("p3_wheel_radius_m must be finite and > 0");
  if (!std::isfinite(c.filter.k_r) || c.filter.k_r < 0.0 || !std::isfinite(c.filter.k_l) ||
      c.filter.k_l < 0.0) {
    return bad("p3_k_r and p3_k_l must be finite and >= 0");
  }
  if (!positive(c.filter.sigma_x_m) || !positive(c.filter.sigma_y_m) ||
      !positive(c.filter.sigma_theta_rad)) {
    return bad("p3_sigma_* must be finite and > 0");
  }
  if (!(c.chi_rad > 0.0 && c.chi_rad < std::numbers::pi / 2)) {
    return bad("p3_chi_rad must be in (0, pi/2)");
  }
  if (!positive(c.initial_position_std_m) || !positive(c.initial_theta_std_rad)) {
    return bad("p3_initial_*_std must be finite and > 0");
  }
  if (!(c.depth_tau_s >= 0.0 && c.depth_tau_s <= 10.0)) {
    return bad("p3_depth_tau_s must be in [0, 10]");
  }
  if (!(c.ebimu_rate_hz > 0.0 && c.ebimu_rate_hz <= 1000.0)) {
    return bad("p3_ebimu_rate_hz must be in (0, 1000]");
  }
  if (c.ebimu_values < 3 || c.ebimu_values > 10) {
    return bad("p3_ebimu_values must be a whole number in [3, 10]");
  }
  if (!(c.wall_slope_rad > 0.0 && c.wall_slope_rad <= std::numbers::pi / 2)) {
    return bad("p3_wall_slope_rad must be in (0, pi/2]");
  }
  if (!std::isfinite(c.wall_azimuth_rad)) return bad("p3_wall_azimuth_rad must be finite");
  return {};
}

std::span<const P3Field> p3_fields() { return kFields; }

const P3Field* find_p3_field(const std::string& key) {
  for (const auto& f : kFields) {
    if (key == f.name) return &f;
  }
  return nullptr;
}

}  // namespace nav::dut

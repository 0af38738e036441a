// SPDX-License-Identifier: MIT
#include "config_p2.hpp"

#include "config_number.hpp"

#include <array>
#include <cmath>

namespace nav::dut {
namespace {

using estimator::P2Observation;

constexpr std::size_t index_of(P2Observation o) { return static_cast<std::size_t>(o); }

// A double member of P2Config.
#define NAV_P2_SCALAR(member) \
  [](const P2Config& c) { return c.member; }, [](P2Config& c, double v) { c.member = v; }
// A component of the process noise.
#define NAV_P2_NOISE(i)                                                 \
  [](const P2Config& c) { return c.filter.process_noise_rthz(i); },     \
      [](P2Config& c, double v) { c.filter.process_noise_rthz(i) = v; }
// The 1-σ of an observation kind.
#define NAV_P2_STD(kind)                                                              \
  [](const P2Config& c) { return c.filter.observation_std[index_of(kind)]; },         \
      [](P2Config& c, double v) { c.filter.observation_std[index_of(kind)] = v; }

const std::array<P2Field, 20> kFields = {{
    {"p2_vehicles", "vehicles N of the joint state (ids 1..N), whole, [2, 8]",
     [](const P2Config& c) { return static_cast<double>(c.vehicles); },
     [](P2Config& c, double v) {
       c.vehicles = whole_or_invalid(v, 2, estimator::kP2MaxVehicles);
     }},
    {"p2_experiment",
     "observation set: 1 none, 2 2-D distance + bearing + heading, 3 3-D distance + bearing "
     "+ heading, 4 as 3 + elevation + pitch",
     [](const P2Config& c) { return static_cast<double>(c.experiment); },
     [](P2Config& c, double v) { c.experiment = whole_or_invalid(v, 1, 4); }},
    {"p2_process_noise_north_m_rts", "process noise of a navigation increment, north "
     "[m/sqrt(s)]", NAV_P2_NOISE(0)},
    {"p2_process_noise_east_m_rts", "process noise, east [m/sqrt(s)]", NAV_P2_NOISE(1)},
    {"p2_process_noise_down_m_rts", "process noise, down [m/sqrt(s)]", NAV_P2_NOISE(2)},
    {"p2_process_noise_heading_rad_rts", "process noise, heading [rad/sqrt(s)]",
     NAV_P2_NOISE(3)},
    {"p2_process_noise_pitch_rad_rts", "process noise, pitch [rad/sqrt(s)]", NAV_P2_NOISE(4)},
    {"p2_distance_2d_std_m", "1-sigma of the 2-D distance [m]",
     NAV_P2_STD(P2Observation::kDistance2d)},
    {"p2_distance_3d_std_m", "1-sigma of the 3-D distance [m]",
     NAV_P2_STD(P2Observation::kDistance3d)},
    {"p2_bearing_std_rad", "1-sigma of the bearing [rad]", NAV_P2_STD(P2Observation::kBearing)},
    {"p2_heading_std_rad", "1-sigma of the relative heading [rad]",
     NAV_P2_STD(P2Observation::kHeading)},
    {"p2_elevation_std_rad", "1-sigma of the elevation [rad]",
     NAV_P2_STD(P2Observation::kElevation)},
    {"p2_pitch_std_rad", "1-sigma of the relative pitch [rad]",
     NAV_P2_STD(P2Observation::kPitch)},
    {"p2_min_horizontal_range_m",
     "below this horizontal separation bearing, elevation and 2-D distance are not fused [m]",
     NAV_P2_SCALAR(filter.min_horizontal_range_m)},
    {"p2_nis_gate", "chi-square gate on a fix's NIS, 0 = off", NAV_P2_SCALAR(filter.nis_gate)},
    {"p2_history_s", "how long late fixes and reports are re-run for, (0, 3600] [s]",
     NAV_P2_SCALAR(filter.history_s)},
    {"p2_initial_position_std_m", "1-sigma of the start (GPS fix) per axis [m]",
     NAV_P2_SCALAR(initial_position_std_m)},
    {"p2_initial_heading_std_rad", "1-sigma of the start heading [rad]",
     NAV_P2_SCALAR(initial_heading_std_rad)},
    {"p2_initial_pitch_std_rad", "1-sigma of the start pitch [rad]",
     NAV_P2_SCALAR(initial_pitch_std_rad)},
    {"p2_timer_start_ticks",
     "GX3 timer at mission time 0 (the GX3's timer_start), whole, [0, 2^32) [1/62500 s]",
     NAV_P2_SCALAR(timer_start_ticks)},
}};

#undef NAV_P2_SCALAR
#undef NAV_P2_NOISE
#undef NAV_P2_STD

}  // namespace

Result<void> validate(const P2Config& c) {
  if (c.vehicles < 2 || c.vehicles > estimator::kP2MaxVehicles) {
    return fail(ErrorCode::kInvalidArgument, "p2_vehicles must be a whole number in [2, " +
                                                 std::to_string(estimator::kP2MaxVehicles) +
                                                 "]");
  }
  if (c.experiment < 1 || c.experiment > 4) {
    return fail(ErrorCode::kInvalidArgument, "p2_experiment must be 1, 2, 3 or 4");
  }
  if (auto ok = estimator::validate(c.filter); !ok) return ok;
  const double stds[] = {c.initial_position_std_m, c.initial_heading_std_rad,
                         c.initial_pitch_std_rad};
  for (const double s : stds) {
    if (!std::isfinite(s) || s <= 0.0) {
      return fail(ErrorCode::kInvalidArgument, "p2_initial_*_std must be finite and > 0");
    }
  }
  const double t = c.timer_start_ticks;
  if (!std::isfinite(t) || t != std::floor(t) || t < 0.0 || t >= 4294967296.0) {
    return fail(ErrorCode::kInvalidArgument,
                "p2_timer_start_ticks must be a whole number in [0, 4294967296)");
  }
  return {};
}

std::span<const P2Field> p2_fields() { return kFields; }

const P2Field* find_p2_field(const std::string& key) {
  for (const auto& f : kFields) {
    if (key == f.name) return &f;
  }
  return nullptr;
}

}  // namespace nav::dut

// SPDX-License-Identifier: MIT
// A1..A3 and D1..D3 are stated in p4_navigator.hpp.
#include "p4_navigator.hpp"

#include <cmath>

#include "nav/common/ensure.hpp"
#include "nav/common/units.hpp"

namespace nav::dut {
namespace {

namespace bi = protocols::beacon_ins;
using estimator::P4Idx;
using estimator::StepStatus;
using estimator::UpdateStatus;

bool finite(const bi::Sample& s) {
  return std::isfinite(s.accel_x_mps2) && std::isfinite(s.accel_y_mps2) &&
         std::isfinite(s.yaw_rate_radps) && std::isfinite(s.heading_rad);
}

}  // namespace

P4Navigator::P4Navigator(const estimator::FilterParams& params, const P4Config& config)
    : params_(params),
      config_(config),
      // The beacon floats: its plane is the datum's at mean sea level (depth 0).
      plane_({units::deg_to_rad(params.origin_lat_deg), units::deg_to_rad(params.origin_lon_deg),
              0.0}),
      ukf_(config.filter),
      out_(config.filter) {
  if (config_.method == P4Method::kDwtUkf) {
    den_x_.emplace(config_.dwt);
    den_y_.emplace(config_.dwt);
    latency_ = den_x_->latency_samples();
  }
}

P4GpsFix P4Navigator::rmc_fix(const protocols::nmea::Rmc& rmc) const {
  P4GpsFix fix;
  fix.position_ne_m.setConstant(std::nan(""));
  if (rmc.lat_deg && rmc.lon_deg) {
    const Vec3 p_n = plane_.to_ned(
        {units::deg_to_rad(*rmc.lat_deg), units::deg_to_rad(*rmc.lon_deg), 0.0});
    fix.position_ne_m = p_n.head<2>();
  }
  if (rmc.sog_kn && rmc.cog_deg) {
    fix.velocity_ne_mps = estimator::rmc_velocity_ne(*rmc.sog_kn * units::kKnotToMps,
                                                     units::deg_to_rad(*rmc.cog_deg));
  }
  return fix;
}

void P4Navigator::on_gps(const P4GpsFix& fix) {
  if (!fix.position_ne_m.allFinite()) return;
  ++counts_.fixes;
  fixes_.push_back(fix);
}

void P4Navigator::step(estimator::P4BeaconUkf& f, const Pending& s, double a_x, double a_y,
                       bool record) {
  if (f.initialised() && s.dt_s) {                                           // A1
    const double dt = *s.dt_s;
    if (dt <= 0.0 || dt > config_.filter.max_dt_s) {
      if (record) ++counts_.dt_resets;
    } else if (f.predict({a_x, a_y, s.omega_z}, dt) != StepStatus::kApplied) {
      if (record) ++counts_.predict_faults;
    }
  }
  const bool started_before = f.initialised();
  for (const P4GpsFix& fix : s.fixes) {                                      // A2
    if (!f.initialised()) {
      f.initialise(fix.position_ne_m, s.heading);                           // B11
      continue;
    }
    const auto r = f.update_gps_position(fix.position_ne_m);                // B8
    if (record) {
      ++(r.status == UpdateStatus::kFused ? counts_.gps_fused : counts_.gps_rejected);
      if (auto i = estimator::innovation_of<2>("p4-gps-position", r)) innovations_.push_back(*i);
    }
    if (config_.rmc_velocity && fix.velocity_ne_mps) {
      const auto v = f.update_gps_velocity(*fix.velocity_ne_mps);           // B10
      if (record) {
        ++(v.status == UpdateStatus::kFused ? counts_.velocity_fused : counts_.velocity_rejected);
        if (auto i = estimator::innovation_of<2>("p4-gps-velocity", v)) innovations_.push_back(*i);
      }
    }
  }
  if (s.compass_due && started_before && f.initialised()) {                 // A3
    const auto r = f.update_compass(s.heading);                             // B9
    if (record) {
      ++(r.status == UpdateStatus::kFused ? counts_.compass_fused : counts_.compass_rejected);
      if (auto i = estimator::innovation_of<1>("p4-compass", r)) innovations_.push_back(*i);
    }
  }
}

void P4Navigator::on_frame(const bi::Sample& s) {
  innovations_.clear();
  if (!finite(s)) {
    // Not stepped, and not pushed into the de-noisers (which would refuse it for one axis
    // only if one were finite). The frame is still answered, with the last estimate.
    ++counts_.frames_invalid;
    return;
  }
  ++counts_.frames;
  Pending p;
  p.f_x = s.accel_x_mps2;
  p.f_y = s.accel_y_mps2;
  p.omega_z = s.yaw_rate_radps;
  p.heading = s.heading_rad;
  if (last_timer_) {
    p.dt_s = static_cast<double>(bi::timer_delta(s.timer_ticks, *last_timer_)) / bi::kTimerHz;
  }
  last_timer_ = s.timer_ticks;
  p.compass_due = frame_index_ % static_cast<std::uint64_t>(config_.compass_every) == 0;
  ++frame_index_;
  p.fixes.swap(fixes_);

  if (latency_ == 0) {  // p4-ukf (and a de-noiser with no delay, which sym4/db4/haar are not)
    step(ukf_, p, p.f_x, p.f_y, true);
    return;
  }
  delay_.push_back(std::move(p));                                            // D1
  const estimator::DwtStreamOutput ox = den_x_->push(s.accel_x_mps2);
  const estimator::DwtStreamOutput oy = den_y_->push(s.accel_y_mps2);
  if (ox.status == estimator::DwtStreamStatus::kDenoised ||
      ox.status == estimator::DwtStreamStatus::kStartupRaw) {                // D2
    // Both de-noisers took every sample, so both return sample i = k − D, the front.
    NAV_ENSURE(oy.index == ox.index && delay_.size() == static_cast<std::size_t>(latency_) + 1,
               "p4: the de-noisers and the delay line disagree");
    const Pending& front = delay_.front();
    if (ox.status == estimator::DwtStreamStatus::kDenoised) {
      ++counts_.denoised;
      step(ukf_, front, ox.value, oy.value, true);
    } else {
      ++counts_.startup_raw;
      step(ukf_, front, front.f_x, front.f_y, true);                       // the raw sample
    }
    delay_.pop_front();
  }
  out_ = ukf_;                                                               // D3
  for (const Pending& q : delay_) step(out_, q, q.f_x, q.f_y, false);
}

estimator::NavSolution P4Navigator::solution() const {
  estimator::NavSolution sol;
  const estimator::P4BeaconUkf& f = output();
  if (!f.initialised()) return sol;
  const estimator::P4Vec& x = f.x();
  sol.attitude_valid = true;
  sol.position_valid = true;
  sol.p_n = Vec3(x(P4Idx::kN), x(P4Idx::kE), 0.0);
  sol.position = plane_.to_geodetic(sol.p_n);
  sol.v_n = Vec3(x(P4Idx::kVn), x(P4Idx::kVe), 0.0);
  sol.q_nb = Quat(Eigen::AngleAxisd(f.heading(), Vec3::UnitZ()));  // level, yaw ψ
  if (const auto P = position_covariance()) {
    sol.p_std_m = P->diagonal().cwiseMax(0.0).cwiseSqrt();
  }
  return sol;
}

std::optional<Mat3> P4Navigator::position_covariance() const {
  const estimator::P4BeaconUkf& f = output();
  if (!f.initialised()) return std::nullopt;
  Mat3 P = Mat3::Zero();
  P.topLeftCorner<2, 2>() = f.position_covariance_ne();
  P(2, 2) = config_.vertical_std_m * config_.vertical_std_m;
  return P;
}

}  // namespace nav::dut

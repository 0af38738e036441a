// SPDX-License-Identifier: MIT
// Steps D0..D3 are stated in dvl_navigator.hpp.
#include "nav/estimator/dvl_navigator.hpp"

#include <cmath>

#include "nav/common/ensure.hpp"
#include "nav/common/units.hpp"

namespace nav::estimator {
namespace {

geodesy::Geodetic origin_of(const FilterParams& p) {
  return {units::deg_to_rad(p.origin_lat_deg), units::deg_to_rad(p.origin_lon_deg),
          -p.origin_depth_m};
}

}  // namespace

DvlNavigator::DvlNavigator(const FilterParams& params, AttitudeFilterKind kind,
                           DvlStart start)
    : params_(params),
      attitude_(make_attitude_filter(kind, params)),
      plane_(origin_of(params)),
      start_(start) {}

void DvlNavigator::add_dvl_velocity(const Vec3& v_b_mps) {
  if (!v_b_mps.allFinite() || v_b_mps.norm() > kMaxDvlSpeedMps) {
    ++stats_.dvl_rejected_invalid;
    return;
  }
  if (queued_velocity_) ++stats_.dvl_superseded;
  queued_velocity_ = v_b_mps;
}

void DvlNavigator::add_depth(double depth_m) {
  if (!std::isfinite(depth_m)) {
    ++stats_.depth_rejected_invalid;
    return;
  }
  queued_depth_ = depth_m;
}

void DvlNavigator::add_gps_position(const GpsPosition& fix) {
  const bool finite = std::isfinite(fix.position.lat_rad) &&
                      std::isfinite(fix.position.lon_rad) && std::isfinite(fix.position.alt_m);
  if (start_ != DvlStart::kFirstGpsFix || started_ || queued_fix_ || !finite) {
    ++stats_.gps_ignored;
    return;
  }
  queued_fix_ = fix.position;
}

void DvlNavigator::on_ahrs(const AhrsSample& s) {
  ++stats_.ahrs_samples;
  last_status_ = AttitudeStatus::kOk;  // until this sample's attitude step says otherwise
  innovations_.clear();
  const bool finite =
      s.omega_b_radps.allFinite() && s.f_b_mps2.allFinite() && s.m_b_tesla.allFinite();
  if (!finite) {
    // The timer of this sample is not trusted either: the next interval spans both samples.
    ++stats_.ahrs_rejected_invalid;
    return;
  }
  if (!aligned_) {
    if (!attitude_->initialise(s.f_b_mps2, s.m_b_tesla)) {
      ++stats_.ahrs_rejected_invalid;
      return;
    }
    aligned_ = true;
    started_ = start_ == DvlStart::kOrigin;
    previous_timer_ = s.timer_ticks;
    queued_velocity_.reset();  // measured before the start: not part of the run
    queued_depth_.reset();
    return;
  }
  const double dt = ahrs_dt_s(previous_timer_, s.timer_ticks);
  previous_timer_ = s.timer_ticks;
  if (dt <= 0.0 || dt > params_.max_dt_s) {
    ++stats_.dt_resets;  // skip propagation; the next interval starts at this sample
    v_b_.reset();        // and the held velocity no longer describes the gap
    return;
  }
  t_s_ += dt;

  if (queued_velocity_) {
    const Vec3 v = *queued_velocity_;
    queued_velocity_.reset();
    const double since = t_s_ - v_b_time_s_;
    if (v_b_ && since > 0.0 && since <= params_.dvl_timeout_s) {
      dv_b_ = (v - *v_b_) / since;  // (D0)
    } else {
      dv_b_.setZero();  // (D0) first velocity, or after a gap
    }
    v_b_ = v;  // (D0)
    v_b_time_s_ = t_s_;
    ++stats_.dvl_used;
  }
  const bool fresh = v_b_.has_value() && t_s_ - v_b_time_s_ <= params_.dvl_timeout_s;

  AttitudeInput in;
  in.omega_b_radps = s.omega_b_radps;
  in.f_b_mps2 = s.f_b_mps2;
  in.m_b_tesla = s.m_b_tesla;
  in.dt_s = dt;
  if (fresh) {
    in.v_b_mps = *v_b_;
    in.dv_b_mps2 = dv_b_;
  }
  last_status_ = attitude_->step(in);  // (D1)
  innovations_ = attitude_->innovations();

  if (fresh) {
    v_n_ = attitude_->q_nb() * *v_b_;  // v_n = R_nb v_b (D2)
    p_n_ += v_n_ * dt;                 // (D2)
  } else {
    v_n_.setZero();
    ++stats_.stale_samples;
  }

  if (queued_depth_) {
    p_n_.z() = *queued_depth_ - params_.origin_depth_m;  // (D3)
    queued_depth_.reset();
    ++stats_.depth_used;
  }

  if (queued_fix_) {
    // (D4) the start; a depth sensor's down position beats the fix's altitude
    const Vec3 p_fix = plane_.to_ned(*queued_fix_);
    p_n_ = stats_.depth_used > 0 ? Vec3(p_fix.x(), p_fix.y(), p_n_.z()) : p_fix;
    queued_fix_.reset();
    started_ = true;
    ++stats_.gps_used;
  }
}

NavSolution DvlNavigator::solution() const {
  NavSolution s;
  s.attitude_valid = aligned_;
  s.position_valid = aligned_ && started_;
  s.q_nb = attitude_->q_nb();
  s.p_n = p_n_;
  s.v_n = v_n_;
  s.position = plane_.to_geodetic(p_n_);
  return s;
}

}  // namespace nav::estimator

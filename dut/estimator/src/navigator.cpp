// SPDX-License-Identifier: MIT
#include "nav/estimator/navigator.hpp"

#include <cmath>
#include <numbers>

#include "nav/common/ensure.hpp"

namespace nav::estimator {

double ahrs_dt_s(std::uint32_t previous_ticks, std::uint32_t current_ticks) {
  // Unsigned subtraction is modulo 2^32, so a wrap between the samples is harmless.
  const std::uint32_t ticks = current_ticks - previous_ticks;
  return static_cast<double>(ticks) / kAhrsTicksPerSecond;
}

Navigator::Navigator(const FilterParams& params, AttitudeFilterKind kind)
    : params_(params), attitude_(make_attitude_filter(kind, params)) {}

template <typename Fix>
void Navigator::enqueue(const Fix& fix) {
  if (queue_.size() >= kMaxQueuedFixes) {
    queue_.erase(queue_.begin());
    ++stats_.gps_queue_dropped;
  }
  queue_.emplace_back(fix);
}

void Navigator::add_gps_position(const GpsPosition& fix) { enqueue(fix); }

void Navigator::add_gps_velocity(const GpsVelocity& fix) { enqueue(fix); }

void Navigator::add_depth(double depth_m) { enqueue(DepthMeasurement{depth_m}); }

void Navigator::on_ahrs(const AhrsSample& s) {
  ++stats_.ahrs_samples;
  last_status_ = AttitudeStatus::kOk;  // until this sample's attitude step says otherwise
  innovations_.clear();
  const bool finite = s.omega_b_radps.allFinite() && s.f_b_mps2.allFinite() &&
                      s.m_b_tesla.allFinite();
  if (!finite) {
    // The timer of this sample is not trusted either: the next interval spans both samples.
    ++stats_.ahrs_rejected_invalid;
  } else if (!aligned_) {
    if (attitude_->initialise(s.f_b_mps2, s.m_b_tesla)) {
      aligned_ = true;
      previous_timer_ = s.timer_ticks;
    } else {
      ++stats_.ahrs_rejected_invalid;
    }
  } else {
    const double dt = ahrs_dt_s(previous_timer_, s.timer_ticks);
    previous_timer_ = s.timer_ticks;
    if (dt <= 0.0 || dt > params_.max_dt_s) {
      ++stats_.dt_resets;  // skip propagation; the next interval starts at this sample
    } else {
      AttitudeInput in;
      in.omega_b_radps = s.omega_b_radps;
      in.f_b_mps2 = s.f_b_mps2;
      in.m_b_tesla = s.m_b_tesla;
      in.dt_s = dt;
      last_status_ = attitude_->step(in);
      const auto& attitude_updates = attitude_->innovations();
      innovations_.insert(innovations_.end(), attitude_updates.begin(), attitude_updates.end());
      if (kf_) {
        const Vec3 a_n = pv::nav_acceleration(attitude_->q_nb(), s.f_b_mps2, gravity_mps2_);
        kf_->predict(a_n, dt, params_.accel_noise_density_mps2_rthz);
      }
    }
  }
  apply_queued_fixes();
}

void Navigator::apply_queued_fixes() {
  for (const auto& fix : queue_) {
    std::visit([this](const auto& f) { apply(f); }, fix);
  }
  queue_.clear();
}

template <int M>
void Navigator::count(const UpdateReport<M>& report, std::uint64_t& fused_counter) {
  switch (report.status) {
    case UpdateStatus::kFused: ++fused_counter; break;
    case UpdateStatus::kRejectedGate: ++stats_.gps_rejected_gate; break;
    case UpdateStatus::kRejectedInvalid: ++stats_.gps_rejected_invalid; break;
    case UpdateStatus::kNumericalFault: ++stats_.numerical_faults; break;
  }
}

void Navigator::apply(const GpsPosition& fix) {
  const geodesy::Geodetic& g = fix.position;
  if (!std::isfinite(g.lat_rad) || !std::isfinite(g.lon_rad) || !std::isfinite(g.alt_m) ||
      std::abs(g.lat_rad) > 0.5 * std::numbers::pi || std::abs(g.lon_rad) > std::numbers::pi) {
    ++stats_.gps_rejected_invalid;
    return;
  }
  if (!kf_) {
    // Anchor: the plane's origin is this fix, so the KF starts at p_n = 0 with the fix's
    // uncertainty and an unknown velocity.
    plane_.emplace(g);
    gravity_mps2_ = geodesy::normal_gravity(g.lat_rad, g.alt_m);
    const double sh = params_.gps_horizontal_std_m;
    const double sv = params_.gps_vertical_std_m;
    const double su = params_.initial_velocity_std_mps;
    pv::Covariance P0 = pv::Covariance::Zero();
    P0.diagonal() << sh * sh, sh * sh, sv * sv, su * su, su * su, su * su;
    kf_.emplace(pv::State::Zero(), P0);
    ++stats_.gps_position_fused;
    return;
  }
  const Vec3 z = plane_->to_ned(g);  // NED of the fix; altitude maps to −z (depth = +z)
  const Vec3 std_m(params_.gps_horizontal_std_m, params_.gps_horizontal_std_m,
                   params_.gps_vertical_std_m);
  const auto report = kf_->update_position(z, std_m, params_.gps_position_gate_nis);
  count(report, stats_.gps_position_fused);
  if (auto i = innovation_of("gps-position", report)) innovations_.push_back(*i);  // [m]
  last_pos_ = report;
}

void Navigator::apply(const GpsVelocity& fix) {
  if (!std::isfinite(fix.sog_mps) || !std::isfinite(fix.cog_rad) || fix.sog_mps < 0.0) {
    ++stats_.gps_rejected_invalid;
    return;
  }
  if (!kf_) {
    ++stats_.gps_velocity_unanchored;
    return;
  }
  const Vec<2> z = pv::velocity_from_sog_cog(fix.sog_mps, fix.cog_rad);  // (M8)
  const auto report = kf_->update_horizontal_velocity(z, params_.gps_velocity_std_mps,
                                                      params_.gps_velocity_gate_nis);
  count(report, stats_.gps_velocity_fused);
  if (auto i = innovation_of("gps-velocity", report)) innovations_.push_back(*i);  // [m/s]
  last_vel_ = report;
}

void Navigator::apply(const DepthMeasurement& depth) {
  if (!std::isfinite(depth.depth_m)) {
    ++stats_.depth_rejected_invalid;
    return;
  }
  if (!kf_) {
    ++stats_.depth_unanchored;
    return;
  }
  // The point at this depth below MSL under the estimated horizontal position, in the plane:
  // D = depth − anchor_depth at the anchor, anchor_depth = −(anchor altitude above MSL),
  // plus the plane's curvature drop away from it, as a GPS altitude maps (M9, M7).
  const geodesy::Geodetic below = plane_->to_geodetic(kf_->p_n());
  const geodesy::Geodetic at_depth{below.lat_rad, below.lon_rad, -depth.depth_m};
  const double z = plane_->to_ned(at_depth).z();  // (M9)
  const auto report = kf_->update_down_position(z, params_.depth_std_m);  // (M9, K3..K7)
  switch (report.status) {
    case UpdateStatus::kFused: ++stats_.depth_fused; break;
    case UpdateStatus::kRejectedInvalid: ++stats_.depth_rejected_invalid; break;
    case UpdateStatus::kNumericalFault: ++stats_.numerical_faults; break;
    case UpdateStatus::kRejectedGate: break;  // depth updates have no gate
  }
  if (auto i = innovation_of("depth", report)) innovations_.push_back(*i);  // [m]
  last_depth_ = report;
}

NavSolution Navigator::solution() const {
  NavSolution s;
  s.attitude_valid = aligned_;
  s.q_nb = attitude_->q_nb();
  if (kf_) {
    s.position_valid = true;
    s.p_n = kf_->p_n();
    s.v_n = kf_->v_n();
    s.p_std_m = kf_->P().diagonal().segment<3>(pv::kPos.idx).cwiseMax(0.0).cwiseSqrt();
    s.position = plane_->to_geodetic(s.p_n);
  }
  return s;
}

}  // namespace nav::estimator

// SPDX-License-Identifier: MIT
// A P1 navigator driven by the AHRS timer and queued GPS fixes (see p1_driver.hpp).
#include "nav/estimator/p1_driver.hpp"

#include <string>
#include <utility>

#include "nav/common/ensure.hpp"
#include "nav/estimator/p1_ekf15.hpp"
#include "nav/estimator/p1_ins.hpp"
#include "nav/estimator/p1_mfins.hpp"
#include "nav/estimator/p1_upf15.hpp"

namespace nav::estimator {

Result<std::unique_ptr<P1Navigator>> make_p1_navigator(std::string_view name,
                                                       const P1Params& params) {
  if (auto ok = validate(params); !ok) return tl::unexpected(ok.error());
  std::unique_ptr<P1Navigator> nav;
  if (name == "ins") nav = std::make_unique<P1Ins>(params);
  if (name == "ekf15") nav = std::make_unique<P1Ekf15>(params);
  if (name == "upf15") nav = std::make_unique<P1Upf15>(params);
  if (name == "mfins") nav = std::make_unique<P1Mfins>(params);
  if (!nav) {
    return fail(ErrorCode::kInvalidArgument, "unknown P1 navigator '" + std::string(name) +
                                                 "' (expected " + p1_navigator_names() + ")");
  }
  return nav;
}

std::string p1_navigator_names() { return "ins, ekf15, upf15, mfins"; }

P1Driver::P1Driver(std::unique_ptr<P1Navigator> navigator, const geodesy::Geodetic& origin,
                   double max_dt_s)
    : navigator_(std::move(navigator)), plane_(origin), max_dt_s_(max_dt_s) {
  NAV_ENSURE(navigator_ != nullptr, "a P1 driver needs a navigator");
  queue_.reserve(kMaxQueuedFixes);
  innovations_.reserve(2 * kMaxQueuedFixes);
}

void P1Driver::add_gps_position(const GpsPosition& fix) {
  if (queue_.size() >= kMaxQueuedFixes) {
    queue_.erase(queue_.begin());
    ++stats_.gps_queue_dropped;
  }
  queue_.push_back(fix);
  ++stats_.gps_queued;
}

void P1Driver::on_ahrs(const AhrsSample& s) {
  ++stats_.ahrs_samples;
  innovations_.clear();
  if (!started_) {
    started_ = true;  // the configured initial state holds at this sample
    previous_timer_ = s.timer_ticks;
    queue_.clear();   // fixes before the start are not part of the run
    return;
  }
  const double dt = ahrs_dt_s(previous_timer_, s.timer_ticks);
  previous_timer_ = s.timer_ticks;
  if (dt <= 0.0 || dt > max_dt_s_) {
    ++stats_.dt_resets;  // no step; the next interval starts at this sample
  } else {
    ImuSample imu;
    imu.dt_s = dt;
    imu.omega_b_radps = s.omega_b_radps;
    imu.f_b_mps2 = s.f_b_mps2;
    imu.m_b_tesla = s.m_b_tesla;
    navigator_->on_imu(imu);  // NaN/Inf refused and counted by the navigator
    const auto& a = navigator_->innovations();
    innovations_.insert(innovations_.end(), a.begin(), a.end());
  }
  for (const GpsPosition& fix : queue_) {
    navigator_->on_gps_position(plane_.to_ned(fix.position));
    const auto& g = navigator_->innovations();
    innovations_.insert(innovations_.end(), g.begin(), g.end());
  }
  queue_.clear();
}

NavSolution P1Driver::solution() const {
  const P1Solution p = navigator_->solution();
  NavSolution s;
  s.attitude_valid = started_ && p.valid;
  s.position_valid = started_ && p.valid;
  s.q_nb = p.q_nb;
  s.p_n = p.p_n;
  s.v_n = p.v_n;
  s.position = plane_.to_geodetic(p.p_n);
  if (p.has_covariance) s.p_std_m = p.P_position_n.diagonal().cwiseMax(0.0).cwiseSqrt();
  return s;
}

}  // namespace nav::estimator

// SPDX-License-Identifier: MIT
// D1 and S1..S5 are stated in p3_navigator.hpp.
#include "p3_navigator.hpp"

#include <cmath>

#include "nav/common/frames.hpp"
#include "nav/common/units.hpp"
#include "nav/common/wall_frame.hpp"
#include "nav/estimator/filter_params.hpp"

namespace nav::dut {
namespace {

namespace we = protocols::wheel_encoder;
using estimator::P3Slice;

/// Below this cos ϑ_m the slope projection S4 is refused (a wall tilted > 84° from vertical).
constexpr double kMinCosPitch = 0.1;
constexpr double kTicksPerSecond = 62500.0;  ///< the Keller poll schedule's clock
/// 1-σ stated across the wall: the robot is pressed on it (S6) [m].
constexpr double kAcrossWallStdM = 0.001;

}  // namespace

P3Navigator::P3Navigator(const estimator::FilterParams& params, const P3Config& config)
    : params_(params),
      config_(config),
      plane_({units::deg_to_rad(params.origin_lat_deg), units::deg_to_rad(params.origin_lon_deg),
              -params.origin_depth_m}),
      R_nw_(wall_rotation(config.wall_slope_rad, config.wall_azimuth_rad)),
      kinematic_(config.chi_rad) {}

void P3Navigator::on_wheel(const we::WheelEncoderSample& s, double angle_per_tick_rad) {
  if (!s.valid) {
    ++counts_.wheel_invalid;
    return;
  }
  ++counts_.wheel_samples;
  const std::size_t j = s.wheel == we::Wheel::kRight ? 0 : 1;  // u = [d_r, d_l]
  if (last_ticks_[j]) {
    travel_(static_cast<Eigen::Index>(j)) += static_cast<double>(we::tick_delta(s.ticks, *last_ticks_[j])) *
                     angle_per_tick_rad * config_.wheel_radius_m;
  }
  last_ticks_[j] = s.ticks;
}

void P3Navigator::add_depth(double depth_m) {
  if (!std::isfinite(depth_m)) return;
  ++counts_.depths;
  const double T = params_.depth_poll_period_s;
  const double a = T / (config_.depth_tau_s + T);            // D1
  depth_lp_ = depth_lp_ ? *depth_lp_ + a * (depth_m - *depth_lp_) : depth_m;  // D1
  depth_new_ = true;
}

void P3Navigator::on_ebimu(const std::array<double, 3>& euler_deg) {
  innovations_.clear();
  const double theta_m = wrap_pi(units::deg_to_rad(euler_deg[0]));  // S3
  const double pitch = units::deg_to_rad(euler_deg[1]);
  if (!std::isfinite(theta_m) || !std::isfinite(pitch)) {
    ++counts_.faults;
    return;
  }
  ++counts_.steps;
  if (!ekf_) {                                                 // S1
    const estimator::P3Vec x0(0.0, 0.0, theta_m);
    const estimator::P3Vec sd(config_.initial_position_std_m, config_.initial_position_std_m,
                              config_.initial_theta_std_rad);
    ekf_.emplace(config_.filter, x0, sd.array().square().matrix().asDiagonal());
    travel_.setZero();
    return;
  }
  const estimator::P3Vec before = ekf_->state();
  if (ekf_->predict(travel_) != estimator::StepStatus::kApplied) ++counts_.faults;  // S2
  travel_.setZero();
  if (config_.method != P3Method::kDeadReckoning && depth_new_) update(pitch, theta_m);
  const estimator::P3Vec& x = ekf_->state();
  const Vec3 dp_w(x(P3Slice::kX) - before(P3Slice::kX), x(P3Slice::kY) - before(P3Slice::kY),
                  0.0);
  v_n_ = R_nw_ * dp_w * config_.ebimu_rate_hz;
}

void P3Navigator::update(double pitch_rad, double theta_m) {
  depth_new_ = false;
  const double c = std::cos(pitch_rad);
  if (std::abs(c) < kMinCosPitch) {
    ++counts_.steep_pitch;
    return;
  }
  const double y_m = (*depth_lp_ - params_.origin_depth_m) / std::abs(c);  // S4, eq 1
  const estimator::P3Vec& x = ekf_->state();
  std::optional<double> x_m;
  if (config_.method == P3Method::kEkfKr) {
    x_m = kinematic_.step(y_m, theta_m, x(P3Slice::kX));        // K1, K2
  }
  const estimator::P3Vec z(x_m.value_or(x(P3Slice::kX)), y_m, theta_m);
  const auto r = ekf_->update(z, x_m.has_value());              // S5: C6–C8
  if (r.status != estimator::UpdateStatus::kFused) {
    ++counts_.faults;
    return;
  }
  ++counts_.updates;
  if (x_m) {
    ++counts_.x_used;
    innovations_.push_back(estimator::innovation_of<3>("p3-x-y-theta", r.y, r.S));
  } else {
    innovations_.push_back(estimator::innovation_of<2>(
        "p3-y-theta", r.y.tail<2>().eval(), r.S.bottomRightCorner<2, 2>().eval()));
  }
}

std::optional<estimator::P3Vec> P3Navigator::wall_state() const {
  if (!ekf_) return std::nullopt;
  return ekf_->state();
}

estimator::NavSolution P3Navigator::solution() const {
  estimator::NavSolution s;
  if (!ekf_) return s;
  const estimator::P3Vec& x = ekf_->state();
  s.attitude_valid = true;
  s.position_valid = true;
  s.p_n = R_nw_ * Vec3(x(P3Slice::kX), x(P3Slice::kY), 0.0);
  s.position = plane_.to_geodetic(s.p_n);
  s.v_n = v_n_;
  const Quat q_wb(Eigen::AngleAxisd(x(P3Slice::kTheta), Vec3::UnitZ()));
  s.q_nb = (Quat(R_nw_) * q_wb).normalized();
  if (const auto P = position_covariance()) {
    s.p_std_m = P->diagonal().cwiseMax(0.0).cwiseSqrt();
  }
  return s;
}

std::optional<Mat3> P3Navigator::position_covariance() const {
  if (!ekf_) return std::nullopt;
  Mat3 P_w = Mat3::Zero();
  P_w.topLeftCorner<2, 2>() = ekf_->covariance().topLeftCorner<2, 2>();
  P_w(2, 2) = kAcrossWallStdM * kAcrossWallStdM;  // S6
  return R_nw_ * P_w * R_nw_.transpose();
}

std::uint32_t P3Navigator::clock_ticks() const {
  const double t = static_cast<double>(counts_.steps) / config_.ebimu_rate_hz;
  return static_cast<std::uint32_t>(
      static_cast<std::uint64_t>(std::llround(t * kTicksPerSecond)) & 0xFFFFFFFFu);
}

}  // namespace nav::dut

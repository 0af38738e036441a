// SPDX-License-Identifier: MIT
// See p1_ins.hpp.
#include "nav/estimator/p1_ins.hpp"

#include "nav/common/ensure.hpp"

namespace nav::estimator {

namespace {
using EM = P1ErrorModel;
}  // namespace

P1Ins::P1Ins(const P1Params& params) : params_(params) {
  NAV_ENSURE(validate(params).has_value(), "P1 parameters must be validated first");
  x_ = EM::initial_state(params);
  P_ = EM::initial_covariance(params);
  Q_c_ = EM::continuous_noise(params);
}

void P1Ins::on_imu(const ImuSample& sample) {
  innovations_.clear();
  ++stats_.imu_samples;
  if (!is_valid(sample, params_.max_dt_s)) {
    ++stats_.imu_rejected_invalid;
    return;
  }
  // No bias is estimated: b̂_a = b̂_g = 0 for ever (their errors stay in P).
  if (!EM::predict(x_, Vec3::Zero(), Vec3::Zero(), P_, sample, Q_c_, params_.gravity_n())) {
    ++stats_.numerical_faults;
  }
}

void P1Ins::on_gps_position(const Vec3& /*p_n_measured_m*/) { innovations_.clear(); }

P1Solution P1Ins::solution() const {
  P1Solution s;
  s.valid = true;
  s.q_nb = x_.q_nb;
  s.p_n = x_.p_n;
  s.v_n = x_.v_n;
  s.P_position_n = P_.block<EM::kDp.dof, EM::kDp.dof>(EM::kDp.idx, EM::kDp.idx);
  s.P_attitude_n = P_.block<EM::kRho.dof, EM::kRho.dof>(EM::kRho.idx, EM::kRho.idx);
  s.has_covariance = true;
  return s;
}

}  // namespace nav::estimator

// SPDX-License-Identifier: MIT
// C1..C8 are stated in p3_crawler_ekf.hpp.
#include "nav/estimator/p3_crawler_ekf.hpp"

#include <cmath>

#include <Eigen/Cholesky>

#include "nav/common/frames.hpp"

namespace nav::estimator {
namespace {

/// Δs, Δθ and φ of C1.
struct Step {
  double ds, dtheta, phi;
};

Step step_of(const P3Vec& x, const P3Input& u, double track_m) {
  const double ds = 0.5 * (u(0) + u(1));                // C1
  const double dtheta = (u(1) - u(0)) / track_m;        // C1
  return {ds, dtheta, x(P3Slice::kTheta) + 0.5 * dtheta};  // C1
}

}  // namespace

P3Vec p3_motion(const P3Vec& x, const P3Input& u, double track_m) {
  const Step s = step_of(x, u, track_m);
  P3Vec out = x;
  out(P3Slice::kX) += s.ds * std::cos(s.phi);   // C2
  out(P3Slice::kY) += s.ds * std::sin(s.phi);   // C2
  out(P3Slice::kTheta) += s.dtheta;             // C2
  return out;
}

P3Mat p3_state_jacobian(const P3Vec& x, const P3Input& u, double track_m) {
  const Step s = step_of(x, u, track_m);
  P3Mat A = P3Mat::Identity();                    // C3
  A(P3Slice::kX, P3Slice::kTheta) = -s.ds * std::sin(s.phi);
  A(P3Slice::kY, P3Slice::kTheta) = s.ds * std::cos(s.phi);
  return A;
}

P3InputJacobian p3_input_jacobian(const P3Vec& x, const P3Input& u, double track_m) {
  const Step s = step_of(x, u, track_m);
  const double c = std::cos(s.phi), sn = std::sin(s.phi);
  const double turn = s.ds / (2.0 * track_m);  // Δs/(2b) = R(ω_r + ω_l)ΔT/(4b), eq 7 with ΔT
  P3InputJacobian W;                            // C4
  W << 0.5 * c + turn * sn, 0.5 * c - turn * sn,
       0.5 * sn - turn * c, 0.5 * sn + turn * c,
       -1.0 / track_m, 1.0 / track_m;
  return W;
}

P3CrawlerEkf::P3CrawlerEkf(const P3Params& params, const P3Vec& x0, const P3Mat& P0)
    : params_(params), x_(x0), P_(P0) {}

StepStatus P3CrawlerEkf::predict(const P3Input& u) {
  if (!u.allFinite()) return StepStatus::kRejectedInvalid;
  const P3Mat A = p3_state_jacobian(x_, u, params_.track_m);
  const P3InputJacobian W = p3_input_jacobian(x_, u, params_.track_m);
  const Eigen::Vector2d q(params_.k_r * std::abs(u(0)), params_.k_l * std::abs(u(1)));
  x_ = p3_motion(x_, u, params_.track_m);                                     // C2
  P_ = A * P_ * A.transpose() + W * q.asDiagonal() * W.transpose();           // C5
  P_ = 0.5 * (P_ + P_.transpose());
  return StepStatus::kApplied;
}

UpdateReport<3> P3CrawlerEkf::update(const P3Vec& z, bool use_x) {
  UpdateReport<3> r;
  if (!z.allFinite()) return r;  // kRejectedInvalid
  const P3Vec sigma(params_.sigma_x_m, params_.sigma_y_m, params_.sigma_theta_rad);
  const P3Mat R = sigma.array().square().matrix().asDiagonal();
  P3Vec nu = z - x_;                                       // C6
  nu(P3Slice::kTheta) = wrap_pi(nu(P3Slice::kTheta));
  const P3Mat S = P_ + R;                                  // C6
  const Eigen::LDLT<P3Mat> S_ldlt(S);
  r.y = nu;
  r.S = S;
  if (S_ldlt.info() != Eigen::Success || !(S_ldlt.vectorD().array() > 0.0).all()) {
    r.status = UpdateStatus::kNumericalFault;
    return r;
  }
  r.nis = nu.dot(S_ldlt.solve(nu));
  P3Mat K = S_ldlt.solve(P_).transpose();                  // C7: K = P S⁻¹ (S, P symmetric)
  if (!use_x) K.row(P3Slice::kX).setZero();                // C7: no x correction
  const P3Mat I_K = P3Mat::Identity() - K;
  const P3Vec x_new = x_ + K * nu;                         // C8
  const P3Mat P_new = I_K * P_ * I_K.transpose() + K * R * K.transpose();  // C8, Joseph
  if (!x_new.allFinite() || !P_new.allFinite()) {
    r.status = UpdateStatus::kNumericalFault;
    return r;
  }
  x_ = x_new;
  x_(P3Slice::kTheta) = wrap_pi(x_(P3Slice::kTheta));
  P_ = 0.5 * (P_new + P_new.transpose());
  r.status = UpdateStatus::kFused;
  return r;
}

}  // namespace nav::estimator

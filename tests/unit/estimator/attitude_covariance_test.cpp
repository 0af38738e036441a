// SPDX-License-Identifier: MIT
// The attitude covariance each attitude source states for `$PNVBCOV` (attitude_filter.hpp):
// the NED rotation vector δθ of R_true R_estᵀ. The Euler filters' map from their state
// (rotation_vector_jacobian) and the ESKF's from its local error are checked against finite
// differences of the rotations themselves; sources without a covariance say so.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "nav/common/frames.hpp"
#include "nav/estimator/attitude_filter.hpp"
#include "nav/estimator/euler_attitude.hpp"
#include "nav/estimator/quat_eskf.hpp"

namespace nav::estimator {
namespace {

Mat3 rotation(const p0::EulerState& x) {
  return quat_from_euler(Euler{x(0), x(1), x(2)}).toRotationMatrix();
}

/// The rotation vector of R (its axis times its angle).
Vec3 log_of(const Mat3& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.axis() * aa.angle();
}

TEST(AttitudeCovariance, EulerJacobianMatchesFiniteDifferencesOfTheRotation) {
  const double h = 1e-7;
  for (const p0::EulerState& x : {p0::EulerState(0.0, 0.0, 0.0), p0::EulerState(0.3, -0.2, 1.1),
                                 p0::EulerState(-2.5, 1.2, -3.0), p0::EulerState(0.1, -1.4, 2.0)}) {
    const Mat3 J = p0::rotation_vector_jacobian(x);
    for (int i = 0; i < 3; ++i) {
      p0::EulerState xp = x, xm = x;
      xp(i) += h;
      xm(i) -= h;
      // δθ of R(x ± h) R(x)ᵀ, central difference.
      const Vec3 column = (log_of(rotation(xp) * rotation(x).transpose()) -
                           log_of(rotation(xm) * rotation(x).transpose())) /
                          (2.0 * h);
      EXPECT_LT((column - J.col(i)).norm(), 1e-7) << "state " << x.transpose() << " column " << i;
    }
  }
}

TEST(AttitudeCovariance, EskfLocalErrorTurnsIntoNedByTheAttitude) {
  // q ⊗ Exp(δθ_b) = Exp(R δθ_b) ⊗ q: checked on the rotations for a small δθ_b.
  const Quat q = quat_from_euler(Euler{0.4, -0.3, 2.2});
  const Vec3 d_b(1e-6, -2e-6, 0.5e-6);
  const Quat q_true = q * Quat(Eigen::AngleAxisd(d_b.norm(), d_b.normalized()));
  const Vec3 d_n = log_of(q_true.toRotationMatrix() * q.toRotationMatrix().transpose());
  EXPECT_LT((d_n - q.toRotationMatrix() * d_b).norm(), 1e-12);
}

TEST(AttitudeCovariance, FiltersWithACovarianceStateItSourcesWithoutOneDoNot) {
  const FilterParams params;
  const Vec3 f_b(0.0, 0.0, -9.80665);
  const Vec3 m_b(20e-6, 1e-6, 40e-6);
  for (const auto kind : {AttitudeFilterKind::kEkf, AttitudeFilterKind::kUkf,
                          AttitudeFilterKind::kEskf}) {
    auto f = make_attitude_filter(kind, params);
    ASSERT_TRUE(f->initialise(f_b, m_b));
    const auto P = f->attitude_covariance_n();
    ASSERT_TRUE(P) << static_cast<int>(kind);
    EXPECT_LT((*P - P->transpose()).norm(), 1e-15);
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(*P);
    EXPECT_GT(eig.eigenvalues().minCoeff(), 0.0) << static_cast<int>(kind);
  }
  // The Euler EKF's is J P Jᵀ of its state and P.
  p0::EulerEkf ekf(p0::EkfParams{}, 0.0);
  ASSERT_TRUE(ekf.initialise(f_b, m_b));
  const Mat3 J = p0::rotation_vector_jacobian(ekf.state());
  EXPECT_LT((*ekf.attitude_covariance_n() - J * ekf.covariance() * J.transpose()).norm(), 1e-15);
  // The ESKF's is R P_θθ Rᵀ of its local error's block.
  QuatEskf eskf(EskfParams{});
  ASSERT_TRUE(eskf.initialise(f_b, m_b));
  const Mat3 R = eskf.q_nb().toRotationMatrix();
  const Mat3 P_tt = eskf.covariance().topLeftCorner<3, 3>();
  EXPECT_LT((*eskf.attitude_covariance_n() - R * P_tt * R.transpose()).norm(), 1e-15);
  for (const auto kind : {AttitudeFilterKind::kRaw, AttitudeFilterKind::kCf,
                          AttitudeFilterKind::kMahony}) {
    auto f = make_attitude_filter(kind, params);
    ASSERT_TRUE(f->initialise(f_b, m_b));
    EXPECT_FALSE(f->attitude_covariance_n()) << static_cast<int>(kind);
  }
}

}  // namespace
}  // namespace nav::estimator

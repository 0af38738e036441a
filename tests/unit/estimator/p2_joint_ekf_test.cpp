// SPDX-License-Identifier: MIT
// Paper P2's joint EKF (p2_joint_ekf.hpp): one step on two vehicles against numbers computed
// by hand, the prediction by increments, three vehicles (a fix couples only the two it
// names), the geometry leaving observations out, refusals, and heading wrap.
#include "nav/estimator/p2_joint_ekf.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Eigenvalues>

namespace nav::estimator {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

P2Vec state(double n, double e, double d, double psi, double theta) {
  return (P2Vec() << n, e, d, psi, theta).finished();
}

/// The 5 × 5 block of M at (r, c): vehicle r/5's rows, vehicle c/5's columns.
P2Mat block(const P2JointEkf::JointMat& M, int r, int c) {
  return M.block<kP2VehicleDim, kP2VehicleDim>(r, c);
}

P2Measurement fix(int i, int j, P2Observation o, double z) {
  P2Measurement m;
  m.observer = i;
  m.observed = j;
  m.set.add(o);
  m.z(static_cast<int>(o)) = z;
  return m;
}

TEST(P2JointEkf, OneDistanceUpdateByHand) {
  // i at the origin, j 3 m North and 4 m East at the same depth; P = I, σ_d = 0.1 m.
  //   H = [−0.6, −0.8, 0, 0, 0, 0.6, 0.8, 0, 0, 0]
  //   S = H Hᵀ + 0.01 = 0.36 + 0.64 + 0.36 + 0.64 + 0.01 = 2.01
  //   z = 5.201, y = 0.201, K = Hᵀ / 2.01, K y = 0.1 Hᵀ
  //   X_i ← (−0.06, −0.08, 0, ...), X_j ← (3.06, 4.08, 0, ...)
  //   P ← I − Hᵀ H / 2.01 (Joseph and short form agree for the optimal gain)
  P2JointEkf f(P2Params{}, 2);
  ASSERT_TRUE(f.init_vehicle(0, state(0, 0, 0, 0, 0), P2Mat::Identity()));
  ASSERT_TRUE(f.init_vehicle(1, state(3, 4, 0, 0, 0), P2Mat::Identity()));
  const P2UpdateReport r = f.update(fix(0, 1, P2Observation::kDistance3d, 5.201));
  ASSERT_EQ(r.status, UpdateStatus::kFused);
  EXPECT_EQ(r.m, 1);
  EXPECT_NEAR(r.y(0), 0.201, 1e-12);
  EXPECT_NEAR(r.S(0, 0), 2.01, 1e-12);
  EXPECT_NEAR(r.nis, 0.201 * 0.201 / 2.01, 1e-12);
  EXPECT_NEAR(f.state(0)(0), -0.06, 1e-12);
  EXPECT_NEAR(f.state(0)(1), -0.08, 1e-12);
  EXPECT_NEAR(f.state(1)(0), 3.06, 1e-12);
  EXPECT_NEAR(f.state(1)(1), 4.08, 1e-12);
  EXPECT_DOUBLE_EQ(f.state(1)(2), 0.0);
  const auto& P = f.joint_covariance();
  EXPECT_NEAR(P(0, 0), 1.0 - 0.36 / 2.01, 1e-12);
  EXPECT_NEAR(P(0, 1), -0.48 / 2.01, 1e-12);
  EXPECT_NEAR(P(0, 5), 0.36 / 2.01, 1e-12);   // N_i with N_j: −(−0.6)(0.6)/2.01
  EXPECT_NEAR(P(1, 6), 0.64 / 2.01, 1e-12);
  EXPECT_DOUBLE_EQ(P(2, 2), 1.0);
  EXPECT_DOUBLE_EQ(P(3, 3), 1.0);
}

TEST(P2JointEkf, PredictionAddsTheIncrementAndItsNoiseToItsVehicleOnly) {
  P2Params params;
  params.process_noise_rthz = state(0.1, 0.2, 0.3, 0.01, 0.02);
  P2JointEkf f(params, 2);
  ASSERT_TRUE(f.init_vehicle(0, state(0, 0, 0, 3.0, 0), P2Mat::Identity()));
  ASSERT_TRUE(f.init_vehicle(1, state(50, 0, 0, 0, 0), P2Mat::Identity()));
  ASSERT_EQ(f.update(fix(0, 1, P2Observation::kDistance3d, 50.3)).status, UpdateStatus::kFused);
  const P2JointEkf::JointMat before = f.joint_covariance();
  const P2Vec x0 = f.state(0);
  const P2Vec x1 = f.state(1);
  ASSERT_EQ(f.predict(0, state(1.0, -2.0, 0.5, 0.3, 0.01), 4.0), StepStatus::kApplied);
  EXPECT_DOUBLE_EQ(f.state(0)(0), x0(0) + 1.0);
  EXPECT_DOUBLE_EQ(f.state(0)(1), x0(1) - 2.0);
  EXPECT_DOUBLE_EQ(f.state(0)(P2Slice::kTheta), x0(P2Slice::kTheta) + 0.01);
  EXPECT_EQ(f.state(1), x1);
  // ψ: about 3.0 + 0.3 wraps to 3.3 − 2π.
  EXPECT_NEAR(f.state(0)(P2Slice::kPsi), x0(P2Slice::kPsi) + 0.3 - 2.0 * std::numbers::pi,
              1e-12);
  const P2JointEkf::JointMat dP = f.joint_covariance() - before;
  const P2Vec expected_diag = state(0.01, 0.04, 0.09, 1e-4, 4e-4) * 4.0;
  EXPECT_LT((block(dP, 0, 0) - P2Mat(expected_diag.asDiagonal())).cwiseAbs().maxCoeff(),
            1e-15);
  // Cross-covariances and the other vehicle are untouched (F = I).
  EXPECT_EQ(block(dP, 0, 5).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(block(dP, 5, 5).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(f.predict(0, state(kNaN, 0, 0, 0, 0), 1.0), StepStatus::kRejectedInvalid);
  EXPECT_EQ(f.predict(0, P2Vec::Zero(), -1.0), StepStatus::kRejectedInvalid);
}

TEST(P2JointEkf, AFixCouplesOnlyTheTwoVehiclesItNames) {
  P2JointEkf f(P2Params{}, 3);
  for (int l = 0; l < 3; ++l) {
    ASSERT_TRUE(f.init_vehicle(l, state(100.0 * l, 10.0 * l, 5.0 * l, 0.1 * l, 0.0),
                               P2Mat::Identity() * (1.0 + l)));
  }
  P2Measurement m;
  m.observer = 2;
  m.observed = 0;
  m.set = P2ObservationSet::experiment(4);
  const P2Vec x2 = f.state(2), x0 = f.state(0);
  for (int k = 0; k < kP2ObservationKinds; ++k) {
    m.z(k) = p2_observe(static_cast<P2Observation>(k), x2, x0) + 0.01;
  }
  const P2UpdateReport r = f.update(m);
  ASSERT_EQ(r.status, UpdateStatus::kFused);
  EXPECT_EQ(r.m, 5);
  EXPECT_EQ(r.fused, P2ObservationSet::experiment(4));
  const auto& P = f.joint_covariance();
  EXPECT_GT(block(P, 0, 10).cwiseAbs().maxCoeff(), 1e-3);  // 0 with 2 now correlated
  EXPECT_EQ(block(P, 0, 5).cwiseAbs().maxCoeff(), 0.0);    // 1 untouched
  EXPECT_EQ(block(P, 5, 10).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(f.state(1), state(100.0, 10.0, 5.0, 0.1, 0.0));
  // The update shrinks the uncertainty of both and stays symmetric positive definite.
  EXPECT_LT(block(P, 0, 0).trace(), 5.0);
  EXPECT_LT(block(P, 10, 10).trace(), 15.0);
  EXPECT_EQ((P - P.transpose()).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<P2JointEkf::JointMat>(P).eigenvalues().minCoeff(), 0.0);
}

TEST(P2JointEkf, VerticalGeometryLeavesTheUndefinedObservationsOut) {
  P2JointEkf f(P2Params{}, 2);
  ASSERT_TRUE(f.init_vehicle(0, state(0, 0, 0, 0, 0), P2Mat::Identity()));
  ASSERT_TRUE(f.init_vehicle(1, state(0.1, 0, 40, 0, 0), P2Mat::Identity()));
  P2Measurement m;
  m.set = P2ObservationSet::experiment(4);
  m.z << 0.1, 40.2, 0.0, 0.0, 1.57, 0.0;
  const P2UpdateReport r = f.update(m);
  ASSERT_EQ(r.status, UpdateStatus::kFused);
  EXPECT_TRUE(r.degenerate.has(P2Observation::kBearing));
  EXPECT_TRUE(r.degenerate.has(P2Observation::kElevation));
  EXPECT_TRUE(r.fused.has(P2Observation::kDistance3d) && r.fused.has(P2Observation::kPitch));
  EXPECT_EQ(r.m, 3);
}

TEST(P2JointEkf, RefusalsLeaveTheFilterAsItWas) {
  P2JointEkf f(P2Params{}, 2);
  EXPECT_FALSE(f.init_vehicle(2, P2Vec::Zero(), P2Mat::Identity()));
  EXPECT_FALSE(f.init_vehicle(0, P2Vec::Zero(), -P2Mat::Identity()));
  P2Mat asym = P2Mat::Identity();
  asym(0, 1) = 0.5;
  EXPECT_FALSE(f.init_vehicle(0, P2Vec::Zero(), asym));
  ASSERT_TRUE(f.init_vehicle(0, P2Vec::Zero(), P2Mat::Identity()));
  // Vehicle 1 has no state yet.
  EXPECT_TRUE(f.update(fix(0, 1, P2Observation::kDistance3d, 10.0)).unknown_vehicle);
  ASSERT_TRUE(f.init_vehicle(1, state(10, 0, 0, 0, 0), P2Mat::Identity()));
  EXPECT_TRUE(f.update(fix(1, 1, P2Observation::kDistance3d, 10.0)).unknown_vehicle);
  const auto X = f.joint_state();
  const auto P = f.joint_covariance();
  EXPECT_EQ(f.update(fix(0, 1, P2Observation::kDistance3d, kNaN)).status,
            UpdateStatus::kRejectedInvalid);
  P2Params gated;
  gated.nis_gate = 9.0;
  P2JointEkf g(gated, 2);
  ASSERT_TRUE(g.init_vehicle(0, P2Vec::Zero(), P2Mat::Identity() * 0.01));
  ASSERT_TRUE(g.init_vehicle(1, state(10, 0, 0, 0, 0), P2Mat::Identity() * 0.01));
  EXPECT_EQ(g.update(fix(0, 1, P2Observation::kDistance3d, 30.0)).status,
            UpdateStatus::kRejectedGate);
  EXPECT_EQ(g.state(1), state(10, 0, 0, 0, 0));
  EXPECT_EQ(f.joint_state(), X);
  EXPECT_EQ(f.joint_covariance(), P);
}

TEST(P2JointEkf, HeadingInnovationWrapsAcrossPi) {
  // ψ_i = 179°, ψ_j = −179°: a measured relative heading of +2° is consistent (innovation ≈ 0),
  // not 358° off.
  const double deg = std::numbers::pi / 180.0;
  P2JointEkf f(P2Params{}, 2);
  ASSERT_TRUE(f.init_vehicle(0, state(0, 0, 0, 179.0 * deg, 0), P2Mat::Identity() * 1e-4));
  ASSERT_TRUE(f.init_vehicle(1, state(20, 0, 0, -179.0 * deg, 0), P2Mat::Identity() * 1e-4));
  const P2UpdateReport r = f.update(fix(0, 1, P2Observation::kHeading, 2.0 * deg));
  ASSERT_EQ(r.status, UpdateStatus::kFused);
  EXPECT_NEAR(r.y(0), 0.0, 1e-12);
  EXPECT_GT(f.state(1)(P2Slice::kPsi), -std::numbers::pi);
  EXPECT_LE(f.state(1)(P2Slice::kPsi), std::numbers::pi);
}

}  // namespace
}  // namespace nav::estimator

// SPDX-License-Identifier: MIT
// Strapdown INS of paper P1 (strapdown.hpp): quaternion kinematics (eq 1) against known
// rotations, the DCM (eq 2) against Eigen, the paper's printed Ξ(q) shown wrong (|q| drifts,
// wrong rotation), the closed-form SO(3) integrals against quadrature, and whole trajectories
// (constant-rate turns, level and banked and climbing) integrated back to the known position.
#include "nav/estimator/strapdown.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "nav/common/units.hpp"
#include "nav/estimator/complementary_attitude.hpp"
#include "p1_test_support.hpp"
#include "test_support.hpp"

namespace nav::estimator {
namespace {

using Vec4 = Eigen::Vector4d;
using Xi43 = Eigen::Matrix<double, 4, 3>;
constexpr double kG0 = units::kStandardGravity;
const Vec3 kGn(0.0, 0.0, kG0);

Quat random_quat(std::mt19937_64& rng) {
  testing::Normal n(rng());
  Vec4 c(n(), n(), n(), n());
  return Quat(c.normalized());  // Eigen's 4-vector constructor is (x, y, z, w)
}

/// Eq 1's matrix as docs/papers.md reads the paper: the ω⊗q form with +q₃ at (4,3).
Xi43 printed_xi(const Quat& q) {
  const double q1 = q.x(), q2 = q.y(), q3 = q.z(), q4 = q.w();
  Xi43 Xi;
  Xi << q4, q3, -q2,  //
      -q3, q4, q1,    //
      q2, -q1, q4,    //
      -q1, -q2, q3;
  return Xi;
}

/// The ω⊗q form with the (4,3) sign right: q̇ = ½ [ω; 0] ⊗ q (ω in the navigation frame).
Xi43 omega_q_xi(const Quat& q) {
  Xi43 Xi = printed_xi(q);
  Xi(3, 2) = -q.z();
  return Xi;
}

/// Integrates q̇ = ½ Xi(q) ω with classic RK4 for n steps of dt (no normalisation).
template <typename XiFn>
Vec4 rk4(XiFn xi, Vec4 c, const Vec3& omega, double dt, int n) {
  auto f = [&](const Vec4& y) { return Vec4(0.5 * xi(Quat(y)) * omega); };
  for (int i = 0; i < n; ++i) {
    const Vec4 k1 = f(c);
    const Vec4 k2 = f(c + 0.5 * dt * k1);
    const Vec4 k3 = f(c + 0.5 * dt * k2);
    const Vec4 k4 = f(c + dt * k3);
    c += dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
  }
  return c;
}

TEST(P1Strapdown, ConstantRateAboutEachAxisGivesTheKnownQuaternion) {
  // 0.3 rad/s for 10 s about body x, y, z from a non-trivial start: q0 ⊗ AngleAxis(3 rad).
  const Quat q0 = quat_from_euler({0.2, -0.4, 1.0});
  for (int axis = 0; axis < 3; ++axis) {
    const Vec3 u = Vec3::Unit(axis);
    const Vec3 omega = 0.3 * u;
    const Quat q_known = q0 * Quat(Eigen::AngleAxisd(3.0, u));
    NavState x;
    x.q_nb = q0;
    for (int i = 0; i < 1000; ++i) {
      x = strapdown_step(x, omega, -(x.q_nb.conjugate() * kGn), 0.01, kGn);
    }
    EXPECT_LT(x.q_nb.angularDistance(q_known), 1e-12) << "axis " << axis;
    // Eq 1 itself (the corrected Ξ) integrated by RK4 reaches the same quaternion.
    const Vec4 c = rk4(quat_rate_matrix, q0.coeffs(), omega, 0.01, 1000);
    EXPECT_LT((c - q_known.coeffs()).norm(), 1e-9) << "axis " << axis;
  }
}

TEST(P1Strapdown, XiIsTheDerivativeOfAKnownRotation) {
  // d/dt (q0 ⊗ Exp(ω t)) at t = 0 by central differences against ½ Ξ(q0) ω (eq 1).
  std::mt19937_64 rng(11);
  testing::Normal n(12);
  for (int k = 0; k < 20; ++k) {
    const Quat q0 = random_quat(rng);
    const Vec3 omega = n.vec3();
    const double h = 1e-6;
    const Vec4 plus = (q0 * quat_exp(omega * h)).coeffs();
    const Vec4 minus = (q0 * quat_exp(-omega * h)).coeffs();
    const Vec4 numeric = (plus - minus) / (2.0 * h);
    EXPECT_LT((quat_derivative(q0, omega) - numeric).norm(), 1e-9);
    // Ξ(q)ᵀ q = 0: the kinematics keep |q| (d|q|²/dt = qᵀ Ξ ω).
    EXPECT_LT((quat_rate_matrix(q0).transpose() * q0.coeffs()).norm(), 1e-15);
  }
}

TEST(P1Strapdown, DcmMatchesEigenForRandomQuaternions) {
  std::mt19937_64 rng(7);
  for (int k = 0; k < 200; ++k) {
    const Quat q = random_quat(rng);
    const Mat3 R = dcm_from_quat(q);
    EXPECT_LT((R - q.toRotationMatrix()).cwiseAbs().maxCoeff(), 1e-15);
    // The (3,1) entry: 2(q₂q₄ − q₁q₃) with q₁ the scalar (eq 2's numbering), i.e.
    // 2(q₁q₃ − q₂q₄) in eq 1's scalar-last numbering.
    EXPECT_NEAR(R(2, 0), 2.0 * (q.x() * q.z() - q.w() * q.y()), 1e-15);
  }
  // A known rotation: pitch up 90° maps body x (forward) to NED up = −z: R(2,0) = −1.
  const Quat pitch_up(Eigen::AngleAxisd(std::numbers::pi / 2.0, Vec3::UnitY()));
  EXPECT_NEAR(dcm_from_quat(pitch_up)(2, 0), -1.0, 1e-15);
}

TEST(P1Strapdown, PrintedXiDiffersExactlyWhereThePaperIsWrong) {
  std::mt19937_64 rng(3);
  for (int k = 0; k < 20; ++k) {
    const Quat q = random_quat(rng);
    // Corrected − printed = [2 [q₁:₃]× ; (0, 0, −2 q₃)]: the product order (the skew part)
    // and the (4,3) sign; the diagonal and the other scalar row entries agree.
    Xi43 expected = Xi43::Zero();
    expected.topRows<3>() = 2.0 * skew(q.vec());
    expected(3, 2) = -2.0 * q.z();
    EXPECT_LT((quat_rate_matrix(q) - printed_xi(q) - expected).cwiseAbs().maxCoeff(), 1e-15);
  }
}

TEST(P1Strapdown, PrintedXiBreaksTheNormAndTheOmegaQFormTurnsAboutTheWrongAxes) {
  // A start with q₃ q₄ ≠ 0 (yaw 60°) and a yaw rate: the printed matrix has qᵀ Ξ ω = 2 q₃ q₄ ω_z
  // (here 0.43 × 0.2 rad/s), so |q| drifts; the corrected Ξ keeps it.
  const Quat q0 = quat_from_euler({0.1, 0.2, std::numbers::pi / 3.0});
  const Vec3 omega(0.05, -0.03, 0.2);
  EXPECT_NEAR(q0.coeffs().dot(printed_xi(q0) * omega), 2.0 * q0.z() * q0.w() * omega.z(),
              1e-15);
  const Vec4 printed = rk4(printed_xi, q0.coeffs(), omega, 0.01, 1000);
  const Vec4 corrected = rk4(quat_rate_matrix, q0.coeffs(), omega, 0.01, 1000);
  EXPECT_GT(std::abs(printed.norm() - 1.0), 0.05);
  EXPECT_LT(std::abs(corrected.norm() - 1.0), 1e-9);
  // Even with the (4,3) sign fixed, the ω⊗q form applies the body rate about the navigation
  // axes: from yaw 60° a roll rate becomes a rotation about North, not about the body's x.
  const Vec3 roll_rate(0.3, 0.0, 0.0);
  const Quat q_known = q0 * Quat(Eigen::AngleAxisd(3.0, Vec3::UnitX()));
  const Quat q_omega_q(Vec4(rk4(omega_q_xi, q0.coeffs(), roll_rate, 0.01, 1000)).normalized());
  const Quat q_right(Vec4(rk4(quat_rate_matrix, q0.coeffs(), roll_rate, 0.01, 1000)));
  EXPECT_GT(q_omega_q.angularDistance(q_known), 0.5);
  EXPECT_LT(q_right.angularDistance(q_known), 1e-9);
  // From the identity the two forms agree (why the error hides in a test that starts level
  // and North).
  const Quat q_id_omega_q(Vec4(rk4(omega_q_xi, Quat::Identity().coeffs(), roll_rate, 0.01,
                                   1000)));
  EXPECT_LT(q_id_omega_q.angularDistance(Quat(Eigen::AngleAxisd(3.0, Vec3::UnitX()))), 1e-9);
}

/// ∫₀¹ Exp(sφ) ds and ∫₀¹∫₀ᵘ Exp(sφ) ds du by composite Simpson (2000 panels).
void quadrature(const Vec3& phi, Mat3& J, Mat3& Gamma) {
  const int n = 2000;
  J.setZero();
  Gamma.setZero();
  for (int i = 0; i <= n; ++i) {
    const double s = static_cast<double>(i) / n;
    const double w = (i == 0 || i == n) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0);
    const Mat3 E = Eigen::AngleAxisd(phi.norm() * s, phi.normalized()).toRotationMatrix();
    J += w * E;
    Gamma += w * (1.0 - s) * E;  // ∫₀¹∫₀ᵘ g(s) ds du = ∫₀¹ (1 − s) g(s) ds
  }
  J /= 3.0 * n;
  Gamma /= 3.0 * n;
}

TEST(P1Strapdown, So3IntegralsMatchQuadrature) {
  // Both branches of S5 (series below 0.05 rad) and around the switch.
  for (const double angle : {1e-7, 1e-3, 0.0499, 0.0501, 0.3, 2.0, 3.1}) {
    const Vec3 phi = angle * Vec3(0.48, -0.6, 0.64);  // unit axis
    Mat3 J, Gamma;
    quadrature(phi, J, Gamma);
    EXPECT_LT((so3_left_jacobian(phi) - J).cwiseAbs().maxCoeff(), 1e-12) << angle;
    EXPECT_LT((so3_double_integral(phi) - Gamma).cwiseAbs().maxCoeff(), 1e-12) << angle;
  }
}

/// Constant-rate turn about NED down at rate Ω and speed v, with a fixed body tilt q_tilt
/// (so the body rate and the specific force are constant in the body frame but on all three
/// axes) and a constant climb rate, integrated for 0.37 of a circle and compared with the
/// analytic circle p(t) = (v/Ω)(sin Ωt, 1 − cos Ωt, 0) + (0, 0, −climb t). (Not a whole
/// circle: an error fixed in the body frame would cancel over one.)
void expect_follows_the_circle(const Quat& q_tilt, double climb_mps, double tolerance_m) {
  const double v = 0.5;
  const double omega = 0.25;
  const int steps = 1000;
  const double T = 0.37 * 2.0 * std::numbers::pi / omega;  // 9.3 s
  const double dt = T / steps;
  NavState x;
  x.q_nb = q_tilt;
  x.v_n = Vec3(v, 0.0, -climb_mps);
  const Vec3 a0_n(0.0, v * omega, 0.0);                   // centripetal at yaw 0, to the right
  const Vec3 omega_b = q_tilt.conjugate() * Vec3(0.0, 0.0, omega);  // q(t) = Rz(Ωt) q_tilt
  const Vec3 f_b = q_tilt.conjugate() * (a0_n - kGn);     // constant in the body frame
  for (int i = 0; i < steps; ++i) {
    x = strapdown_step(x, omega_b, f_b, dt, kGn);
  }
  const double psi = omega * T;
  const Vec3 p_known =
      Vec3(v / omega * std::sin(psi), v / omega * (1.0 - std::cos(psi)), -climb_mps * T);
  const Vec3 v_known(v * std::cos(psi), v * std::sin(psi), -climb_mps);
  EXPECT_LT((x.p_n - p_known).norm(), tolerance_m);
  EXPECT_LT((x.v_n - v_known).norm(), tolerance_m);
  EXPECT_LT(x.q_nb.angularDistance(Quat(Eigen::AngleAxisd(psi, Vec3::UnitZ())) * q_tilt), 1e-12);
}

TEST(P1Strapdown, ConstantRateTurnsFollowTheKnownCircle) {
  // S2..S4 are exact for constant ω and f: only round-off is left (1000 steps).
  expect_follows_the_circle(Quat::Identity(), 0.0, 1e-10);
  expect_follows_the_circle(quat_from_euler({0.35, 0.17, 0.0}), 0.0, 1e-10);
  expect_follows_the_circle(quat_from_euler({-0.5, 0.3, 0.8}), 0.1, 1e-10);
}

TEST(P1Strapdown, FirstOrderIntegrationWouldNotClose) {
  // The reason for S3/S4: a whole circle integrated to first order (f rotated by the start
  // attitude of each step) misses the start by far more than the closed form's round-off.

  const double v = 0.5, omega = 0.25;
  const int steps = 2500;
  const double dt = 2.0 * std::numbers::pi / omega / steps;
  Vec3 p = Vec3::Zero(), vel(v, 0.0, 0.0);
  Quat q = Quat::Identity();
  const Vec3 f_b(0.0, v * omega, -kG0);
  for (int i = 0; i < steps; ++i) {
    const Vec3 a = q * f_b + kGn;
    p += vel * dt + 0.5 * a * dt * dt;
    vel += a * dt;
    q = q * quat_exp(Vec3(0.0, 0.0, omega * dt));
  }
  EXPECT_GT(p.norm(), 1e-4);
}

}  // namespace
}  // namespace nav::estimator

// SPDX-License-Identifier: MIT
// The P1 error models (p1_error_model.hpp E1..E11, p1_attitude_ekf.hpp A2, A5, A6) against
// central finite differences of the non-linear models written here independently: the
// true-minus-nominal error dynamics (F), one strapdown step of the true and the nominal state
// (Φ), the magnetometer and gravity residuals of a true attitude and bias (H_mag, H_grav),
// the reset (G_r). Random states from fixed seeds. Also P1Params::validate.
#include "nav/estimator/p1_error_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "nav/common/units.hpp"
#include "nav/estimator/p1_attitude_ekf.hpp"
#include "nav/estimator/strapdown.hpp"
#include "p1_test_support.hpp"
#include "test_support.hpp"

namespace nav::estimator {
namespace {

using EM = P1ErrorModel;
using Vec15 = EM::VecN;
using Mat15 = EM::MatN;
using testing::Normal;
using testing::quat_log;
constexpr double kG0 = units::kStandardGravity;
const Vec3 kGn(0.0, 0.0, kG0);

/// Exp of SO(3) by Eigen's AngleAxis (independent of the library's quat_exp).
Mat3 so3_exp(const Vec3& phi) {
  const double a = phi.norm();
  return a < 1e-300 ? Mat3::Identity() : Mat3(Eigen::AngleAxisd(a, phi / a).toRotationMatrix());
}
Quat quat_exp_ref(const Vec3& phi) { return Quat(so3_exp(phi)); }

/// A random nominal: attitude, biases, raw IMU reading.
struct Point {
  NavState x;
  Vec3 b_a, b_g, omega_m, f_m;
};

Point random_point(Normal& n) {
  Point pt;
  pt.x.p_n = 10.0 * n.vec3();
  pt.x.v_n = n.vec3();
  pt.x.q_nb = quat_exp_ref(2.0 * n.vec3());
  pt.b_a = 0.05 * n.vec3();
  pt.b_g = 0.01 * n.vec3();
  pt.omega_m = 0.5 * n.vec3();
  pt.f_m = pt.x.q_nb.conjugate() * (-kGn) + n.vec3();  // gravity plus a manoeuvre
  return pt;
}

/// δẋ of the true state x̂ ⊕ δx minus the nominal, exactly (no linearisation): the model E1
/// linearises. ρ̇ from d/dt Exp(ρ) = [J(ρ) ρ̇]× Exp(ρ) and Ṙ_err R_errᵀ = [R (ω − ω̂)]×.
Vec15 error_rate(const Point& pt, const Vec15& dx) {
  const Vec3 rho = dx.segment<3>(EM::kRho.idx);
  const Mat3 R_hat = pt.x.q_nb.toRotationMatrix();
  const Mat3 R = so3_exp(rho) * R_hat;
  const Vec3 b_a = pt.b_a + dx.segment<3>(EM::kDba.idx);
  const Vec3 b_g = pt.b_g + dx.segment<3>(EM::kDbg.idx);
  Vec15 r = Vec15::Zero();
  r.segment<3>(EM::kDp.idx) = dx.segment<3>(EM::kDv.idx);
  r.segment<3>(EM::kDv.idx) = R * (pt.f_m - b_a) - R_hat * (pt.f_m - pt.b_a);
  const Vec3 w_err = R * ((pt.omega_m - b_g) - (pt.omega_m - pt.b_g));
  r.segment<3>(EM::kRho.idx) = so3_left_jacobian(rho).partialPivLu().solve(w_err);
  return r;  // biases: random walks, zero mean rate
}

/// δx after one strapdown step of the true state x̂ ⊕ δx and of the nominal.
Vec15 step_error(const Point& pt, double dt, const Vec15& dx) {
  const NavState nominal =
      strapdown_step(pt.x, pt.omega_m - pt.b_g, pt.f_m - pt.b_a, dt, kGn);
  NavState truth = pt.x;
  truth.p_n += dx.segment<3>(EM::kDp.idx);
  truth.v_n += dx.segment<3>(EM::kDv.idx);
  truth.q_nb = quat_exp_ref(dx.segment<3>(EM::kRho.idx)) * pt.x.q_nb;
  const Vec3 b_a = pt.b_a + dx.segment<3>(EM::kDba.idx);
  const Vec3 b_g = pt.b_g + dx.segment<3>(EM::kDbg.idx);
  truth = strapdown_step(truth, pt.omega_m - b_g, pt.f_m - b_a, dt, kGn);
  Vec15 out = dx;
  out.segment<3>(EM::kDp.idx) = truth.p_n - nominal.p_n;
  out.segment<3>(EM::kDv.idx) = truth.v_n - nominal.v_n;
  out.segment<3>(EM::kRho.idx) = quat_log(truth.q_nb * nominal.q_nb.conjugate());
  return out;
}

/// Central-difference Jacobian of fn at δx = 0 (step h).
template <int M, int N, typename Fn>
Mat<M, N> numeric_jacobian(Fn fn, double h) {
  Mat<M, N> J;
  for (int j = 0; j < N; ++j) {
    Vec<N> e = Vec<N>::Zero();
    e(j) = h;
    J.col(j) = (fn(e) - fn(-e)) / (2.0 * h);
  }
  return J;
}

TEST(P1ErrorModel, SystemMatrixMatchesFiniteDifferencesOfTheErrorDynamics) {
  Normal n(101);
  for (int k = 0; k < 10; ++k) {
    const Point pt = random_point(n);
    const Mat15 F =
        EM::system_matrix(pt.x.q_nb.toRotationMatrix(), pt.f_m - pt.b_a);   // (E2)
    const Mat15 F_num =
        numeric_jacobian<15, 15>([&](const Vec15& dx) { return error_rate(pt, dx); }, 1e-6);
    EXPECT_LT((F - F_num).cwiseAbs().maxCoeff(), 1e-8) << "state " << k;
  }
}

TEST(P1ErrorModel, TransitionIsExactForAFrozenNominal) {
  // ω̂ = 0: R̂ and f̂ stay constant over the step, so exp(F dt) is the exact Jacobian of the
  // step, even over a long dt where F² dt²/2 (ρ → δp) and F³ dt³/6 (δb_g → δp) matter.
  Normal n(202);
  for (int k = 0; k < 10; ++k) {
    Point pt = random_point(n);
    pt.omega_m = pt.b_g;
    const double dt = 0.5;
    const Mat15 Phi =
        EM::transition(EM::system_matrix(pt.x.q_nb.toRotationMatrix(), pt.f_m - pt.b_a), dt);
    const Mat15 Phi_num = numeric_jacobian<15, 15>(
        [&](const Vec15& dx) { return step_error(pt, dt, dx); }, 1e-6);
    EXPECT_LT((Phi - Phi_num).cwiseAbs().maxCoeff(), 1e-7) << "state " << k;
    // A first-order I + F dt would miss the higher terms by far more.
    const Mat15 first_order =
        Mat15::Identity() + EM::system_matrix(pt.x.q_nb.toRotationMatrix(), pt.f_m - pt.b_a) * dt;
    EXPECT_GT((first_order - Phi_num).cwiseAbs().maxCoeff(), 1e-2) << "state " << k;
  }
}

TEST(P1ErrorModel, TransitionMatchesAStrapdownStepWhileTurning) {
  // ω̂ ≠ 0: F is frozen at the step's start, so Φ is off by O(|ω̂| dt · |f̂| dt) in the ρ → δv
  // block and O(|ω̂| dt²) in ρ ← δb_g: below 3 |ω̂| |f̂| dt² + 1e-8 at an IMU step of 10 ms.
  Normal n(303);
  for (int k = 0; k < 10; ++k) {
    const Point pt = random_point(n);
    const double dt = 0.01;
    const Mat15 Phi =
        EM::transition(EM::system_matrix(pt.x.q_nb.toRotationMatrix(), pt.f_m - pt.b_a), dt);
    const Mat15 Phi_num = numeric_jacobian<15, 15>(
        [&](const Vec15& dx) { return step_error(pt, dt, dx); }, 1e-6);
    const double bound =
        3.0 * (pt.omega_m - pt.b_g).norm() * (pt.f_m - pt.b_a).norm() * dt * dt + 1e-8;
    EXPECT_LT((Phi - Phi_num).cwiseAbs().maxCoeff(), bound) << "state " << k;
  }
}

TEST(P1ErrorModel, ProcessNoiseMatchesTheVanLoanIntegral) {
  // Q = ½ (Φ Q_c Φᵀ + Q_c) dt (E4) against ∫₀^dt Φ(τ) Q_c Φ(τ)ᵀ dτ by Simpson (200 panels):
  // the trapezoid's error is O(dt³ |F|²) relative, below 1 % at dt = 0.1 s.
  Normal n(808);
  const P1Params p;
  const Mat15 Q_c = EM::continuous_noise(p);
  EXPECT_DOUBLE_EQ(Q_c(EM::kDv.idx, EM::kDv.idx),
                   p.accel_noise_mps2_rthz * p.accel_noise_mps2_rthz);
  EXPECT_DOUBLE_EQ(Q_c(EM::kRho.idx + 2, EM::kRho.idx + 2),
                   p.gyro_noise_radps_rthz * p.gyro_noise_radps_rthz);
  for (int k = 0; k < 5; ++k) {
    const Point pt = random_point(n);
    const Mat15 F = EM::system_matrix(pt.x.q_nb.toRotationMatrix(), pt.f_m - pt.b_a);
    const double dt = 0.1;
    const int panels = 200;
    Mat15 Q_exact = Mat15::Zero();
    for (int i = 0; i <= panels; ++i) {
      const double tau = dt * i / panels;
      const double w = (i == 0 || i == panels) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0);
      const Mat15 Phi_tau = EM::transition(F, tau);
      Q_exact += w * Phi_tau * Q_c * Phi_tau.transpose();
    }
    Q_exact *= dt / (3.0 * panels);
    const Mat15 Q = EM::process_noise(EM::transition(F, dt), Q_c, dt);
    EXPECT_LT((Q - Q_exact).norm(), 0.01 * Q_exact.norm()) << "state " << k;
    EXPECT_TRUE((Q - Q.transpose()).isZero(0.0));
  }
}

TEST(P1ErrorModel, MagnetometerJacobianMatchesFiniteDifferences) {
  Normal n(404);
  const Vec3 m_n(2.2e-5, -1.5e-6, 4.1e-5);
  for (int k = 0; k < 10; ++k) {
    const Quat q_hat = quat_exp_ref(2.0 * n.vec3());
    const Mat3 R_hat = q_hat.toRotationMatrix();
    // m̃_b of the true attitude Exp(ρ) R̂ (noise-free), residual of E6 at the estimate.
    auto z = [&](const Vec15& dx) {
      const Mat3 R_true = so3_exp(dx.segment<3>(EM::kRho.idx)) * R_hat;
      return Vec3(EM::mag_residual(R_hat, R_true.transpose() * m_n, m_n));
    };
    const Mat<3, 15> H_num = numeric_jacobian<3, 15>(z, 1e-6);
    const Mat<3, 15> H = EM::mag_jacobian(m_n);                               // (E7)
    EXPECT_LT((H - H_num).cwiseAbs().maxCoeff(), 1e-13) << "state " << k;
    EXPECT_LT(z(Vec15::Zero()).norm(), 1e-18);  // zero residual at the truth (|mⁿ| = 5e-5 T)
    // The attitude EKF's layout (A5) carries the same block.
    const Mat3 H_att = P1AttitudeEkf::mag_jacobian(m_n).block<3, 3>(0, P1AttitudeEkf::kRho.idx);
    EXPECT_EQ(H_att, Mat3(H.block<3, 3>(0, EM::kRho.idx)));
  }
  // It observes nothing about a rotation about mⁿ itself.
  EXPECT_LT((EM::mag_jacobian_rho(m_n) * m_n).norm(), 1e-25);
}

TEST(P1ErrorModel, GravityJacobianMatchesFiniteDifferences) {
  // δgⁿ of a true attitude Exp(ρ) R̂ and accel bias b̂_a + δb_a, the accelerometer reading the
  // true specific force of an acceleration a_n which is also the motion acceleration given.
  using AEkf = P1AttitudeEkf;
  Normal n(505);
  for (int k = 0; k < 10; ++k) {
    const Quat q_hat = quat_exp_ref(2.0 * n.vec3());
    const Mat3 R_hat = q_hat.toRotationMatrix();
    const Vec3 b_a_hat = 0.05 * n.vec3();
    const Vec3 a_n = n.vec3();
    auto z = [&](const AEkf::VecN& dx) {
      const Mat3 R_true = so3_exp(dx.segment<3>(AEkf::kRho.idx)) * R_hat;
      const Vec3 f_m = R_true.transpose() * (a_n - kGn) + b_a_hat + dx.segment<3>(AEkf::kDba.idx);
      return Vec3(EM::gravity_residual(R_hat, f_m - b_a_hat, a_n, kGn));      // (E8)
    };
    const Mat<3, 9> H_num = numeric_jacobian<3, 9>(z, 1e-6);
    const Vec3 f_hat = R_hat.transpose() * (a_n - kGn);  // f̂ at δx = 0
    const Mat<3, 9> H = AEkf::gravity_jacobian(R_hat, f_hat);                 // (A6, E9)
    EXPECT_LT((H - H_num).cwiseAbs().maxCoeff(), 1e-8) << "state " << k;
    EXPECT_LT(z(AEkf::VecN::Zero()).norm(), 1e-12);
  }
  // At rest and level, J_ρ ρ = g (−ε_E, ε_N, 0): tilt only, no heading.
  const Mat3 J = EM::accel_error_jacobian_rho(Mat3::Identity(), -kGn);
  EXPECT_LT((J * Vec3(0.01, 0.02, 0.3) - kG0 * Vec3(-0.02, 0.01, 0.0)).norm(), 1e-12);
}

TEST(P1ErrorModel, GpsJacobianSelectsThePositionError) {
  Vec15 dx;
  for (int i = 0; i < 15; ++i) dx(i) = i + 1.0;
  EXPECT_EQ(EM::gps_jacobian() * dx, Vec3(1.0, 2.0, 3.0));
}

TEST(P1ErrorModel, ResetJacobianMatchesFiniteDifferences) {
  // ρ' = Log(Exp(ρ) Exp(−ρ̂)) after injecting ρ̂; G_r = I + ½[ρ̂]× is its first-order
  // Jacobian at ρ = ρ̂ (error O(|ρ̂|²) ≈ 3e-5 here), the local-error form I − ½[ρ̂]× is not.
  Normal n(606);
  for (int k = 0; k < 10; ++k) {
    const Vec3 rho_hat = 0.02 * n.vec3().normalized();
    auto after = [&](const Vec3& d) {
      return quat_log(quat_exp_ref(rho_hat + d) * quat_exp_ref(-rho_hat));
    };
    const Mat3 G_num = numeric_jacobian<3, 3>(after, 1e-6);
    EXPECT_LT((EM::reset_jacobian_rho(rho_hat) - G_num).cwiseAbs().maxCoeff(), 1e-4);
    EXPECT_GT(((Mat3::Identity() - 0.5 * skew(rho_hat)) - G_num).cwiseAbs().maxCoeff(), 1e-2);
  }
  // Injection is a rotation of the navigation frame: Exp(ρ) ⊗ q.
  const Quat q = quat_exp_ref(Vec3(0.3, -0.2, 1.0));
  const Vec3 rho(0.01, -0.02, 0.03);
  EXPECT_LT(EM::inject_attitude(q, rho).angularDistance(quat_exp_ref(rho) * q), 1e-15);
}

TEST(P1ErrorModel, AttitudeEkfTransitionMatchesFiniteDifferences) {
  using AEkf = P1AttitudeEkf;
  Normal n(707);
  for (int k = 0; k < 10; ++k) {
    const Quat q_hat = quat_exp_ref(2.0 * n.vec3());
    const Vec3 omega_hat = (k < 5 ? 0.0 : 0.5) * n.vec3();  // frozen (exact) and turning
    const double dt = k < 5 ? 0.5 : 0.01;
    auto step = [&](const AEkf::VecN& dx) {
      const Quat nominal = q_hat * quat_exp_ref(omega_hat * dt);
      const Quat truth = quat_exp_ref(dx.segment<3>(AEkf::kRho.idx)) * q_hat *
                         quat_exp_ref((omega_hat - dx.segment<3>(AEkf::kDbg.idx)) * dt);
      AEkf::VecN out = dx;
      out.segment<3>(AEkf::kRho.idx) = quat_log(truth * nominal.conjugate());
      return out;
    };
    const Mat<9, 9> Phi_num = numeric_jacobian<9, 9>(step, 1e-6);
    const Mat<9, 9> Phi = AEkf::transition(q_hat.toRotationMatrix(), dt);    // (A2)
    const double bound = k < 5 ? 1e-8 : omega_hat.norm() * dt * dt + 1e-9;
    EXPECT_LT((Phi - Phi_num).cwiseAbs().maxCoeff(), bound) << "state " << k;
  }
}

TEST(P1Params, DefaultsAreValidAndBadFieldsAreNamed) {
  EXPECT_TRUE(validate(P1Params{}).has_value());
  P1Params p;
  p.gps_position_std_m = 0.0;
  auto r = validate(p);
  ASSERT_FALSE(r.has_value());
  EXPECT_NE(r.error().detail.find("gps_position_std_m"), std::string::npos);
  p = P1Params{};
  p.initial_q_nb = Quat(2.0, 0.0, 0.0, 0.0);
  r = validate(p);
  ASSERT_FALSE(r.has_value());
  EXPECT_NE(r.error().detail.find("initial_q_nb"), std::string::npos);
  p = P1Params{};
  p.gyro_noise_radps_rthz = std::nan("");
  r = validate(p);
  ASSERT_FALSE(r.has_value());
  EXPECT_NE(r.error().detail.find("gyro_noise_radps_rthz"), std::string::npos);
  p = P1Params{};
  p.mag_field_n_tesla = Vec3(20.0, 0.0, 40.0);  // µT by mistake
  EXPECT_FALSE(validate(p).has_value());
  p = P1Params{};
  p.resample_ess_fraction = 1.5;
  EXPECT_FALSE(validate(p).has_value());
  p = P1Params{};
  p.particle_count = 0;
  r = validate(p);
  ASSERT_FALSE(r.has_value());
  EXPECT_NE(r.error().detail.find("particle_count"), std::string::npos);
  p.particle_count = P1Params::kMaxParticles + 1;  // 0.4 GB and more: refused, not allocated
  r = validate(p);
  ASSERT_FALSE(r.has_value());
  EXPECT_NE(r.error().detail.find("particle_count must be in [1, 100000]"), std::string::npos);
  p.particle_count = P1Params::kMaxParticles;
  EXPECT_TRUE(validate(p).has_value());
}

}  // namespace
}  // namespace nav::estimator

// SPDX-License-Identifier: MIT
// Navigator "upf15" (p1_upf15.hpp) on paper P1's stadium (p1_test_support.hpp) at 0.5 m/s with
// seeded sensor errors (biases drawn from the prior, white noise, 1 Hz GPS, 100 Hz
// magnetometer), as p1_ekf15_test.cpp runs ekf15: it converges, agrees with ekf15 with many
// particles, is bit-identical for one seed, refuses NaN/Inf, rides out a 30 s GPS outage, runs
// with 10 particles, and runs on the UPF's shared-covariance path with a positive-definite Q.
// Every random number comes from a fixed seed; nothing depends on time.
#include "nav/estimator/p1_upf15.hpp"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <limits>
#include <vector>

#include "nav/common/units.hpp"
#include "nav/estimator/complementary_attitude.hpp"
#include "nav/estimator/p1_ekf15.hpp"
#include "p1_test_support.hpp"

namespace nav::estimator {
namespace {

using EM = P1ErrorModel;
using testing::attitude_error_n;
using testing::Errors;
using testing::Normal;
using testing::run_stadium;
using testing::SensorErrors;
using testing::Stadium;
using testing::StadiumRun;
using testing::Truth;

constexpr double kDt = StadiumRun::kDt;
constexpr double kSpeed = StadiumRun::kSpeed;

P1Params params_with(int particles, std::uint64_t filter_seed = 1) {
  P1Params p;
  p.particle_count = particles;
  p.seed = filter_seed;
  return p;
}


/// Symmetric and positive semi-definite to round-off (a spread of n ≤ 15 points is singular).
bool symmetric_psd(const EM::MatN& P) {
  if (!P.allFinite() || !(P - P.transpose()).isZero(0.0)) return false;
  const Eigen::SelfAdjointEigenSolver<EM::MatN> eig(P);
  return eig.eigenvalues().minCoeff() >= -1e-12 * eig.eigenvalues().cwiseAbs().maxCoeff();
}


TEST(P1Upf15, ProcessNoiseIsPositiveDefiniteAndTheSharedPathIsUsed) {
  // E4's Q has a δp block (½ σ_a² dt³) and is PD with every density positive; a zero bias
  // walk is floored (p1_upf15.hpp).
  P1Params p = params_with(10);
  p.accel_bias_walk_mps3_rthz = 0.0;
  p.gyro_bias_walk_radps2_rthz = 0.0;
  const Mat3 R_nb = dcm_from_quat(quat_exp(Vec3(0.1, -0.2, 2.0)));
  for (const double dt : {1e-3, 0.01, 0.1}) {
    const EM::MatN Phi = EM::transition(EM::system_matrix(R_nb, Vec3(0.3, -0.1, -9.8)), dt);
    const EM::MatN Q = EM::process_noise(Phi, P1Upf15::continuous_noise(p), dt);
    EXPECT_EQ(Eigen::LLT<EM::MatN>(Q).info(), Eigen::Success) << dt;
    const double sa2 = p.accel_noise_mps2_rthz * p.accel_noise_mps2_rthz;
    EXPECT_GE(Q(0, 0), 0.5 * sa2 * dt * dt * dt) << dt;  // ½ σ_a² dt³ + the ρ, δb terms
    EXPECT_LT(Q(0, 0), 2.0 * sa2 * dt * dt * dt) << dt;
  }
  static_assert(UpfSharedCovarianceProcess<P1UpfErrorProcess, 15>);
  static_assert(UpfLinearMeasurement<P1UpfGpsMeasurement, 15>);
  static_assert(UpfLinearMeasurement<P1UpfMagMeasurement, 15>);
  StadiumRun run(3, p);
  P1Upf15 upf(run.params());
  EXPECT_FALSE(upf.filter().shares_covariance());  // before the first predict
  bool shared = true;
  while (run.time() < 3.0) {
    run.step(upf);
    shared = shared && upf.filter().shares_covariance();
  }
  EXPECT_TRUE(shared);
  EXPECT_EQ(upf.stats().numerical_faults, 0u);
  EXPECT_EQ(upf.stats().mag_fused, 300u);
  EXPECT_EQ(upf.stats().gps_fused, 3u);
}

TEST(P1Upf15, ConvergesOnTheStadium) {
  StadiumRun run(7, params_with(50));
  P1Upf15 upf(run.params());
  const double two_laps = 2.0 * Stadium(kSpeed).lap_time_s();
  const Errors e = run_stadium(run, upf, two_laps);
  const double sigma_gps = run.params().gps_position_std_m;
  EXPECT_LT(e.rms_per_axis, sigma_gps);  // filters the fixes (ekf15: 0.7 σ; see below)
  EXPECT_LT(e.worst_p, 3.0 * sigma_gps);
  EXPECT_LT(e.worst_att, 0.5 * units::kDegToRad);
  EXPECT_TRUE(symmetric_psd(upf.covariance()));
  EXPECT_EQ(upf.stats().gps_fused, static_cast<std::uint64_t>(two_laps));
  EXPECT_EQ(upf.stats().mag_fused, upf.stats().imu_samples);
  EXPECT_EQ(upf.stats().numerical_faults, 0u);
}

TEST(P1Upf15, StaysNearEkf15OnTheSameData) {
  // 250 particles against ekf15 on the same data. upf15 weighs by the GPS likelihood of each
  // particle's draw (upf.hpp L5), which counts a fix twice, so it does not tend to the Kalman
  // filter: its position follows the fixes more closely and is noisier than ekf15's. Bounds:
  // both well below the GPS noise (they filter), upf15's within twice ekf15's, and the
  // attitudes within half a degree of each other (both are held by the same magnetometer).
  StadiumRun run(9, params_with(250));
  P1Upf15 upf(run.params());
  P1Ekf15 ekf(run.params());
  double sq_upf = 0.0, sq_ekf = 0.0, worst_datt = 0.0;
  int n = 0;
  while (run.time() < 60.0) {
    run.step({&upf, &ekf});
    if (run.time() < 30.0) continue;
    const P1Solution a = upf.solution();
    const P1Solution b = ekf.solution();
    sq_upf += (run.truth().p_n - a.p_n).squaredNorm();
    sq_ekf += (run.truth().p_n - b.p_n).squaredNorm();
    ++n;
    worst_datt = std::max(worst_datt, attitude_error_n(a.q_nb, b.q_nb).norm());
  }
  const double rms_upf = std::sqrt(sq_upf / (3.0 * n));
  const double rms_ekf = std::sqrt(sq_ekf / (3.0 * n));
  RecordProperty("rms_upf_m", std::to_string(rms_upf));
  RecordProperty("rms_ekf_m", std::to_string(rms_ekf));
  std::printf("rms per axis: upf15 %.4f m, ekf15 %.4f m; worst attitude difference %.3f deg\n",
              rms_upf, rms_ekf, worst_datt / units::kDegToRad);
  const double sigma_gps = run.params().gps_position_std_m;
  EXPECT_LT(rms_ekf, 0.7 * sigma_gps);
  EXPECT_LT(rms_upf, sigma_gps);
  EXPECT_LT(rms_upf, 2.0 * rms_ekf);
  EXPECT_LT(worst_datt, 0.5 * units::kDegToRad);
}

TEST(P1Upf15, RidesOutAGpsOutage) {
  StadiumRun run(21, params_with(50));
  P1Upf15 upf(run.params());
  double before = 0.0, after = 0.0;
  while (run.time() < 100.0) {
    const bool outage = run.time() >= 40.0 && run.time() < 70.0;
    run.step(upf, !outage);
    const double e = (run.truth().p_n - upf.nominal().p_n).norm();
    if (run.time() >= 25.0 && run.time() < 40.0) before = std::max(before, e);
    if (run.time() >= 80.0) after = std::max(after, e);
  }
  EXPECT_EQ(upf.stats().imu_samples, 10000u);
  EXPECT_LT(before, 3.0 * run.params().gps_position_std_m);
  EXPECT_LT(after, 3.0 * run.params().gps_position_std_m);  // recovered within 10 s
  EXPECT_TRUE(symmetric_psd(upf.covariance()));
}

/// Everything a refused input must leave as it was (the generator is checked by the next
/// step matching a twin's).
struct Snapshot {
  NavState x;
  Vec3 b_a, b_g;
  std::vector<EM::VecN> particles;
  std::vector<double> log_w;
  explicit Snapshot(const P1Upf15& f) : x(f.nominal()), b_a(f.accel_bias_b()), b_g(f.gyro_bias_b()) {
    for (int i = 0; i < f.filter().particle_count(); ++i) {
      particles.push_back(f.filter().particle_state(i));
    }
    log_w.assign(f.filter().log_weights().begin(), f.filter().log_weights().end());
  }
  bool operator==(const Snapshot& o) const {
    return x.p_n == o.x.p_n && x.v_n == o.x.v_n && x.q_nb.coeffs() == o.x.q_nb.coeffs() &&
           b_a == o.b_a && b_g == o.b_g && particles == o.particles && log_w == o.log_w;
  }
};

TEST(P1Upf15, SameSeedIsBitIdenticalDifferentSeedIsNot) {
  const auto final_state = [](std::uint64_t filter_seed) {
    StadiumRun run(5, params_with(50, filter_seed));
    P1Upf15 upf(run.params());
    while (run.time() < 3.0) run.step(upf);
    return Snapshot(upf);
  };
  const Snapshot a = final_state(1);
  EXPECT_TRUE(a == final_state(1));
  const Snapshot b = final_state(2);
  EXPECT_FALSE(a == b);
  EXPECT_NE(a.x.p_n, b.x.p_n);  // the estimate itself differs, not only the particles
}

TEST(P1Upf15, RefusesNanAndInfAndCountsThem) {
  StadiumRun run(31, params_with(50));
  StadiumRun twin_run(31, params_with(50));
  P1Upf15 upf(run.params());
  P1Upf15 twin(twin_run.params());
  while (run.time() < 2.0) {
    run.step(upf);
    twin_run.step(twin);
  }
  const Snapshot before(upf);
  const P1Stats stats = upf.stats();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  ImuSample good;
  good.dt_s = kDt;
  good.f_b_mps2 = Vec3(0.0, 0.0, -9.8);
  good.m_b_tesla = Vec3(2e-5, 0.0, 4e-5);
  std::vector<ImuSample> bad(6, good);
  bad[0].omega_b_radps.x() = nan;
  bad[1].f_b_mps2.y() = inf;
  bad[2].m_b_tesla.z() = -inf;
  bad[3].dt_s = nan;
  bad[4].dt_s = 0.0;
  bad[5].dt_s = inf;
  for (const ImuSample& s : bad) {
    upf.on_imu(s);
    EXPECT_TRUE(upf.innovations().empty());
  }
  for (const Vec3& fix : {Vec3(nan, 0.0, 0.0), Vec3(0.0, inf, 0.0), Vec3(0.0, 0.0, -inf)}) {
    upf.on_gps_position(fix);
    EXPECT_TRUE(upf.innovations().empty());
    EXPECT_EQ(upf.last_gps_status(), UpdateStatus::kRejectedInvalid);
  }
  EXPECT_TRUE(Snapshot(upf) == before);
  EXPECT_EQ(upf.stats().imu_samples, stats.imu_samples + 6);
  EXPECT_EQ(upf.stats().imu_rejected_invalid, stats.imu_rejected_invalid + 6);
  EXPECT_EQ(upf.stats().gps_rejected_invalid, stats.gps_rejected_invalid + 3);
  // The generator was not touched either: the next steps match the twin's bit for bit.
  while (run.time() < 3.0) {
    run.step(upf);
    twin_run.step(twin);
  }
  EXPECT_TRUE(Snapshot(upf) == Snapshot(twin));
}

TEST(P1Upf15, TenParticlesRunAndReportInnovations) {
  StadiumRun run(11, params_with(10));
  P1Upf15 upf(run.params());
  while (run.time() < 20.005) {
    run.step(upf);
    ASSERT_TRUE(upf.solution().p_n.allFinite());
  }
  EXPECT_EQ(upf.filter().particle_count(), 10);
  EXPECT_EQ(upf.stats().numerical_faults, 0u);
  EXPECT_EQ(upf.stats().gps_fused, 20u);
  EXPECT_EQ(upf.stats().mag_fused, upf.stats().imu_samples);
  EXPECT_TRUE(symmetric_psd(upf.covariance()));
  ASSERT_EQ(upf.innovations().size(), 1u);  // the last sample: magnetometer only
  EXPECT_STREQ(upf.innovations()[0].source, "mag");
  upf.on_gps_position(run.truth().p_n);
  ASSERT_EQ(upf.innovations().size(), 1u);
  EXPECT_STREQ(upf.innovations()[0].source, "gps-position");
  EXPECT_EQ(upf.innovations()[0].dof, 3);
  const P1Solution s = upf.solution();
  EXPECT_EQ(s.P_attitude_n, Mat3(upf.covariance().block<3, 3>(EM::kRho.idx, EM::kRho.idx)));
}

}  // namespace
}  // namespace nav::estimator

// SPDX-License-Identifier: MIT
// Deterministic triad distortions (scale factor, misalignment, saturation, quantization) and
// the magnetometer's hard/soft iron, on top of TriadErrorModel (error_model.cpp, Eq. (E1)-(E3)).
// Expected values are written out by hand from the equations, not computed by the model.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "nav/common/ensure.hpp"
#include "nav/emulators/device.hpp"

namespace nav::emulators {
namespace {

constexpr double kTight = 1e-15;  ///< double-rounding tolerance for O(1) values [-]

/// Random terms used where a test needs them: noise, bias and walk all active.
TriadErrors noisy() { return TriadErrors{0.05, 0.1, 0.02}; }

/// The bits of a double, to compare outputs bit for bit (EXPECT_EQ treats -0.0 == +0.0).
std::uint64_t bits(double x) {
  std::uint64_t b = 0;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

TEST(TriadSensorErrorModel, WithDefaultsIsBitIdenticalToTriadErrorModel) {
  TriadSensorErrors e;
  e.random = noisy();
  TriadSensorErrorModel ext(e);
  TriadErrorModel base(e.random);
  std::mt19937_64 a(11), b(11);
  const std::vector<Vec3> inputs = {Vec3(1.0, -2.0, 3.0), Vec3(-0.0, 0.0, -0.0),
                                    Vec3(1e300, -1e-300, 0.5)};
  for (int k = 0; k < 30; ++k) {
    const Vec3& x = inputs[static_cast<std::size_t>(k) % inputs.size()];
    const double dt = k == 0 ? 0.0 : 0.01;
    const Vec3 y_ext = ext.apply(x, dt, a);
    const Vec3 y_base = base.apply(x, dt, b);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(bits(y_ext[i]), bits(y_base[i])) << k << " " << i;
  }
  EXPECT_EQ(ext.walk(), base.walk());
  EXPECT_EQ(a(), b());  // same number of raw outputs consumed
}

TEST(TriadSensorErrorModel, WithoutAnyErrorIsExact) {
  TriadSensorErrorModel m{TriadSensorErrors{}};
  std::mt19937_64 rng(1);
  EXPECT_EQ(m.apply(Vec3(0.1, 2.5, -7.0), 0.0, rng), Vec3(0.1, 2.5, -7.0));
  EXPECT_EQ(m.gain(), Mat3::Identity());
}

TEST(TriadSensorErrorModel, AddedTermsNeverChangeTheDraws) {
  // Every added term enabled: the engine advances by exactly six normals (12 raw outputs) per
  // call, as TriadErrorModel does, and the random part equals TriadErrorModel's on K x.
  TriadSensorErrors e;
  e.random = noisy();
  e.scale_factor = Vec3(300.0, -150.0, 80.0) * kPpm;
  e.misalignment_rad = Vec3(1e-3, -2e-3, 0.5e-3);
  TriadSensorErrorModel ext(e);
  TriadErrorModel base(e.random);
  std::mt19937_64 a(77), b(77), c(77);
  const Vec3 x(0.3, -9.81, 1.2);
  for (int k = 0; k < 20; ++k) {
    const double dt = k == 0 ? 0.0 : 0.1;
    const Vec3 y = ext.apply(x, dt, a);
    const Vec3 y_ref = base.apply(ext.gain() * x, dt, b);
    EXPECT_EQ(y, y_ref) << k;
  }
  c.discard(20 * 12);
  EXPECT_EQ(a(), c());

  // Saturation and quantization draw nothing either.
  e.saturation = 2.0;
  e.quantum = 0.01;
  TriadSensorErrorModel clipped(e);
  std::mt19937_64 d(77), f(77);
  for (int k = 0; k < 20; ++k) (void)clipped.apply(x, 0.1, d);
  f.discard(20 * 12);
  EXPECT_EQ(d(), f());
}

TEST(TriadSensorErrorModel, ScaleFactorInPpmMultipliesEachAxis) {
  TriadSensorErrors e;
  e.scale_factor = Vec3(250.0, -1000.0, 0.0) * kPpm;  // +250 ppm, -0.1 %, none
  TriadSensorErrorModel m(e);
  std::mt19937_64 rng(3);
  const Vec3 y = m.apply(Vec3(2.0, 4.0, -8.0), 0.0, rng);
  EXPECT_NEAR(y.x(), 2.0005, kTight * 4);
  EXPECT_NEAR(y.y(), 3.996, kTight * 8);
  EXPECT_EQ(y.z(), -8.0);
}

TEST(TriadSensorErrorModel, BiasIsNotScaledScaleComesFirst) {
  // Eq. (E1a) before (E1b): y = (1 + s) x + b, not (1 + s)(x + b).
  TriadSensorErrors e;
  e.random = TriadErrors{0.0, 0.5, 0.0};
  e.scale_factor = Vec3::Constant(0.1);  // 10 %
  TriadSensorErrorModel m(e);
  std::mt19937_64 rng(3);
  EXPECT_EQ(m.apply(Vec3::Zero(), 0.0, rng), Vec3::Constant(0.5));
  const Vec3 y = m.apply(Vec3::Constant(1.0), 0.0, rng);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(y[i], 1.1 + 0.5, kTight * 2);
}

TEST(SmallAngleMisalignment, IsIMinusTheCrossProductMatrix) {
  const Mat3 M = small_angle_misalignment(Vec3(0.01, 0.02, 0.03));
  Mat3 expected;
  expected << 1.0, 0.03, -0.02,  //
      -0.03, 1.0, 0.01,          //
      0.02, -0.01, 1.0;
  EXPECT_EQ(M, expected);
  EXPECT_EQ(small_angle_misalignment(Vec3::Zero()), Mat3::Identity());
}

TEST(SmallAngleMisalignment, SensorRotatedAboutZSeesTheVectorRotatedBack) {
  // Sensor axes rotated by +theta about z: the ideal x axis appears at -theta in the sensor's
  // x-y plane, i.e. (cos, -sin, 0) ~ (1, -theta, 0).
  constexpr double kTheta = 2e-3;
  TriadSensorErrors e;
  e.misalignment_rad = Vec3(0.0, 0.0, kTheta);
  TriadSensorErrorModel m(e);
  std::mt19937_64 rng(3);
  const Vec3 y = m.apply(Vec3::UnitX(), 0.0, rng);
  EXPECT_EQ(y, Vec3(1.0, -kTheta, 0.0));
  // First-order rotation: agrees with the exact R_is^T to O(theta^2).
  const Mat3 R_is = Eigen::AngleAxisd(kTheta, Vec3::UnitZ()).toRotationMatrix();
  EXPECT_LE((m.gain() - R_is.transpose()).cwiseAbs().maxCoeff(), kTheta * kTheta);
}

TEST(SmallAngleMisalignment, IsOrthogonalToFirstOrderForAnyAxis) {
  // M^T M = I + [theta]x^T [theta]x: the departure from orthogonality is <= |theta|^2.
  std::mt19937_64 rng(2718);
  for (int k = 0; k < 100; ++k) {
    const Vec3 theta = 5e-3 * Vec3(standard_normal(rng), standard_normal(rng),
                                   standard_normal(rng));
    const Mat3 M = small_angle_misalignment(theta);
    EXPECT_LE((M.transpose() * M - Mat3::Identity()).cwiseAbs().maxCoeff(),
              theta.squaredNorm() + 1e-16);
    // The exact rotation of the same vector: R_is^T differs by O(|theta|^2) too.
    const Mat3 R_is = Eigen::AngleAxisd(theta.norm(), theta.normalized()).toRotationMatrix();
    EXPECT_LE((M - R_is.transpose()).cwiseAbs().maxCoeff(), theta.squaredNorm());
  }
}

TEST(TriadSensorErrorModel, GainIsScaleTimesMisalignment) {
  TriadSensorErrors e;
  e.scale_factor = Vec3(0.01, 0.02, -0.03);
  e.misalignment_rad = Vec3(0.001, 0.002, 0.003);
  TriadSensorErrorModel m(e);
  Mat3 expected;  // row i of M scaled by (1 + s_i)
  expected << 1.01 * 1.0, 1.01 * 0.003, 1.01 * -0.002,  //
      1.02 * -0.003, 1.02 * 1.0, 1.02 * 0.001,           //
      0.97 * 0.002, 0.97 * -0.001, 0.97 * 1.0;
  EXPECT_LE((m.gain() - expected).cwiseAbs().maxCoeff(), kTight);
}

TEST(TriadSensorErrorModel, SaturationClipsAfterNoise) {
  // Range +-1: big inputs clip exactly at the range whatever the noise; small ones pass.
  TriadSensorErrors e;
  e.random = TriadErrors{0.2, 0.0, 0.0};
  e.saturation = 1.0;
  TriadSensorErrorModel m(e);
  std::mt19937_64 rng(5);
  for (int k = 0; k < 1000; ++k) {
    EXPECT_EQ(m.apply(Vec3(50.0, -50.0, 3.0), 0.01, rng), Vec3(1.0, -1.0, 1.0));
  }
  // Noise near the range is clipped too: no sample beyond it, and some at it.
  int at_range = 0;
  for (int k = 0; k < 1000; ++k) {
    const Vec3 y = m.apply(Vec3::Constant(0.9), 0.01, rng);
    EXPECT_LE(y.cwiseAbs().maxCoeff(), 1.0);
    at_range += (y.array() == 1.0).count() > 0 ? 1 : 0;
  }
  // P(0.9 + 0.2 n > 1) = P(n > 0.5) = 0.31 per axis; at least one of three: 0.67.
  EXPECT_GT(at_range, 500);
  EXPECT_LT(at_range, 850);
}

TEST(TriadSensorErrorModel, QuantizationRoundsToTheNearestCode) {
  TriadSensorErrors e;
  e.quantum = 0.25;
  TriadSensorErrorModel m(e);
  std::mt19937_64 rng(5);
  EXPECT_EQ(m.apply(Vec3(0.12, 0.13, -0.13), 0.0, rng), Vec3(0.0, 0.25, -0.25));
  EXPECT_EQ(m.apply(Vec3(0.125, -0.125, 1.0), 0.0, rng), Vec3(0.25, -0.25, 1.0));  // ties away
  EXPECT_EQ(m.apply(Vec3(1e6 + 0.1, -3.3, 7.874), 0.0, rng), Vec3(1e6, -3.25, 7.75));
}

TEST(TriadSensorErrorModel, QuantizationErrorIsUniformWithinHalfAnLsb) {
  // With noise much wider than the LSB q, the quantization error e = y - y~ is uniform on
  // [-q/2, q/2]: mean 0, standard deviation q / sqrt(12). Standard errors: q/sqrt(12 N) for
  // the mean, q/sqrt(180 N) for the standard deviation (Var(e^2) = q^4/180).
  constexpr double kQ = 0.01;
  constexpr int kN = 100'000;
  TriadSensorErrors e;
  e.random = TriadErrors{1.0, 0.0, 0.0};
  e.quantum = kQ;
  TriadSensorErrors e_raw = e;
  e_raw.quantum = 0.0;
  TriadSensorErrorModel quantized(e), raw(e_raw);
  std::mt19937_64 a(99), b(99);  // same draws: raw gives y~ of the same sample
  double sum = 0.0, sum2 = 0.0, max_abs = 0.0;
  for (int k = 0; k < kN; ++k) {
    const double err = quantized.apply(Vec3::Zero(), 0.0, a).x() -
                       raw.apply(Vec3::Zero(), 0.0, b).x();
    sum += err;
    sum2 += err * err;
    max_abs = std::max(max_abs, std::abs(err));
  }
  EXPECT_LE(max_abs, kQ / 2 * (1 + 1e-9));
  EXPECT_NEAR(sum / kN, 0.0, 5.0 * kQ / std::sqrt(12.0 * kN));
  EXPECT_NEAR(std::sqrt(sum2 / kN), kQ / std::sqrt(12.0), 5.0 * kQ / std::sqrt(180.0 * kN));
}

TEST(TriadSensorErrorModel, SaturationThenQuantizationStaysWithinTheRange) {
  // Range not a multiple of the LSB: the output is the largest code inside the range.
  TriadSensorErrors e;
  e.saturation = 1.05;
  e.quantum = 0.1;
  TriadSensorErrorModel m(e);
  std::mt19937_64 rng(5);
  const Vec3 y = m.apply(Vec3(2.0, -2.0, 1.04), 0.0, rng);
  EXPECT_NEAR(y.x(), 1.0, kTight * 2);
  EXPECT_NEAR(y.y(), -1.0, kTight * 2);
  EXPECT_NEAR(y.z(), 1.0, kTight * 2);  // round(10.4) = 10
  // Range an exact multiple whose ratio rounds below the integer (0.3 / 0.1 = 2.999...96):
  // full scale is still the code 3.
  e.saturation = 0.3;
  TriadSensorErrorModel full(e);
  EXPECT_NEAR(full.apply(Vec3::Constant(5.0), 0.0, rng).x(), 0.3, kTight);
  EXPECT_NEAR(full.apply(Vec3::Constant(-5.0), 0.0, rng).x(), -0.3, kTight);
}

TEST(HardSoftIron, IsSoftIronTimesFieldPlusHardIron) {
  HardSoftIron iron;
  iron.hard_iron_T = Vec3(1e-6, -2e-6, 0.5e-6);
  iron.soft_iron << 1.05, 0.02, 0.0,  //
      0.02, 0.97, -0.01,               //
      0.0, -0.01, 1.0;
  const Vec3 b(2.0e-5, 0.0, 4.0e-5);  // GX3 default Earth field, NED [T]
  const Vec3 expected(1.05 * 2.0e-5 + 1e-6,                       //
                      0.02 * 2.0e-5 - 0.01 * 4.0e-5 - 2e-6,       //
                      4.0e-5 + 0.5e-6);
  EXPECT_LE((iron.apply(b) - expected).cwiseAbs().maxCoeff(), 1e-19);
  EXPECT_EQ(HardSoftIron{}.apply(b), b);  // defaults: no disturbance
}

TEST(HardSoftIron, TurnsTheFieldSphereIntoAnOffsetEllipsoid) {
  // A vehicle turning in a constant field: the undisturbed readings lie on a sphere of radius
  // |b|; disturbed, on the ellipsoid W S^2 |b| + h. The calibration inverse W^-1 (y - h)
  // restores the radius, and the centre of the readings is h.
  HardSoftIron iron;
  iron.hard_iron_T = Vec3(3e-6, -1e-6, 2e-6);
  iron.soft_iron << 1.1, 0.05, 0.0,  //
      0.05, 0.9, 0.0,                 //
      0.0, 0.0, 1.0;
  const Vec3 b_n(2.0e-5, 0.0, 4.0e-5);
  Vec3 centre = Vec3::Zero();
  double min_norm = 1.0, max_norm = 0.0;
  constexpr int kHeadings = 360;
  for (int k = 0; k < kHeadings; ++k) {
    const double yaw = 2.0 * std::numbers::pi * k / kHeadings;
    const Vec3 b_b = Eigen::AngleAxisd(yaw, Vec3::UnitZ()).toRotationMatrix().transpose() * b_n;
    const Vec3 y = iron.apply(b_b);
    centre += y / kHeadings;
    const double undone = iron.soft_iron.lu().solve(y - iron.hard_iron_T).norm();
    EXPECT_NEAR(undone, b_n.norm(), 1e-18);
    min_norm = std::min(min_norm, (y - iron.hard_iron_T).norm());
    max_norm = std::max(max_norm, (y - iron.hard_iron_T).norm());
  }
  // The horizontal part averages out over a full turn; the vertical part is W's z row.
  EXPECT_LE((centre - (iron.hard_iron_T + Vec3(0.0, 0.0, b_n.z()))).cwiseAbs().maxCoeff(), 1e-18);
  // Really an ellipsoid, not a sphere: the radius varies by ~5 % over the turn.
  EXPECT_GT(max_norm - min_norm, 0.01 * b_n.norm());
}

TEST(MagnetometerErrorModel, IronActsBeforeTheSensorErrors) {
  HardSoftIron iron;
  iron.hard_iron_T = Vec3(1e-6, 0.0, 0.0);
  iron.soft_iron = Mat3::Identity() * 1.1;
  TriadSensorErrors sensor;
  sensor.random = TriadErrors{0.0, 1e-7, 0.0};  // bias 0.1 uT
  sensor.scale_factor = Vec3::Constant(0.5);
  MagnetometerErrorModel m(iron, sensor);
  std::mt19937_64 rng(8);
  const Vec3 b(2e-5, 0.0, 4e-5);
  // y = 1.5 (1.1 b + h) + bias: the sensor's scale factor also scales the hard iron.
  const Vec3 expected = 1.5 * (1.1 * b + iron.hard_iron_T) + Vec3::Constant(1e-7);
  EXPECT_LE((m.apply(b, 0.0, rng) - expected).cwiseAbs().maxCoeff(), 1e-19);
}

TEST(MagnetometerErrorModel, DrawsExactlyLikeTheSensorModel) {
  HardSoftIron iron;
  iron.hard_iron_T = Vec3(1e-6, 2e-6, -3e-6);
  TriadSensorErrors sensor;
  sensor.random = TriadErrors{2e-7, 1e-7, 1e-8};
  MagnetometerErrorModel mag(iron, sensor);
  TriadSensorErrorModel plain(sensor);
  std::mt19937_64 a(4), b(4);
  const Vec3 field(2e-5, 1e-6, 4e-5);
  for (int k = 0; k < 10; ++k) {
    EXPECT_EQ(mag.apply(field, 0.01, a), plain.apply(iron.apply(field), 0.01, b));
  }
  EXPECT_EQ(a(), b());
}

TEST(TriadSensorErrorModel, InvalidParametersAreContractViolations) {
  struct Violation {};
  const auto previous = set_ensure_handler(
      [](const char*, int, const char*, const std::string&) { throw Violation{}; });
  auto make = [](auto edit) {
    TriadSensorErrors e;
    edit(e);
    return TriadSensorErrorModel(e);
  };
  EXPECT_THROW(make([](TriadSensorErrors& e) { e.saturation = 0.0; }), Violation);
  EXPECT_THROW(make([](TriadSensorErrors& e) { e.saturation = -1.0; }), Violation);
  EXPECT_THROW(make([](TriadSensorErrors& e) {
                 e.saturation = std::numeric_limits<double>::quiet_NaN();
               }),
               Violation);
  EXPECT_THROW(make([](TriadSensorErrors& e) { e.quantum = -0.1; }), Violation);
  EXPECT_THROW(make([](TriadSensorErrors& e) {
                 e.quantum = std::numeric_limits<double>::infinity();
               }),
               Violation);
  EXPECT_THROW(make([](TriadSensorErrors& e) {
                 e.scale_factor.x() = std::numeric_limits<double>::quiet_NaN();
               }),
               Violation);
  EXPECT_THROW(make([](TriadSensorErrors& e) {
                 e.misalignment_rad.z() = std::numeric_limits<double>::infinity();
               }),
               Violation);
  EXPECT_NO_THROW(make([](TriadSensorErrors&) {}));

  HardSoftIron singular;
  singular.soft_iron = Mat3::Zero();
  EXPECT_THROW(MagnetometerErrorModel(singular, TriadSensorErrors{}), Violation);
  HardSoftIron mirrored;
  mirrored.soft_iron = Vec3(1.0, 1.0, -1.0).asDiagonal();
  EXPECT_THROW(MagnetometerErrorModel(mirrored, TriadSensorErrors{}), Violation);
  HardSoftIron nan_offset;
  nan_offset.hard_iron_T.y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(MagnetometerErrorModel(nan_offset, TriadSensorErrors{}), Violation);
  set_ensure_handler(previous);
}

}  // namespace
}  // namespace nav::emulators

// SPDX-License-Identifier: MIT
#include "nav/emulators/mounted_truth.hpp"

#include <chrono>
#include <utility>

#include "nav/common/ensure.hpp"

namespace nav::emulators {
namespace {

/// Half-width of the central difference giving the angular acceleration.
constexpr Duration kRateStep = std::chrono::milliseconds(1);

}  // namespace

MountedTruth::MountedTruth(std::shared_ptr<const Truth> body, const Mount& mount)
    : body_(std::move(body)), mount_(mount), R_bd_(mount.q_bd.normalized().toRotationMatrix()) {
  NAV_ENSURE(body_ != nullptr, "a mounted device needs its vehicle's truth");
  mount_.q_bd.normalize();
}

Vec3 MountedTruth::angular_acceleration_b(Duration t) const {
  const Duration before = t >= kRateStep ? t - kRateStep : Duration{0};
  const Duration after = t + kRateStep;
  const Vec3 delta = body_->at(after).omega_b - body_->at(before).omega_b;
  return delta / to_seconds(after - before);
}

TruthSample MountedTruth::at(Duration t) const {
  const TruthSample b = body_->at(t);
  const Vec3& l = mount_.lever_arm_b;
  const Mat3 R_nb = b.q_nb.toRotationMatrix();
  const Vec3 alpha_b = angular_acceleration_b(t);
  // Acceleration of the device origin relative to the body reference, in b.
  const Vec3 a_lever_b = alpha_b.cross(l) + b.omega_b.cross(b.omega_b.cross(l));

  TruthSample d = b;
  d.p_n = b.p_n + R_nb * l;
  d.v_n = b.v_n + R_nb * b.omega_b.cross(l);
  d.a_n = b.a_n + R_nb * a_lever_b;
  d.q_nb = b.q_nb * mount_.q_bd;
  d.omega_b = R_bd_.transpose() * b.omega_b;
  d.f_b = R_bd_.transpose() * (b.f_b + a_lever_b);
  return d;
}

}  // namespace nav::emulators

// SPDX-License-Identifier: MIT
// The covariance navd states for a solution (solution_covariance.hpp).
#include "solution_covariance.hpp"

#include "nav/common/units.hpp"

namespace nav::dut {
namespace {

/// A block of P (3×3), its σ times scale; nullopt when P is not finite or a variance is < 0.
std::optional<protocols::navd::CovarianceBlock> block(const Mat3& P, double scale) {
  if (!P.allFinite() || (P.diagonal().array() < 0.0).any()) return std::nullopt;
  protocols::navd::Matrix3 m{};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) m[3 * i + j] = 0.5 * (P(i, j) + P(j, i));
  }
  return protocols::navd::block_of(m, scale);
}

}  // namespace

std::optional<protocols::navd::SolutionCovariance> solution_covariance(
    std::uint64_t tag, const estimator::NavSolution& nav, const estimator::AttitudeFilter& attitude,
    const estimator::PositionVelocityFilter* position_velocity) {
  protocols::navd::SolutionCovariance c;
  c.trigger_tag = tag;
  if (nav.attitude_valid) {
    if (const auto P = attitude.attitude_covariance_n()) c.attitude = block(*P, units::rad_to_deg(1.0));
  }
  if (nav.position_valid && position_velocity != nullptr) {
    const auto& P = position_velocity->P();
    using estimator::pv::kPos;
    using estimator::pv::kVel;
    c.position = block(P.block<kPos.dof, kPos.dof>(kPos.idx, kPos.idx), 1.0);
    c.velocity = block(P.block<kVel.dof, kVel.dof>(kVel.idx, kVel.idx), 1.0);
  }
  if (!c.attitude && !c.position && !c.velocity) return std::nullopt;
  return c;
}

}  // namespace nav::dut

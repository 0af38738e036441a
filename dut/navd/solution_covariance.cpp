// SPDX-License-Identifier: MIT
// The covariance navd states for a solution (solution_covariance.hpp).
#include "solution_covariance.hpp"

#include <cstring>

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

std::optional<protocols::navd::SolutionCovariance> solution_covariance(
    std::uint64_t tag, const estimator::P1Solution& p1) {
  if (!p1.valid || !p1.has_covariance) return std::nullopt;
  protocols::navd::SolutionCovariance c;
  c.trigger_tag = tag;
  c.attitude = block(p1.P_attitude_n, units::rad_to_deg(1.0));
  c.position = block(p1.P_position_n, 1.0);
  if (!c.attitude && !c.position) return std::nullopt;
  return c;
}

std::optional<protocols::navd::SolutionCovariance> solution_covariance(
    std::uint64_t tag, const std::optional<Mat3>& P_position_n) {
  if (!P_position_n) return std::nullopt;
  protocols::navd::SolutionCovariance c;
  c.trigger_tag = tag;
  c.position = block(*P_position_n, 1.0);
  if (!c.position) return std::nullopt;
  return c;
}

std::string solution_innovations(std::uint64_t tag,
                                 const std::vector<estimator::Innovation>& updates) {
  std::string out;
  for (const auto& u : updates) {
    if (u.dof < 1 || u.dof > estimator::Innovation::kMaxDof) continue;
    const auto m = static_cast<Eigen::Index>(u.dof);
    const auto nu = u.nu.head(m);
    const auto S = u.S.topLeftCorner(m, m);
    if (!nu.allFinite() || !S.allFinite() || (S.diagonal().array() < 0.0).any()) continue;
    // Readable units on the wire (NIS does not depend on them).
    const double scale = std::strcmp(u.source, "euler") == 0 ? units::rad_to_deg(1.0)
                         : std::strcmp(u.source, "mag") == 0 ? 1e6
                                                             : 1.0;
    std::array<double, protocols::navd::kMaxInnovationDof> v{};
    protocols::navd::Matrix4 s{};
    for (Eigen::Index i = 0; i < m; ++i) {
      v[static_cast<std::size_t>(i)] = scale * nu(i);
      for (Eigen::Index j = 0; j < m; ++j) {
        s[static_cast<std::size_t>(4 * i + j)] = scale * scale * 0.5 * (S(i, j) + S(j, i));
      }
    }
    out += protocols::navd::encode(
        protocols::navd::innovation_of(tag, u.source, u.dof, v, s));
  }
  return out;
}

}  // namespace nav::dut

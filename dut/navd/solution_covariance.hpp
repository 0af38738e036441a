// SPDX-License-Identifier: MIT
// The `$PNVBCOV` navd writes before each `$PNVBSOL` (docs/dut-contract.md §4): the attitude
// covariance of every attitude source that keeps one (EKF, UKF, ESKF: attitude_filter.hpp) and
// the position and velocity covariance of the GPS navigator's Kalman filter once it started.
// Raw, complementary and Mahony sources and DVL dead reckoning keep none: no sentence, or
// empty blocks. Pure.
#pragma once

#include <cstdint>
#include <optional>

#include "nav/estimator/attitude_filter.hpp"
#include "nav/estimator/navigator.hpp"
#include "nav/protocols/navd_covariance.hpp"

namespace nav::dut {

/// The covariance of the solution answering `tag`; nullopt when there is no block to state
/// (a covariance that is not finite or has a negative variance is left out, not written).
std::optional<protocols::navd::SolutionCovariance> solution_covariance(
    std::uint64_t tag, const estimator::NavSolution& nav, const estimator::AttitudeFilter& attitude,
    const estimator::PositionVelocityFilter* position_velocity);

}  // namespace nav::dut

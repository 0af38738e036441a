// SPDX-License-Identifier: MIT
// The `$PNVBCOV` navd writes before each `$PNVBSOL` (docs/dut-contract.md §4): the attitude
// covariance of every attitude source that keeps one (EKF, UKF, ESKF: attitude_filter.hpp) and
// the position and velocity covariance of the GPS navigator's Kalman filter once it started.
// Raw, complementary and Mahony sources and DVL dead reckoning keep none: no sentence, or
// empty blocks. And the `$PNVBINN` of each measurement update made at the sample, before it.
// Pure.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "nav/estimator/attitude_filter.hpp"
#include "nav/estimator/navigator.hpp"
#include "nav/estimator/p1_types.hpp"
#include "nav/protocols/navd_covariance.hpp"
#include "nav/protocols/navd_innovation.hpp"

namespace nav::dut {

/// The covariance of the solution answering `tag`; nullopt when there is no block to state
/// (a covariance that is not finite or has a negative variance is left out, not written).
std::optional<protocols::navd::SolutionCovariance> solution_covariance(
    std::uint64_t tag, const estimator::NavSolution& nav, const estimator::AttitudeFilter& attitude,
    const estimator::PositionVelocityFilter* position_velocity);

/// The covariance a paper P1 navigator states with its solution (position and attitude
/// blocks); nullopt when it keeps none or neither block can be stated.
std::optional<protocols::navd::SolutionCovariance> solution_covariance(
    std::uint64_t tag, const estimator::P1Solution& p1);

/// The covariance of a navigator that states its position's only (paper P2: the own block of
/// the joint state) [m²]; nullopt without one, or when it cannot be stated.
std::optional<protocols::navd::SolutionCovariance> solution_covariance(
    std::uint64_t tag, const std::optional<Mat3>& P_position_n);

/// The `$PNVBINN` sentences of the updates made at the sample answering `tag`, one after
/// another (empty when none): angles in degrees and fields in µT, the rest in the estimator's
/// SI units. An update whose ν or S is not finite, or S with a negative variance, is left
/// out.
std::string solution_innovations(std::uint64_t tag,
                                 const std::vector<estimator::Innovation>& updates);

}  // namespace nav::dut

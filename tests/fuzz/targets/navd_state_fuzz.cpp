// SPDX-License-Identifier: MIT
// navd state reports (navd_state.hpp, docs/wire-formats.md) as a vehicle's modem link reads
// what the channel delivers: through the StreamDecoder (sync 0xAA) in any reads, and by the
// reader loop. A decoded covariance is symmetric, positive semi-definite and has the sent σ
// on its diagonal, whatever the bytes. A decoded report is encodable, and sent again decodes
// to the same fields (exactly: they are whole counts), the same σ, and correlations within
// 1e-2 (navd_state.cpp: a rebuilt diagonal near 0 moves by up to 7.8e-3); a well-conditioned
// covariance (every σ > 0, correlation eigenvalues >= 1e-2) comes back exactly.
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

#include "fuzz_support.hpp"
#include "nav/protocols/navd_state.hpp"

namespace {

namespace state = nav::protocols::navd_state;
using nav::fuzz::ByteSpan;


/// Offset of the five std counts in a frame (navd_state.hpp's table) [bytes].
constexpr std::size_t kStdOffset = 26;
/// Largest |ΔC| between a decoded correlation matrix and the one sent again.
constexpr double kCorrelationTolerance = 1e-2;
/// Smallest correlation eigenvalue of a covariance that must come back exactly.
constexpr double kWellConditioned = 1e-2;

/// Symmetric, positive semi-definite, σ² of the frame's std counts on the diagonal.
void check_covariance(const state::Covariance& P, ByteSpan frame) {
  NAV_ENSURE(P == P.transpose(), "a decoded covariance is not symmetric");
  for (int i = 0; i < state::kStateSize; ++i) {
    const std::size_t at = kStdOffset + 2 * static_cast<std::size_t>(i);
    const double sigma = (frame[at] | frame[at + 1] << 8) /
                         (i < state::kHeading ? state::kStdMetresScale : state::kStdRadiansScale);
    NAV_ENSURE(P(i, i) == sigma * sigma, "a decoded variance is not the sent σ²");
  }
  const Eigen::SelfAdjointEigenSolver<state::Covariance> eig(P, Eigen::EigenvaluesOnly);
  NAV_ENSURE(eig.eigenvalues().minCoeff() >= -1e-12 * std::max(1.0, P.diagonal().maxCoeff()),
             "a decoded covariance is not positive semi-definite");
}

/// Correlation matrix of P; a zero σ gives a zero row and column.
state::Covariance correlation_of(const state::Covariance& P) {
  Eigen::Matrix<double, state::kStateSize, 1> inv;
  for (int i = 0; i < state::kStateSize; ++i) {
    inv(i) = P(i, i) > 0.0 ? 1.0 / std::sqrt(P(i, i)) : 0.0;
  }
  return inv.asDiagonal() * P * inv.asDiagonal();
}

/// Every σ > 0 and the correlation eigenvalues >= kWellConditioned.
bool well_conditioned(const state::Covariance& P) {
  if ((P.diagonal().array() <= 0.0).any()) return false;
  const Eigen::SelfAdjointEigenSolver<state::Covariance> eig(correlation_of(P),
                                                             Eigen::EigenvaluesOnly);
  return eig.eigenvalues().minCoeff() >= kWellConditioned;
}

void check(const state::StateReport& r, ByteSpan bytes) {
  if (r.covariance_valid) check_covariance(r.covariance, bytes);
  NAV_ENSURE(state::encodable(r), "a decoded report is not encodable");
  const nav::protocols::Bytes again = state::encode(r);
  const auto s = nav::fuzz::parse_exactly<state::StateReport, &state::parse>(again);
  NAV_ENSURE(s.vehicle_id == r.vehicle_id && s.t_s == r.t_s && s.lat_deg == r.lat_deg &&
                 s.lon_deg == r.lon_deg && s.depth_m == r.depth_m &&
                 s.heading_rad == r.heading_rad && s.pitch_rad == r.pitch_rad &&
                 s.attitude_valid == r.attitude_valid &&
                 s.covariance_valid == r.covariance_valid,
             "a report sent again decodes to other fields");
  NAV_ENSURE(s.covariance.diagonal() == r.covariance.diagonal(),
             "a covariance sent again decodes to other σ");
  const double moved =
      (correlation_of(s.covariance) - correlation_of(r.covariance)).cwiseAbs().maxCoeff();
  NAV_ENSURE(moved <= kCorrelationTolerance,
             "a covariance sent again moves its correlations by " + std::to_string(moved));
  NAV_ENSURE(!r.covariance_valid || !well_conditioned(r.covariance) || s.covariance == r.covariance,
             "a well-conditioned covariance sent again decodes to another one");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const nav::fuzz::Input in(data, size);
  nav::fuzz::stream<state::StateReport, &state::parse>(in, state::kSync1);
  nav::fuzz::drain<state::StateReport, &state::parse>(in.stream, check);
  return 0;
}

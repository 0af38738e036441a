// SPDX-License-Identifier: MIT
// The DUT's optional covariance sentence `$PNVBCOV` (docs/dut-contract.md §4): how uncertain
// the `$PNVBSOL` it follows claims to be, as standard deviations and correlations of three
// 3×3 blocks, each present or left empty:
//
//   position  NED [m]
//   velocity  NED [m/s]
//   attitude  the rotation vector δθ of R_true · R_estᵀ, resolved in NED [deg]: the true
//             attitude is the estimate rotated by δθ about NED axes (R_true = Exp([δθ]×) R_est,
//             a "global" error). |δθ| is the attitude error the bench judges.
//
// A block as σ₁, σ₂, σ₃ ≥ 0 and correlations ρ₁₂, ρ₁₃, ρ₂₃ in [−1, 1] rather than the six
// covariance entries: plain decimals need no exponent, and the printed numbers read directly.
// Pure: no I/O.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "nav/common/result.hpp"
#include "nav/protocols/nmea0183.hpp"

namespace nav::protocols::navd {

inline constexpr const char* kCovarianceAddress = "PNVBCOV";  ///< talker "P" + "NVBCOV"

/// A symmetric 3×3 covariance as standard deviations and correlations.
struct CovarianceBlock {
  std::array<double, 3> sigma{};  ///< σ of axes 1, 2, 3 (N, E, D)
  std::array<double, 3> rho{};    ///< correlations of axes (1, 2), (1, 3), (2, 3)
  bool operator==(const CovarianceBlock&) const = default;
};

/// The covariance of one solution, naming the trigger its `$PNVBSOL` answers.
struct SolutionCovariance {
  std::uint64_t trigger_tag = 0;
  std::optional<CovarianceBlock> position;  ///< σ [m]
  std::optional<CovarianceBlock> velocity;  ///< σ [m/s]
  std::optional<CovarianceBlock> attitude;  ///< σ [deg] of the NED rotation-vector error
  bool operator==(const SolutionCovariance&) const = default;
};

/// Row-major 3×3 matrix.
using Matrix3 = std::array<double, 9>;

/// The block of a covariance P (symmetric; its diagonal ≥ 0), σ in the square root of P's
/// unit times `scale` (e.g. rad → deg); a zero σ gives zero correlations.
CovarianceBlock block_of(const Matrix3& P, double scale = 1.0);

/// The covariance a block stands for, σ divided by `scale` first.
Matrix3 covariance_of(const CovarianceBlock& b, double scale = 1.0);

/// Frames a covariance as a `$PNVBCOV` sentence with CRLF: σ with six significant digits,
/// correlations with four decimals, no exponent. Needs finite σ ≥ 0 and |ρ| ≤ 1.
std::string encode(const SolutionCovariance& c);

/// Decodes the fields of an already framed sentence whose address is PNVBCOV: 19 fields
/// (the tag, then position, velocity, attitude: σ₁ σ₂ σ₃ ρ₁₂ ρ₁₃ ρ₂₃ each), a block's six all
/// present or all empty, σ ≥ 0, |ρ| ≤ 1.
Result<SolutionCovariance> decode_covariance(const nmea::Sentence& s);

}  // namespace nav::protocols::navd

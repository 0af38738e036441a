// SPDX-License-Identifier: MIT
// The DUT's optional innovation sentence `$PNVBINN` (docs/dut-contract.md §4): one
// measurement update the DUT made while answering a trigger, as its innovation ν = z − ẑ and
// the innovation covariance S the filter predicted for it, so the bench can judge the
// normalised innovation squared NIS = νᵀ S⁻¹ ν without knowing the truth:
//
//   $PNVBINN,<trigger_tag>,<source>,<m>,<ν₁>..<νₘ>,<σ₁>..<σₘ>,<ρ₁₂>,<ρ₁₃>..<ρ₍ₘ₋₁₎ₘ>*hh
//
// m (1..4) is the measurement's dimension; S as standard deviations σᵢ = √Sᵢᵢ ≥ 0 and
// correlations ρᵢⱼ = Sᵢⱼ / (σᵢ σⱼ) ∈ [−1, 1] of the pairs i < j in row order (m = 3: ρ₁₂ ρ₁₃
// ρ₂₃, as `$PNVBCOV`'s blocks; m = 4: ρ₁₂ ρ₁₃ ρ₁₄ ρ₂₃ ρ₂₄ ρ₃₄). ν and σ are in the
// measurement's own units (NIS does not depend on them). `source` names the measurement
// ([a-z0-9_-], 1 to 16 characters; navd: euler, accel, mag, gps-position, gps-velocity,
// depth). Pure: no I/O.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "nav/common/result.hpp"
#include "nav/protocols/nmea0183.hpp"

namespace nav::protocols::navd {

inline constexpr const char* kInnovationAddress = "PNVBINN";  ///< talker "P" + "NVBINN"
inline constexpr int kMaxInnovationDof = 4;                     ///< largest m on the wire
inline constexpr std::size_t kMaxSourceName = 16;               ///< longest source name

/// One measurement update, naming the trigger whose `$PNVBSOL` it comes before.
struct Innovation {
  std::uint64_t trigger_tag = 0;
  std::string source;                           ///< which measurement
  int dof = 0;                                  ///< m, 1..kMaxInnovationDof
  std::array<double, kMaxInnovationDof> nu{};   ///< ν₁..νₘ (the rest 0)
  std::array<double, kMaxInnovationDof> sigma{};  ///< σ₁..σₘ of S (the rest 0)
  /// ρ of the pairs i < j in row order, the first m(m−1)/2 used (the rest 0).
  std::array<double, 6> rho{};
  bool operator==(const Innovation&) const = default;
};

/// Row-major 4×4; an m-dimensional S fills its top-left m×m.
using Matrix4 = std::array<double, 16>;

/// An innovation from ν and S (symmetric, its diagonal ≥ 0; the top-left m×m of S): σ = √Sᵢᵢ,
/// ρ clamped to [−1, 1] (0 where a σ is 0).
Innovation innovation_of(std::uint64_t tag, std::string source, int dof,
                         const std::array<double, kMaxInnovationDof>& nu, const Matrix4& S);

/// The S an innovation stands for (top-left m×m, zero elsewhere).
Matrix4 covariance_of(const Innovation& i);

/// True for a name of 1..kMaxSourceName characters of [a-z0-9_-].
bool valid_source_name(const std::string& name);

/// Frames an innovation as a `$PNVBINN` sentence with CRLF: ν and σ with six significant
/// digits, ρ with four decimals, no exponent. Needs a valid source name, 1 ≤ m ≤ 4, finite
/// ν, finite σ ≥ 0 and |ρ| ≤ 1.
std::string encode(const Innovation& i);

/// Decodes the fields of an already framed sentence whose address is PNVBINN: tag, source,
/// m, then m values of ν, m of σ ≥ 0 and m(m−1)/2 of ρ ∈ [−1, 1], none empty.
Result<Innovation> decode_innovation(const nmea::Sentence& s);

}  // namespace nav::protocols::navd

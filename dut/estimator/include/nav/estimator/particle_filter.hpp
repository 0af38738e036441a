// SPDX-License-Identifier: MIT
// Particle-filter building blocks, independent of any model: a seeded random-number generator
// whose draws are reproducible, log-space weight normalisation, the effective sample size,
// systematic resampling and the Gaussian log-density through a Cholesky factor.
//
// References:
//   [A02] M. S. Arulampalam, S. Maskell, N. Gordon, T. Clapp, "A tutorial on particle filters
//         for online nonlinear/non-Gaussian Bayesian tracking", IEEE Trans. Signal Processing
//         50(2), 2002: Algorithm 2 (systematic resampling) and the effective sample size.
//   [K96] G. Kitagawa, "Monte Carlo filter and smoother for non-Gaussian nonlinear state space
//         models", J. Comput. Graph. Stat. 5(1), 1996 (systematic resampling).
//   [M64] G. Marsaglia, T. A. Bray, "A convenient method for generating normal variables",
//         SIAM Review 6(3), 1964 (the polar method).
// Equation labels W1..W6 are this file's own.
//
//   W1  l̃_i = (l_i − m) − ln Σ_j exp(l_j − m),  m = max_j l_j     log-sum-exp normalisation
//   W2  w_i = exp(l̃_i)                                            Σ w_i = 1
//   W3  ESS = 1 / Σ w_i²  (w normalised)                           [A02]
//   W4  u_j = (u + j) / N,  u ~ U[0, 1),  j = 0..N−1               systematic pointers [K96]
//   W5  a_j = min{ i : c_i > u_j },  c_i = Σ_{k<=i} w_k            ancestor of slot j
//       so particle i is copied ⌊N w_i⌋ or ⌈N w_i⌉ times (up to round-off when a pointer
//       lies within an ulp of a cumulative sum: u + j is rounded).
//   W6  ln N(r; 0, L Lᵀ) = −½ |L⁻¹ r|² − Σ ln L_jj − (n/2) ln 2π   (one triangular solve)
//
// Randomness: std::mt19937_64 is specified exactly by the C++ standard (its 10000th output of
// the default seed is fixed), but std::uniform_real_distribution and std::normal_distribution
// are implementation-defined. Rng therefore draws its own: uniform = (raw >> 11)·2⁻⁵³ (exact
// integer arithmetic), normal by the polar method (one std::log and one std::sqrt per pair;
// sqrt is exactly rounded by IEEE 754, log is the platform libm's, glibc's within an ulp).
// Same seed and same binary → bit-identical draws.
//
// Weights that are NaN, negative or all zero are refused (WeightStatus::kInvalid) with the
// outputs untouched; nothing here allocates, throws or aborts on data.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <random>
#include <span>

#include <Eigen/Core>

#include "nav/estimator/linear_kf.hpp"

namespace nav::estimator {

/// Seeded generator of reproducible uniform and standard-normal draws (see the file comment).
class Rng {
 public:
  /// Seeds std::mt19937_64 with `seed`.
  explicit Rng(std::uint64_t seed);

  /// Next raw 64-bit output of the engine.
  std::uint64_t next_u64() { return engine_(); }
  /// Uniform draw in [0, 1): the top 53 bits of one raw output times 2⁻⁵³ [-].
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  /// Standard-normal draw N(0, 1) (Marsaglia polar method; the second value of each pair is
  /// kept for the next call) [-].
  double normal();

 private:
  std::mt19937_64 engine_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

/// Outcome of a weight operation.
enum class WeightStatus {
  kOk,       ///< computed; outputs written
  kInvalid,  ///< NaN, +Inf, a negative weight, no positive weight, or mismatched sizes:
             ///< outputs untouched
};

/// Normalises log-weights in place (W1) and writes the weights w = exp(l̃) (W2), Σ w = 1.
/// −Inf entries (dead particles) get weight 0; NaN or +Inf, all −Inf, or sizes that differ →
/// kInvalid with both spans untouched. Log-weights near −1000 (likelihoods below the smallest
/// double) normalise without underflow.
WeightStatus normalize_log_weights(std::span<double> log_w, std::span<double> w);

/// Effective sample size 1/Σ w² (W3) of normalised weights [-]: N for uniform weights, 1 when
/// one weight is 1. 0 for an empty span.
double effective_sample_size(std::span<const double> w);

/// Systematic resampling (W4, W5) with the offset u ∈ [0, 1): writes, for each slot j, the
/// index of its ancestor (non-decreasing). The weights need not sum exactly to one (the
/// pointers are scaled by their sum); a zero-weight particle is never chosen. Invalid weights,
/// u outside [0, 1), or ancestors.size() != w.size() → kInvalid with `ancestors` untouched.
WeightStatus systematic_resample(std::span<const double> w, double u,
                                 std::span<std::size_t> ancestors);

/// Systematic resampling with the offset drawn from `rng` (one uniform draw).
WeightStatus systematic_resample(std::span<const double> w, Rng& rng,
                                 std::span<std::size_t> ancestors);

/// ln N(r; 0, Σ) with Σ = L Lᵀ, L lower triangular with a positive diagonal (W6): the residual r
/// in Σ's units, the result in ln of 1/(units of r)ⁿ.
template <int K>
double gaussian_log_density(const Vec<K>& r, const Mat<K, K>& L) {
  const Vec<K> u = L.template triangularView<Eigen::Lower>().solve(r);  // u = L⁻¹ r
  const double log_det_half = L.diagonal().array().log().sum();          // ½ ln |Σ|
  return -0.5 * u.squaredNorm() - log_det_half -
         0.5 * K * std::log(2.0 * std::numbers::pi);                     // (W6)
}

}  // namespace nav::estimator

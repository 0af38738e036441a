// SPDX-License-Identifier: MIT
// Particle-filter building blocks (particle_filter.hpp, W1..W5): the seeded generator, log-space
// weight normalisation, ESS and systematic resampling.
#include "nav/estimator/particle_filter.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace nav::estimator {
namespace {

/// Finite, non-negative weights with a positive sum; the sum.
bool weights_valid(std::span<const double> w, double& sum) {
  sum = 0.0;
  for (const double wi : w) {
    if (!std::isfinite(wi) || wi < 0.0) {
      return false;
    }
    sum += wi;
  }
  return sum > 0.0 && std::isfinite(sum);
}

}  // namespace

Rng::Rng(std::uint64_t seed) : engine_(seed) {}

double Rng::normal() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  // Polar method [M64]: (v1, v2) uniform in the unit disc (rejection, 4/π draws per pair on
  // average), s = v1² + v2²; v1·√(−2 ln s / s), v2·√(−2 ln s / s) are independent N(0, 1).
  double v1 = 0.0;
  double v2 = 0.0;
  double s = 0.0;
  do {
    v1 = 2.0 * uniform() - 1.0;
    v2 = 2.0 * uniform() - 1.0;
    s = v1 * v1 + v2 * v2;
  } while (s >= 1.0 || s == 0.0);
  const double factor = std::sqrt(-2.0 * std::log(s) / s);
  spare_ = v2 * factor;
  has_spare_ = true;
  return v1 * factor;
}

WeightStatus normalize_log_weights(std::span<double> log_w, std::span<double> w) {
  if (log_w.size() != w.size() || log_w.empty()) {
    return WeightStatus::kInvalid;
  }
  double m = -std::numeric_limits<double>::infinity();
  for (const double l : log_w) {
    if (std::isnan(l) || l == std::numeric_limits<double>::infinity()) {
      return WeightStatus::kInvalid;
    }
    if (l > m) {
      m = l;
    }
  }
  if (!std::isfinite(m)) {  // every particle dead
    return WeightStatus::kInvalid;
  }
  double sum = 0.0;
  for (const double l : log_w) {
    sum += std::exp(l - m);  // exp(−Inf) = 0; the largest term is exactly 1, so sum >= 1
  }
  // l_i − m first: both may be near −1000, and their difference is exact when they are close
  // (Sterbenz), where l_i − (m + ln Σ) would lose ~3 digits to cancellation.
  const double log_sum = std::log(sum);
  for (std::size_t i = 0; i < log_w.size(); ++i) {
    log_w[i] = (log_w[i] - m) - log_sum;  // (W1)
    w[i] = std::exp(log_w[i]);            // (W2)
  }
  return WeightStatus::kOk;
}

double effective_sample_size(std::span<const double> w) {
  double sum_sq = 0.0;
  for (const double wi : w) {
    sum_sq += wi * wi;
  }
  return sum_sq > 0.0 ? 1.0 / sum_sq : 0.0;  // (W3)
}

WeightStatus systematic_resample(std::span<const double> w, double u,
                                 std::span<std::size_t> ancestors) {
  double total = 0.0;
  if (ancestors.size() != w.size() || !weights_valid(w, total) || !(u >= 0.0 && u < 1.0)) {
    return WeightStatus::kInvalid;
  }
  const std::size_t n = w.size();
  // The last particle with a positive weight: where a pointer lands when round-off puts it at
  // (or past) the final cumulative sum.
  std::size_t last_positive = n - 1;
  while (w[last_positive] == 0.0) {
    --last_positive;
  }
  const double step = total / static_cast<double>(n);
  std::size_t i = 0;
  double c = w[0];  // c_i (W5)
  for (std::size_t j = 0; j < n; ++j) {
    const double pointer = (u + static_cast<double>(j)) * step;  // u_j, scaled by Σ w (W4)
    while (c <= pointer && i < last_positive) {
      ++i;
      c += w[i];
    }
    ancestors[j] = i;  // a_j = min{ i : c_i > u_j } (W5)
  }
  return WeightStatus::kOk;
}

WeightStatus systematic_resample(std::span<const double> w, Rng& rng,
                                 std::span<std::size_t> ancestors) {
  return systematic_resample(w, rng.uniform(), ancestors);
}

}  // namespace nav::estimator

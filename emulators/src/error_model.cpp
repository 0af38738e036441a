// SPDX-License-Identifier: MIT
// Sensor error models and per-device seeds (see device.hpp).
//
// Triad model, per axis i and sample k (dt_k = time since the previous sample):
//   w_i[k]  = w_i[k-1] + sigma_walk * sqrt(dt_k) * n1     bias random walk, w[-1] = 0
//   y_i[k]  = x_i[k] + b + w_i[k] + sigma_white * n2      n1, n2 ~ N(0, 1) independent
// so Var(w(t)) = sigma_walk^2 * t (unit^2), cf. gz-sensors GaussianNoiseModel.
#include <cmath>
#include <numbers>

#include "nav/common/ensure.hpp"
#include "nav/emulators/device.hpp"

namespace nav::emulators {
namespace {

constexpr std::uint64_t kFnvOffset = 14695981039346656037ULL;  ///< FNV-1a 64 offset basis
constexpr std::uint64_t kFnvPrime = 1099511628211ULL;          ///< FNV-1a 64 prime

std::uint64_t fnv1a64(std::string_view s) {
  std::uint64_t h = kFnvOffset;
  for (const char c : s) {
    h ^= static_cast<std::uint8_t>(c);
    h *= kFnvPrime;
  }
  return h;
}

/// splitmix64 finaliser (Steele, Lea, Flood 2014), as used to seed xoshiro generators.
std::uint64_t splitmix64(std::uint64_t x) {
  std::uint64_t z = x + 0x9E3779B97F4A7C15ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

/// 53-bit uniform in [0, 1) from one raw engine output.
double unit_uniform(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

}  // namespace

std::uint64_t device_seed(std::uint64_t scenario_seed, std::string_view device_name) {
  return splitmix64(scenario_seed ^ fnv1a64(device_name));
}

double standard_normal(std::mt19937_64& rng) {
  const double u1 = 1.0 - unit_uniform(rng);  // (0, 1]: log is finite
  const double u2 = unit_uniform(rng);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

Vec3 TriadErrorModel::apply(const Vec3& truth, double dt_s, std::mt19937_64& rng) {
  NAV_ENSURE(dt_s >= 0.0 && std::isfinite(dt_s), "dt_s must be finite and >= 0");
  const double walk_step = e_.bias_walk_std * std::sqrt(dt_s);
  for (int i = 0; i < 3; ++i) walk_[i] += walk_step * standard_normal(rng);
  Vec3 white;
  for (int i = 0; i < 3; ++i) white[i] = e_.white_std * standard_normal(rng);
  return truth + Vec3::Constant(e_.bias) + walk_ + white;
}

}  // namespace nav::emulators

// SPDX-License-Identifier: MIT
// Sensor error models and per-device seeds (see device.hpp).
//
// Triad model, per axis i and sample k (dt_k = time since the previous sample):
//   w_i[k]  = w_i[k-1] + sigma_walk * sqrt(dt_k) * n1     bias random walk, w[-1] = 0
//   y_i[k]  = x_i[k] + b + w_i[k] + sigma_white * n2      n1, n2 ~ N(0, 1) independent
// so Var(w(t)) = sigma_walk^2 * t (unit^2), cf. gz-sensors GaussianNoiseModel.
// Bias instability, a first-order Gauss-Markov process of standard deviation sigma_gm and
// correlation time tau (Groves sec. 4.4.2; IEEE Std 952-1997 Annex C models the flat floor of
// the Allan deviation this way), only when sigma_gm > 0, drawn after the six normals above:
//   g_i[0]  = sigma_gm * n3                                  stationary from the start
//   g_i[k]  = e^(-dt_k/tau) g_i[k-1] + sigma_gm sqrt(1 - e^(-2 dt_k/tau)) * n3   (exact
//             discretisation: Var(g) = sigma_gm^2 at every k, correlation e^(-|lag|/tau))
//   y_i[k] += g_i[k]
//
// Triad sensor model (TriadSensorErrorModel), applied in this order to a truth vector x given
// in the sensor's ideal frame (error terms as in Groves, "Principles of GNSS, Inertial, and
// Multisensor Integrated Navigation Systems", 2nd ed., sec. 4.4; the equation labels (E..)
// are this file's own):
//   u      = K x,   K = (I + diag(s)) M                 misalignment, then scale factor  (E1a)
//   v      = u + b + w[k]                               bias and bias walk (as above)    (E1b)
//   y~     = v + sigma_white * n2                       white noise                      (E1c)
//   y^_i   = clamp(y~_i, -r, +r)                        saturation at the range r        (E1d)
//   y_i    = q * clamp(round(y^_i / q), -c, +c)         quantization, LSB q,             (E1e)
//            c = floor(r / q)                           codes that fit in the range
// The scale-factor error s_i belongs to the sensing axis i, so it multiplies the component
// already projected on that axis (row i of M); M (I + diag(s)) differs only by s * theta.
// Misalignment from the small rotation vector theta of the sensor axes (R_is ~ I + [theta]x):
//   M = I - [theta]x = [  1        theta_z  -theta_y ]                                  (E2)
//                      [ -theta_z  1         theta_x ]
//                      [  theta_y -theta_x   1       ]
// Hard and soft iron (magnetometers), applied to the field b before (E1) (the disturbance is
// the vehicle's, not the sensor's; Groves sec. 6.1.1; NXP AN4246 "Calibrating an eCompass"
// writes the same model as B = W B_e + V):
//   b_dist = W b + h,   W soft-iron matrix, h hard-iron offset [T]                     (E3)
// (E1b)-(E1c) are TriadErrorModel itself: the draws are its six normals per sample, and the
// deterministic terms (E1a), (E1d), (E1e), (E3) draw nothing.
#include <algorithm>
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


}  // namespace

std::uint64_t device_seed(std::uint64_t scenario_seed, std::string_view device_name) {
  return splitmix64(scenario_seed ^ fnv1a64(device_name));
}

double unit_uniform(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
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
  if (e_.instability_std > 0.0) {
    NAV_ENSURE(std::isfinite(e_.instability_std) && e_.instability_tau_s > 0.0,
               "bias instability needs a finite std and a correlation time > 0");
    const double phi = started_ ? std::exp(-dt_s / e_.instability_tau_s) : 0.0;
    const double drive = e_.instability_std * std::sqrt(1.0 - phi * phi);
    for (int i = 0; i < 3; ++i) markov_[i] = phi * markov_[i] + drive * standard_normal(rng);
  }
  started_ = true;
  return truth + Vec3::Constant(e_.bias) + walk_ + white + markov_;
}

Mat3 small_angle_misalignment(const Vec3& theta_rad) {
  NAV_ENSURE(theta_rad.allFinite(), "misalignment angles must be finite");
  Mat3 theta_x;  // [theta]x, the cross-product matrix
  theta_x << 0.0, -theta_rad.z(), theta_rad.y(),
      theta_rad.z(), 0.0, -theta_rad.x(),
      -theta_rad.y(), theta_rad.x(), 0.0;
  return Mat3::Identity() - theta_x;  // Eq. (E2)
}

TriadSensorErrorModel::TriadSensorErrorModel(const TriadSensorErrors& e)
    : e_(e), random_(e.random) {
  NAV_ENSURE(e.scale_factor.allFinite(), "scale_factor must be finite");
  NAV_ENSURE(e.saturation > 0.0, "saturation must be > 0 (infinity = none)");
  NAV_ENSURE(e.quantum >= 0.0 && std::isfinite(e.quantum),
             "quantum must be finite and >= 0 (0 = none)");
  K_ = (Vec3::Ones() + e.scale_factor).asDiagonal() * small_angle_misalignment(e.misalignment_rad);
}

Vec3 TriadSensorErrorModel::apply(const Vec3& truth, double dt_s, std::mt19937_64& rng) {
  // With K = I exactly, K x = x exactly for finite x: the defaults reproduce TriadErrorModel.
  const Vec3 u = K_ * truth;             // Eq. (E1a)
  Vec3 y = random_.apply(u, dt_s, rng);  // Eq. (E1b), (E1c)
  const double r = e_.saturation;
  const double q = e_.quantum;
  // Largest code within the range; the relative margin keeps r / q = 2.9999999999999996
  // (r = 0.3, q = 0.1) at 3 codes.
  const double max_code = q > 0.0 ? std::floor(r / q * (1.0 + 1e-12)) : 0.0;
  for (int i = 0; i < 3; ++i) {
    y[i] = std::clamp(y[i], -r, r);  // Eq. (E1d)
    if (q > 0.0) {
      y[i] = q * std::clamp(std::round(y[i] / q), -max_code, max_code);  // Eq. (E1e)
    }
  }
  return y;
}

Vec3 HardSoftIron::apply(const Vec3& b_T) const {
  return soft_iron * b_T + hard_iron_T;  // Eq. (E3)
}

MagnetometerErrorModel::MagnetometerErrorModel(const HardSoftIron& iron,
                                               const TriadSensorErrors& sensor)
    : iron_(iron), sensor_(sensor) {
  NAV_ENSURE(iron.hard_iron_T.allFinite(), "hard_iron_T must be finite");
  NAV_ENSURE(iron.soft_iron.allFinite() && iron.soft_iron.determinant() > 0.0,
             "soft_iron must be finite with a positive determinant (no reflection, invertible)");
}

Vec3 MagnetometerErrorModel::apply(const Vec3& b_T, double dt_s, std::mt19937_64& rng) {
  return sensor_.apply(iron_.apply(b_T), dt_s, rng);
}

std::vector<Duration> sample_times(double rate_hz, Duration duration) {
  std::vector<Duration> t;
  for (std::int64_t k = 0;; ++k) {
    const Duration t_k = from_seconds(static_cast<double>(k) / rate_hz);
    if (t_k >= duration) break;
    t.push_back(t_k);
  }
  return t;
}

}  // namespace nav::emulators

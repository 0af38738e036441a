// SPDX-License-Identifier: MIT
// The JONSWAP spectrum and its components (see wave_spectrum.hpp for J1..J4).
#include "nav/emulators/wave_spectrum.hpp"

#include <cmath>
#include <numbers>

#include "nav/common/ensure.hpp"
#include "nav/emulators/device.hpp"

namespace nav::emulators {
namespace {

void ensure_valid(const JonswapSpec& spec) {
  NAV_ENSURE(std::isfinite(spec.significant_height_m) && spec.significant_height_m >= 0.0,
             "significant wave height must be finite and >= 0");
  NAV_ENSURE(std::isfinite(spec.peak_period_s) && spec.peak_period_s > 0.0,
             "peak period must be finite and > 0");
  NAV_ENSURE(std::isfinite(spec.gamma) && spec.gamma >= 1.0, "JONSWAP gamma must be >= 1");
}

}  // namespace

double jonswap_density(const JonswapSpec& spec, double omega_radps) {
  ensure_valid(spec);
  if (omega_radps <= 0.0 || spec.significant_height_m == 0.0) return 0.0;
  const double hs = spec.significant_height_m;
  const double wp = 2.0 * std::numbers::pi / spec.peak_period_s;
  const double r = omega_radps / wp;
  const double s_pm = 5.0 / 16.0 * hs * hs * std::pow(wp, 4) * std::pow(omega_radps, -5) *
                      std::exp(-1.25 * std::pow(r, -4));                          // J1
  const double sigma = omega_radps <= wp ? 0.07 : 0.09;                          // J2
  const double a_gamma = 1.0 - 0.287 * std::log(spec.gamma);
  const double x = (omega_radps - wp) / (sigma * wp);
  return a_gamma * s_pm * std::pow(spec.gamma, std::exp(-0.5 * x * x));
}

std::vector<WaveComponent> discretise_jonswap(const JonswapSpec& spec, std::size_t n,
                                              std::mt19937_64& rng) {
  ensure_valid(spec);
  NAV_ENSURE(n >= 1, "a sea needs at least one wave component");
  const double wp = 2.0 * std::numbers::pi / spec.peak_period_s;
  const double w_lo = kSpectrumLowRatio * wp;
  const double dw = (kSpectrumHighRatio - kSpectrumLowRatio) * wp / static_cast<double>(n);
  std::vector<WaveComponent> out;
  out.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double u = unit_uniform(rng);
    const double phase = 2.0 * std::numbers::pi * unit_uniform(rng);
    const double w = w_lo + (static_cast<double>(i) + u) * dw;                   // J3
    const double a = std::sqrt(2.0 * jonswap_density(spec, w) * dw);
    out.push_back({a, w, phase});
  }
  const double hs_drawn = significant_height(out);
  if (spec.significant_height_m == 0.0 || hs_drawn == 0.0) return {};
  const double scale = spec.significant_height_m / hs_drawn;                     // J4
  for (WaveComponent& c : out) c.amplitude_m *= scale;
  return out;
}

double significant_height(const std::vector<WaveComponent>& components) {
  double m0 = 0.0;
  for (const WaveComponent& c : components) m0 += 0.5 * c.amplitude_m * c.amplitude_m;
  return 4.0 * std::sqrt(m0);
}

}  // namespace nav::emulators

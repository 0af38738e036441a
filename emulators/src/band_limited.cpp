// SPDX-License-Identifier: MIT
// Band-limited random signal (see band_limited.hpp for B1-B3).
#include "nav/emulators/band_limited.hpp"

#include <cmath>
#include <numbers>

#include "nav/common/ensure.hpp"
#include "nav/emulators/device.hpp"

namespace nav::emulators {

BandLimitedSignal::BandLimitedSignal(const BandSpec& spec, std::mt19937_64& rng) {
  NAV_ENSURE(std::isfinite(spec.rms) && spec.rms >= 0.0, "band rms must be finite and >= 0");
  NAV_ENSURE(spec.order >= 0 && spec.order <= 2, "band order must be 0, 1 or 2");
  NAV_ENSURE(std::isfinite(spec.f_hi_hz) && spec.f_lo_hz > 0.0 && spec.f_lo_hz <= spec.f_hi_hz,
             "band must satisfy 0 < f_lo <= f_hi");
  NAV_ENSURE(spec.components >= 1, "a band needs at least one component");
  const auto n = spec.components;
  const double width_hz = (spec.f_hi_hz - spec.f_lo_hz) / static_cast<double>(n);
  components_.reserve(n);
  double sum_w_2k = 0.0;
  for (std::size_t j = 0; j < n; ++j) {
    const double u = unit_uniform(rng);
    const double phase = 2.0 * std::numbers::pi * unit_uniform(rng);
    const double f_hz = spec.f_lo_hz + (static_cast<double>(j) + u) * width_hz;  // B1
    const double w = 2.0 * std::numbers::pi * f_hz;
    sum_w_2k += std::pow(w, 2 * spec.order);
    components_.push_back({0.0, w, phase});
  }
  const double amplitude = spec.rms * std::sqrt(2.0 / sum_w_2k);  // B3
  for (Component& c : components_) c.amplitude = amplitude;
  if (spec.rms == 0.0) components_.clear();
}

SignalValue BandLimitedSignal::at(double t_s) const {
  SignalValue v;
  for (const Component& c : components_) {
    const double arg = c.w_radps * t_s + c.phase_rad;
    const double s = std::sin(arg);
    const double co = std::cos(arg);
    v.x += c.amplitude * s;                                 // B1
    v.dx += c.amplitude * c.w_radps * co;                   // B2
    v.ddx -= c.amplitude * c.w_radps * c.w_radps * s;
  }
  return v;
}

}  // namespace nav::emulators

// SPDX-License-Identifier: MIT
// A band-limited random signal with analytic derivatives: a sum of sinusoids whose
// frequencies fill a band [f_lo, f_hi] (one per equal-width bin, at a random place in it) with
// random phases and equal amplitudes, the spectral representation of a stationary Gaussian
// process (M. Shinozuka, G. Deodatis, "Simulation of stochastic processes by spectral
// representation", Appl. Mech. Rev. 44(4), 1991): a flat spectrum of the signal inside the band
// and nothing outside it. Equation labels B1..B3 are this file's own.
//
//   B1  x(t)   =  sum_j A sin(w_j t + phi_j),  w_j = 2 pi f_j,  j = 0 .. n-1
//       f_j    =  f_lo + (j + u_j) (f_hi - f_lo) / n,   u_j, phi_j / 2 pi ~ U[0, 1)
//   B2  x'(t)  =  sum_j A w_j cos(w_j t + phi_j),   x''(t) = -sum_j A w_j^2 sin(w_j t + phi_j)
//   B3  A      =  rms sqrt(2 / sum_j w_j^(2k))      so that the mean-square of the k-th
//                                                   derivative is rms^2 (k = 0, 1, 2)
// The RMS is exact over long times for the drawn frequencies (each sinusoid's mean square is
// A^2 w^(2k) / 2). Deterministic: the frequencies and phases
// come from the engine handed to the constructor, in that order (u_j then phi_j per j).
#pragma once

#include <cstddef>
#include <random>
#include <vector>

namespace nav::emulators {

/// One band of a band-limited signal: its RMS (of the signal or of a derivative) and band.
struct BandSpec {
  double rms = 0.0;       ///< root mean square of the `order`-th derivative [unit / s^order]
  int order = 0;          ///< 0: rms of the signal, 1: of its rate, 2: of its second derivative
  double f_lo_hz = 0.1;   ///< lower edge of the band [Hz] (> 0)
  double f_hi_hz = 1.0;   ///< upper edge [Hz] (>= f_lo_hz)
  std::size_t components = 24;  ///< number of sinusoids (>= 1)
};

/// A signal, its rate and its second derivative at one instant.
struct SignalValue {
  double x = 0.0;    ///< [unit]
  double dx = 0.0;   ///< [unit/s]
  double ddx = 0.0;  ///< [unit/s^2]
};

/// A band-limited random signal (B1-B3); zero everywhere when rms = 0.
class BandLimitedSignal {
 public:
  BandLimitedSignal() = default;
  /// Draws the frequencies and phases from rng. The spec must be valid (checked by NAV_ENSURE:
  /// finite, rms >= 0, order 0..2, 0 < f_lo <= f_hi, components >= 1).
  BandLimitedSignal(const BandSpec& spec, std::mt19937_64& rng);

  /// The signal and its two derivatives at t [s].
  SignalValue at(double t_s) const;
 private:
  struct Component {
    double amplitude;  ///< A [unit]
    double w_radps;    ///< w_j [rad/s]
    double phase_rad;  ///< phi_j [rad]
  };
  std::vector<Component> components_;
};

}  // namespace nav::emulators

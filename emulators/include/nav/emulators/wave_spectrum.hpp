// SPDX-License-Identifier: MIT
// The JONSWAP wave spectrum and its discretisation into long-crested sinusoidal components,
// for the sea-state truth kind (sea_state_truth.hpp).
//
// Reference: DNV-RP-C205 "Environmental conditions and environmental loads" (2010),
// §3.5.5 "JONSWAP spectrum" (after K. Hasselmann et al., "Measurements of wind-wave growth
// and swell decay during the Joint North Sea Wave Project (JONSWAP)", Dtsch. Hydrogr. Z.,
// Ergänzungsheft A 8(12), 1973). Equation labels J1..J4 are this file's own.
//
//   J1  S_PM(w) = 5/16 Hs^2 wp^4 w^-5 exp(-5/4 (w/wp)^-4)        Pierson-Moskowitz, wp = 2 pi/Tp
//   J2  S_J(w)  = A_g S_PM(w) g^exp(-(w - wp)^2 / (2 s^2 wp^2))  JONSWAP, g = gamma
//       A_g = 1 - 0.287 ln(g)                                    normalising factor (DNV)
//       s   = 0.07 for w <= wp, 0.09 for w > wp                   spectral width parameter
//   (gamma = 1 gives Pierson-Moskowitz; 3.3 is the JONSWAP mean, DNV's range is 1..7.)
//   J3  N components, one per equal-width bin of [w_lo, w_hi] = [0.5 wp, 4 wp]:
//       w_i = w_lo + (i + u_i) dw,  dw = (w_hi - w_lo)/N,  phi_i = 2 pi v_i,  u_i, v_i ~ U[0,1)
//       a_i = sqrt(2 S_J(w_i) dw)                  (Shinozuka-Deodatis, as band_limited.hpp)
//   J4  a_i <- a_i Hs / (4 sqrt(m0)),  m0 = sum_i a_i^2 / 2
//       so the discretised sea has 4 sqrt(m0) = Hs exactly (the spectral significant height
//       H_m0; A_g makes J2 hold this only approximately, and the bins drop the tails).
//
// The range: below 0.5 wp J1 is negligible (its factor exp(-5/4 (w/wp)^-4) is exp(-20) there);
// above 4 wp lies under 0.5 % of m0 (renormalised by J4), in waves shorter than lambda_p / 16
// (2.7 m at Tp = 5.3 s), which a hull of a metre or so no longer follows. The random
// frequency inside each bin keeps the record from repeating every 2 pi / dw (~150 s at
// N = 96, Tp = 5.3 s).
// Deterministic: u_i then v_i per component, from the engine handed in.
#pragma once

#include <cstddef>
#include <random>
#include <vector>

namespace nav::emulators {

/// A JONSWAP sea: significant height, peak period and peak enhancement (J1, J2).
struct JonswapSpec {
  double significant_height_m = 0.0;  ///< Hs = 4 sqrt(m0) [m] (>= 0)
  double peak_period_s = 5.3;         ///< Tp = 2 pi / wp [s] (> 0)
  double gamma = 3.3;                 ///< peak enhancement [-], 1 = Pierson-Moskowitz
};

/// One long-crested wave: elevation a cos(k d.x - w t + phi).
struct WaveComponent {
  double amplitude_m = 0.0;  ///< a_i [m]
  double omega_radps = 0.0;  ///< w_i [rad/s] (> 0)
  double phase_rad = 0.0;    ///< phi_i [rad]
};

/// Lower and upper edge of the discretised band, as multiples of wp (J3) [-].
inline constexpr double kSpectrumLowRatio = 0.5;
inline constexpr double kSpectrumHighRatio = 4.0;

/// S_J(w) of J2 at w > 0 [m^2 s/rad]; 0 for w <= 0 or Hs = 0. The spec must be valid
/// (NAV_ENSURE: finite, Hs >= 0, Tp > 0, gamma >= 1).
double jonswap_density(const JonswapSpec& spec, double omega_radps);

/// N components of the spectrum (J3, J4), drawn from rng; empty when Hs = 0. The spec must
/// be valid (as jonswap_density) and n >= 1 (NAV_ENSURE).
std::vector<WaveComponent> discretise_jonswap(const JonswapSpec& spec, std::size_t n,
                                              std::mt19937_64& rng);

/// 4 sqrt(sum a_i^2 / 2): the significant height of a set of components [m].
double significant_height(const std::vector<WaveComponent>& components);

}  // namespace nav::emulators

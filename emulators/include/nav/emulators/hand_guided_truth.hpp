// SPDX-License-Identifier: MIT
// The hand-guided truth kind (truth_kind.hpp): a rig moved by people, who mean it to follow a
// nominal path (any truth kind, in practice the path segments of truth.hpp) and do not quite.
// Four effects, each a band-limited random signal (band_limited.hpp) seeded from the scenario:
//
//   uneven speed  the rig runs ahead of and behind the nominal schedule: its progress is the
//                 nominal truth at a warped time tau(t) = t + delta(t) - delta(0), with
//                 delta' the fractional speed variation (rms `speed`), so it slows down and
//                 speeds up along the path but never leaves it, and stands still where the
//                 nominal path does (a stop or a turn on the spot stays one);
//   sway, heave   the hands steer it off the path: a horizontal displacement d_N, d_E (rms
//                 `sway` each) and a vertical one d_D (rms `heave`), each minus its value at
//                 t = 0 so that the rig starts on its mark;
//   wobble        its attitude wanders about the nominal: roll, pitch, yaw perturbations
//                 (rms `roll`, `pitch`, `yaw`) applied in the body frame;
//   shake         the pushes of a walking person's steps: a small 3-D displacement whose
//                 acceleration has rms `shake` per axis, in the band of walking cadence
//                 (minus its value at t = 0, as the sway).
//
// With the nominal truth N(.) at tau (p, v, a, q, omega), w(t) = ZYX(roll_w, pitch_w, yaw_w)
// the wobble and d = sway/heave + shake (labels H1..H5 are this file's own):
//   H1  tau   = t + delta(t) - delta(0),   tau' = 1 + delta'(t),   tau'' = delta''(t)
//   H2  p_n   = p(tau) + d(t)
//       v_n   = v(tau) tau' + d'(t)
//       a_n   = a(tau) tau'^2 + v(tau) tau'' + d''(t)
//   H3  q_nb  = q(tau) * q_w(t)
//   H4  omega = R_w^T omega(tau) tau' + E(roll_w, pitch_w) [roll_w', pitch_w', yaw_w']
//               (the rate of a product of rotations; E the ZYX Euler kinematics of truth.cpp)
//   H5  f_b   = R_nb^T (a_n - g_n)
// so the set stays consistent (tests/unit/emulators/truth_kind_test.cpp integrates it).
// distance_m is the nominal path's at tau (the sway is not counted).
//
// build() refuses a spec whose warped time would stop or run backwards (tau' <= 0) anywhere in
// [0, horizon], found on a grid of 1/(20 f_hi) of the speed band: lower `speed.rms`.
#pragma once

#include <cstdint>
#include <memory>

#include "nav/common/result.hpp"
#include "nav/emulators/band_limited.hpp"
#include "nav/emulators/truth_kind.hpp"

namespace nav::emulators {

/// The spectrum of hand-guided motion (scenario `vehicle.hand_guided`); a band with rms 0 is
/// off. Orders are fixed: speed 1 (rms of delta', a fraction), sway/heave/roll/pitch/yaw 0,
/// shake 2 (rms of the acceleration).
struct HandGuidedSpec {
  BandSpec speed{0.0, 1, 0.02, 0.3};   ///< fractional speed variation [-]
  BandSpec sway{0.0, 0, 0.03, 0.3};    ///< horizontal displacement, each of N and E [m]
  BandSpec heave{0.0, 0, 0.05, 0.5};   ///< vertical displacement [m]
  BandSpec roll{0.0, 0, 0.2, 0.8};     ///< roll wobble [rad]
  BandSpec pitch{0.0, 0, 0.2, 0.8};    ///< pitch wobble [rad]
  BandSpec yaw{0.0, 0, 0.05, 0.5};     ///< yaw wobble [rad]
  BandSpec shake{0.0, 2, 1.5, 2.5};    ///< acceleration of the step pushes, each axis [m/s^2]
};

/// The hand-guided truth kind; see the file comment.
class HandGuidedTruth final : public Truth {
 public:
  /// Draws every band from one engine seeded with `seed` (order: speed, sway N, sway E, heave,
  /// shake N, E, D, roll, pitch, yaw). Errors name the band: a band not 0 < f_lo <= f_hi, a
  /// negative or non-finite rms, or a speed variation that stops the rig within [0, horizon].
  static Result<HandGuidedTruth> build(std::shared_ptr<const Truth> nominal,
                                       const HandGuidedSpec& spec, std::uint64_t seed,
                                       double gravity_mps2, Duration horizon);

  TruthSample at(Duration t) const override;

 private:
  HandGuidedTruth() = default;

  std::shared_ptr<const Truth> nominal_;
  double gravity_mps2_ = 0.0;
  BandLimitedSignal speed_, sway_n_, sway_e_, heave_, shake_n_, shake_e_, shake_d_;
  BandLimitedSignal roll_, pitch_, yaw_;
  double delta0_s_ = 0.0;   ///< delta(0) [s]
  Vec3 offset0_n_ = Vec3::Zero();  ///< sway, heave and shake at t = 0 [m]
};

}  // namespace nav::emulators

// SPDX-License-Identifier: MIT
// The sea-state truth kind (truth_kind.hpp): a small craft floating in waves (paper P4's
// beacon near Busan), whose thrusters hold it on a nominal path over ground (any truth kind,
// in practice the path segments of truth.hpp) while the waves heave, surge and tilt it.
//
// The craft is a wave follower: its response amplitude operator is 1 in heave and in tilt
// (it rides the surface and lies along it). That holds for waves far longer than the hull:
// at Tp = 5.3 s the peak wave is g Tp^2 / (2 pi) = 44 m long, the shortest component
// (4 wp, wave_spectrum.hpp) 2.7 m, against a beacon of about a metre.
// The sea is long-crested (one direction), deep water, linear (Airy) theory, the components
// of a JONSWAP spectrum (wave_spectrum.hpp). Labels SS1..SS11 are this file's own.
//
// With the nominal truth N(t) (p, v, a, q, omega; yaw psi and its rate psi'), the waves
// coming from beta_from (0 = North, + East, like wind), so travelling along
// d = (cos beta, sin beta, 0), beta = beta_from + pi, and x = (p_N, p_E) the nominal's
// horizontal position (the phase is taken there, so the encounter frequency of a moving
// craft comes out of it):
//   SS1  k_i    = w_i^2 / g                          deep-water dispersion
//   SS2  th_i   = k_i d.x - w_i t + phi_i
//        th_i'  = k_i d.v - w_i,    th_i'' = k_i d.a
//   SS3  eta    =  sum a_i cos th_i                  surface elevation, up [m]
//        xi     = -sum a_i sin th_i                  orbital surge along d at the surface [m]
//        (and their first and second derivatives by the chain rule, as band_limited's B2)
//   SS4  p_n    = p + (xi d_N, xi d_E, -eta) - (the same at t = 0)   starts on its mark
//        v_n    = v + (xi' d, -eta'),   a_n = a + (xi'' d, -eta'')
//   SS5  grad eta = -s d,  s = sum a_i k_i sin th_i  (horizontal slope, NED)
//        sx = grad eta . (cos psi, sin psi) = -s cos(beta - psi)   rising ahead > 0
//        sy = grad eta . (-sin psi, cos psi) = -s sin(beta - psi)  rising to starboard > 0
//   SS6  pitch_w = atan(sx)                          nose up where the surface rises ahead
//        roll_w  = atan(-sy / sqrt(1 + sx^2))        starboard down where it falls to starboard
//        (exactly: body z = the surface's downward normal (sx, sy, 1) / |.| in heading axes)
//   SS7  q_nb   = q ⊗ q_w,  q_w = ZYX(roll_w, pitch_w, 0)
//        omega  = R_w^T omega + E(roll_w, pitch_w) [roll_w', pitch_w', 0]   (as hand_guided H4)
//   SS8  f_b    = R_nb^T (a_n - g_n)
// so the set stays consistent (tests/unit/emulators/sea_state_truth_test.cpp integrates it).
// The tilt is not offset at t = 0: the craft starts on its mark but lying on the surface.
// distance_m is the nominal path's.
//
// Wind and surface drift (for the beacon's thrust and compass disturbance, beacon_thrust.hpp):
//   SS9  wind_n  = U (cos(b_w + pi), sin(b_w + pi), 0),  b_w the wind's from-direction
//        water_n = k_drift wind_n,  k_drift = 0.03 by default
// The 3 % of wind speed rule for the wind-driven surface drift is a rule of thumb of
// oil-spill and search-and-rescue drift modelling (reviewed in ASCE Task Committee on
// Modeling of Oil Spills, "State-of-the-art review of modeling transport and fate of oil
// spills", J. Hydraul. Eng. 122(11), 1996, which reports wind factors of a few per cent), not
// a model of this sea: a default to change. The thrusters hold the craft on its path, so the drift
// does not move the truth; with `free_drift` the craft instead drifts with the water: x(t)
// becomes x(t) + water_n t in SS2 and SS4 (and v gains water_n).
//   SS10 water at the craft = water_n + (xi' d_N, xi' d_E, -eta')   the drift plus the waves'
//        orbital velocity at the surface: v_n - water = the nominal velocity (plus the drift
//        when drifting free) minus water_n, the craft's velocity through the water
//   SS11 surface at the craft = -eta + eta(0)   (depth, NED; SS4's offset) so that depth minus
//        surface is the nominal's, 0: a GNSS antenna on the craft never goes under water
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "nav/common/result.hpp"
#include "nav/emulators/truth_kind.hpp"
#include "nav/emulators/wave_spectrum.hpp"

namespace nav::emulators {

/// The wind over the sea (SS9).
struct WindSpec {
  double speed_mps = 0.0;     ///< U, mean wind speed [m/s] (>= 0)
  double from_rad = 0.0;      ///< direction it blows from, 0 = North, + towards East [rad]
  double drift_factor = 0.03; ///< k_drift, surface drift / wind speed [-] (0 .. 0.1)
};

/// A sea state (scenario `vehicle.sea`).
struct SeaSpec {
  JonswapSpec spectrum;          ///< Hs, Tp, gamma (wave_spectrum.hpp)
  double from_rad = 0.0;         ///< direction the waves come from, 0 = North, + East [rad]
  std::size_t components = 96;   ///< N, number of wave components (1 .. 4096)
  WindSpec wind;
  bool free_drift = false;       ///< the craft drifts with water_velocity_n() (SS9)
};

/// The sea-state truth kind; see the file comment.
class SeaStateTruth final : public Truth {
 public:
  /// Draws the components of spec.spectrum (wave_spectrum.hpp, J3-J4) from one engine seeded
  /// with `seed`. Errors name the field ("sea.peak_period: ..."): Hs < 0, Tp <= 0, gamma
  /// outside [1, 7], components outside 1 .. 4096, a wind speed < 0 or a drift factor outside
  /// [0, 0.1], anything non-finite.
  static Result<SeaStateTruth> build(std::shared_ptr<const Truth> nominal, const SeaSpec& spec,
                                     std::uint64_t seed, double gravity_mps2);

  /// The same craft in the given components (for tests: a single hand-made wave); the spectrum
  /// fields of spec are ignored. Contract (NAV_ENSURE): finite, every w_i > 0.
  static SeaStateTruth with_components(std::shared_ptr<const Truth> nominal,
                                       std::vector<WaveComponent> components,
                                       const SeaSpec& spec, double gravity_mps2);

  TruthSample at(Duration t) const override;

  /// The wave components, as drawn [m, rad/s, rad].
  const std::vector<WaveComponent>& components() const { return components_; }
  /// d, the direction the waves travel, NED, unit and horizontal [-].
  const Vec3& wave_direction_n() const { return d_n_; }
  /// The wind (air) velocity, NED, horizontal, towards where it blows (SS9) [m/s].
  const Vec3& wind_n() const { return wind_n_; }
  /// The wind-driven surface drift the thrusters hold against, NED (SS9) [m/s].
  const Vec3& drift_n() const { return water_n_; }
  /// SS10: the water at the craft: the surface drift plus the waves' orbital velocity
  /// (xi' d, -eta'), which the craft rides (a wave follower), so that v_n minus it is the
  /// craft's velocity through the water, what its thrusters push (beacon_thrust.hpp) [m/s].
  Vec3 water_velocity_n(Duration t) const override;
  /// The wind, the same everywhere and always (SS9) [m/s].
  Vec3 wind_velocity_n(Duration /*t*/) const override { return wind_n_; }
  /// SS11: the surface at the craft, -eta + eta(0) (SS4's offset: depths are measured from
  /// the surface where the craft starts): the craft rides it, so its depth minus this is the
  /// nominal's, 0 on a surface path [m].
  double surface_depth_m(Duration t) const override;

 private:
  SeaStateTruth() = default;

  /// SS2-SS3 and SS5 at one instant, from the horizontal position, velocity, acceleration
  /// of the phase reference x.
  struct Waves {
    double eta = 0.0, eta_dot = 0.0, eta_ddot = 0.0;  ///< elevation, up [m, m/s, m/s^2]
    double xi = 0.0, xi_dot = 0.0, xi_ddot = 0.0;     ///< surge along d [m, m/s, m/s^2]
    double s = 0.0, s_dot = 0.0;                      ///< grad eta = -s d (SS5) [-, 1/s]
  };
  Waves waves(double t_s, const Vec3& x_n, const Vec3& v_n, const Vec3& a_n) const;
  /// The same at scenario time t, at the nominal's place (drifting with the water when free).
  Waves waves_at(Duration t) const;

  std::shared_ptr<const Truth> nominal_;
  std::vector<WaveComponent> components_;
  std::vector<double> k_;          ///< k_i (SS1) [rad/m]
  double beta_rad_ = 0.0;          ///< beta, direction the waves travel [rad]
  Vec3 d_n_ = Vec3::UnitX();
  Vec3 wind_n_ = Vec3::Zero();
  Vec3 water_n_ = Vec3::Zero();
  bool free_drift_ = false;
  double gravity_mps2_ = 0.0;
  Vec3 offset0_n_ = Vec3::Zero();  ///< the wave displacement at t = 0 [m]
};

}  // namespace nav::emulators

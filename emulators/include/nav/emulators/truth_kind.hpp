// SPDX-License-Identifier: MIT
// What every truth kind gives: the vehicle's (or a device's) full motion at any scenario time.
//
// A truth kind is one way a vehicle moves: path segments with a speed profile (truth.hpp), a
// hand-guided rig (hand_guided_truth.hpp), a crawler on a wall plane (wall_truth.hpp), a craft
// in waves (sea_state_truth.hpp).
// Every device generator, the judge and the reactive devices read motion through this
// interface only, so a new kind is a new class and nothing else changes for them. A kind must
// give a consistent set: v_n the derivative of p_n, a_n of v_n, omega_b the body rate of q_nb,
// f_b = R_bn (a_n - g_n). tests/unit/emulators/truth_kind_test.cpp checks it for each kind
// by integrating the rates (truth_consistency.hpp).
//
// Frames: n = NED at the datum (treated as inertial), b = the body (FRD) of whatever moves:
// the vehicle, or a device mounted on it (MountedTruth, mounted_truth.hpp).
#pragma once

#include "nav/common/frames.hpp"
#include "nav/common/time.hpp"

namespace nav::emulators {

/// Truth at one instant.
struct TruthSample {
  Duration t{};                    ///< scenario time [ns]
  Vec3 p_n = Vec3::Zero();         ///< position, NED [m]; depth = p_n.z()
  Vec3 v_n = Vec3::Zero();         ///< velocity, NED [m/s]
  Vec3 a_n = Vec3::Zero();         ///< acceleration, NED [m/s^2]
  Quat q_nb = Quat::Identity();    ///< attitude body -> NED
  Vec3 omega_b = Vec3::Zero();     ///< angular rate of b w.r.t. n, in b [rad/s]
  Vec3 f_b = Vec3::Zero();         ///< specific force a - g, in b [m/s^2]
  double distance_m = 0.0;         ///< horizontal distance travelled since start [m]
};

/// A truth kind: motion evaluated at any scenario time t >= 0, deterministic and cheap.
class Truth {
 public:
  virtual ~Truth() = default;
  /// Truth at scenario time t >= 0.
  virtual TruthSample at(Duration t) const = 0;
  /// The water's velocity over ground at the body at scenario time t, NED [m/s]: what the
  /// body moves through (a current, the orbital motion of waves). Still water unless the kind
  /// models the sea (sea_state_truth.hpp). A device mount sees its vehicle's.
  virtual Vec3 water_velocity_n(Duration /*t*/) const { return Vec3::Zero(); }
  /// The wind over ground at the body at scenario time t, NED [m/s]. Calm unless the kind
  /// models it.
  virtual Vec3 wind_velocity_n(Duration /*t*/) const { return Vec3::Zero(); }
  /// The depth of the water surface at the body at scenario time t, NED [m]: 0 (the level
  /// depths are measured from) unless the kind models waves (sea_state_truth.hpp), whose
  /// craft rides the surface as it heaves. A device mount sees its vehicle's.
  virtual double surface_depth_m(Duration /*t*/) const { return 0.0; }

 protected:
  Truth() = default;
  Truth(const Truth&) = default;
  Truth& operator=(const Truth&) = default;
};

/// How far below the water surface a truth sample of `truth` at its time is [m]: its depth
/// minus the surface's (what decides whether a GNSS antenna has a fix).
inline double depth_below_surface_m(const Truth& truth, const TruthSample& s) {
  return s.p_n.z() - truth.surface_depth_m(s.t);
}

}  // namespace nav::emulators

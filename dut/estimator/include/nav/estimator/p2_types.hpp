// SPDX-License-Identifier: MIT
// What paper P2's cooperative localisation shares: the per-vehicle state, the six relative
// observations, the observation sets of the paper's four experiments, and the parameters.
//
// Reference: Choi, Lee, Lee, Kim, Lee, Kang, Lee, "Multi-AUV localisation with relative 3D
// observations", J. Korea Robotics Society 17(2), 2022 (docs/papers.md, P2). The paper has
// two vehicles; navbench generalises the joint filter to N (the paper's stated future work).
//
// Conventions: n = local NED [m] on one origin common to all vehicles; ψ heading (yaw),
// 0 = North, positive towards East, wrapped to (−π, π]; θ pitch, nose up positive [rad].
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

#include <Eigen/Core>

#include "nav/common/result.hpp"

namespace nav::estimator {

/// Dimension of one vehicle's state X_l = [N, E, D, ψ, θ]ᵀ (papers.md P2, "State per AUV").
inline constexpr int kP2VehicleDim = 5;
using P2Vec = Eigen::Matrix<double, kP2VehicleDim, 1>;
using P2Mat = Eigen::Matrix<double, kP2VehicleDim, kP2VehicleDim>;

/// Named parts of X_l.
struct P2Slice {
  static constexpr int kPos = 0;    ///< [N, E, D] [m], 3 entries
  static constexpr int kPsi = 3;    ///< ψ [rad]
  static constexpr int kTheta = 4;  ///< θ [rad]
};

/// The six relative observations of vehicle j made by vehicle i (papers.md P2 table).
enum class P2Observation : std::uint8_t {
  kDistance2d = 0,  ///< z_d0 = √(ΔN² + ΔE²) [m]
  kDistance3d = 1,  ///< z_d = √(ΔN² + ΔE² + ΔD²) [m]
  kBearing = 2,     ///< atan2(ΔE, ΔN) − ψ_i [rad], wrapped
  kHeading = 3,     ///< ψ_j − ψ_i [rad], wrapped
  kElevation = 4,   ///< atan2(ΔD, z_d0) [rad], + when j is deeper
  kPitch = 5,       ///< θ_j − θ_i [rad]
};
inline constexpr int kP2ObservationKinds = 6;

/// "distance-2d", "distance-3d", "bearing", "heading", "elevation", "pitch".
std::string_view to_string(P2Observation o);

/// True for the angle observations, whose innovation is wrapped to (−π, π].
constexpr bool is_angle(P2Observation o) {
  return o == P2Observation::kBearing || o == P2Observation::kHeading ||
         o == P2Observation::kElevation || o == P2Observation::kPitch;
}

/// A set of observation kinds (bit k = P2Observation k).
class P2ObservationSet {
 public:
  constexpr P2ObservationSet() = default;
  constexpr P2ObservationSet& add(P2Observation o) {
    bits_ = static_cast<std::uint8_t>(bits_ | (1u << static_cast<unsigned>(o)));
    return *this;
  }
  constexpr bool has(P2Observation o) const {
    return (bits_ >> static_cast<unsigned>(o)) & 1u;
  }
  constexpr bool empty() const { return bits_ == 0; }
  constexpr int size() const { return __builtin_popcount(bits_); }
  constexpr bool operator==(const P2ObservationSet&) const = default;

  /// The paper's experiments: 1 none (navigation only); 2 2-D distance, bearing, heading;
  /// 3 3-D distance, bearing, heading; 4 experiment 3 with elevation and pitch.
  /// Contract: 1 ≤ expt ≤ 4.
  static P2ObservationSet experiment(int expt);

 private:
  std::uint8_t bits_ = 0;
};

/// Parameters of the joint filter. SI units.
struct P2Params {
  /// Process noise of each vehicle's navigation increment, as a rate: Q_l = diag(q²)·Δt per
  /// step of Δt seconds (the paper's Q per step, made independent of the step length)
  /// [m/√s, m/√s, m/√s, rad/√s, rad/√s].
  P2Vec process_noise_rthz = (P2Vec() << 0.05, 0.05, 0.02, 0.002, 0.002).finished();
  /// 1-σ of each observation kind, indexed by P2Observation (papers.md: range 0.1 m, angles
  /// 1°) [m or rad].
  std::array<double, kP2ObservationKinds> observation_std = {0.1, 0.1, 0.01745329251994330,
                                                             0.01745329251994330,
                                                             0.01745329251994330,
                                                             0.01745329251994330};
  /// Bearing, elevation and 2-D distance need a horizontal separation: below this the
  /// observations that divide by z_d0 are not fused (counted as degenerate) [m].
  double min_horizontal_range_m = 0.5;
  /// NIS gate per observation set; 0 = none. χ²(5) at 99.99 % is 25.7 [-].
  double nis_gate = 0.0;
  /// How long the filter keeps its history to re-run for a late observation or report [s].
  /// An event older than the newest minus this is refused (counted as too late).
  double history_s = 20.0;
};

/// At most this many vehicles in one joint state (5 × 8 = 40 states).
inline constexpr int kP2MaxVehicles = 8;

/// Every field finite and in range (std > 0, noise ≥ 0, history > 0), or an error naming the
/// field.
Result<void> validate(const P2Params& p);

}  // namespace nav::estimator

// SPDX-License-Identifier: MIT
// DVL dead reckoning (paper P0): the DVL's body-frame velocity over the bottom, rotated to NED
// by the attitude of the configured source (attitude_filter.hpp), integrated from a known
// start. The same dead reckoning serves every attitude source, so their navigation can be
// compared on equal terms.
//
// Time comes only from the AHRS timer (as navigator.hpp). DVL velocities and depths carry no
// time usable against it, so they are queued and taken at the next AHRS sample:
//
//   AHRS sample k (interval Δt_k from the timer):
//     D0  the last DVL velocity queued since sample k−1 becomes the held velocity v_b,
//         stamped with sample k's time t_k; v̇_b = (v_b − v_b,prev)/(t_k − t_prev) between
//         two consecutive DVL velocities (zero for the first, or after a gap > dvl_timeout_s)
//     D1  attitude step of the source with (ω, f, m, Δt_k; v_b, v̇_b when fresh)
//     D2  if v_b is fresh (t_k − its stamp ≤ dvl_timeout_s):
//           v_n = R_nb v_b;   p_n ← p_n + v_n Δt_k          (P0 "DVL navigation")
//         else v_n = 0 and p_n is held (counted as a stale sample)
//     D3  the last depth queued since sample k−1, if any, sets the down position:
//           p_n,z = depth − origin_depth_m    (a pressure sensor beats integrating v_d)
//
// The dead reckoning starts at the configured origin (origin_lat_deg, origin_lon_deg,
// origin_depth_m) when the attitude source initialises from the first usable AHRS sample;
// position and attitude are valid from then on. Started with DvlStart::kFirstGpsFix
// (paper P2's vehicles, which dive from the surface), the position is not valid until the
// first GPS fix queued by add_gps_position(): at the next AHRS sample it sets p_n (D4, after
// D0..D3; only north and east once a depth has set the down position, D3), and the dead
// reckoning goes on from there; later fixes are counted, not used. No GPS is used: the P0 experiment runs
// submerged in a pool. The DVL is assumed aligned with the AHRS (instrument frame = body
// FRD) with no lever arm, as in the paper. No I/O, no clocks.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "nav/common/geodesy.hpp"
#include "nav/estimator/attitude_filter.hpp"
#include "nav/estimator/filter_params.hpp"
#include "nav/estimator/navigator.hpp"

namespace nav::estimator {

/// Counters for the exit summary and tests.
struct DvlNavigatorStats {
  std::uint64_t ahrs_samples = 0;           ///< samples given to on_ahrs()
  std::uint64_t ahrs_rejected_invalid = 0;  ///< samples with NaN/Inf (or unusable alignment)
  std::uint64_t dt_resets = 0;              ///< intervals <= 0 or > max_dt_s (no propagation)
  std::uint64_t dvl_used = 0;               ///< DVL velocities taken as v_b (D0)
  std::uint64_t dvl_rejected_invalid = 0;   ///< DVL velocities with NaN/Inf or > 20 m/s
  std::uint64_t dvl_superseded = 0;         ///< queued velocities replaced by a later one
  std::uint64_t stale_samples = 0;          ///< propagated samples without a fresh v_b (D2)
  std::uint64_t depth_used = 0;             ///< depths applied (D3)
  std::uint64_t depth_rejected_invalid = 0; ///< depths with NaN/Inf
  std::uint64_t gps_used = 0;               ///< GPS fixes that set the start (D4)
  std::uint64_t gps_ignored = 0;            ///< GPS fixes after the start, not finite, or kOrigin
};

/// Where the dead reckoning starts.
enum class DvlStart {
  kOrigin,       ///< the configured origin, at the first AHRS sample (paper P0)
  kFirstGpsFix,  ///< the first GPS fix (a vehicle that dives from the surface, paper P2)
};

/// DVL dead reckoning with a configurable attitude source; see the file comment.
class DvlNavigator {
 public:
  /// params must pass validate(); `kind` selects the attitude source.
  DvlNavigator(const FilterParams& params, AttitudeFilterKind kind,
               DvlStart start = DvlStart::kOrigin);

  /// Queues a bottom-track velocity of the vehicle over ground, body frame [m/s].
  void add_dvl_velocity(const Vec3& v_b_mps);
  /// Queues a depth below mean sea level [m, + down].
  void add_depth(double depth_m);
  /// Queues a GPS position: with DvlStart::kFirstGpsFix the first one sets the start (D4);
  /// any other is counted as ignored.
  void add_gps_position(const GpsPosition& fix);

  /// Processes one AHRS sample (D0..D3).
  void on_ahrs(const AhrsSample& sample);

  /// The current estimate: attitude_valid once the source initialised, position_valid from
  /// then on (kOrigin) or from the first GPS fix on (kFirstGpsFix); p_std_m is zero (dead
  /// reckoning carries no covariance).
  NavSolution solution() const;
  /// Status of the attitude step of the last AHRS sample (kOk when it made none).
  AttitudeStatus last_attitude_status() const { return last_status_; }
  const AttitudeFilter& attitude() const { return *attitude_; }
  const DvlNavigatorStats& stats() const { return stats_; }
  /// The attitude source's measurement updates at the last AHRS sample (dead reckoning
  /// itself makes none).
  const std::vector<Innovation>& innovations() const { return innovations_; }

  /// Largest DVL speed accepted (the NavQuest 600's ±20 kn) [m/s].
  static constexpr double kMaxDvlSpeedMps = 10.3;

 private:
  FilterParams params_;
  std::unique_ptr<AttitudeFilter> attitude_;
  geodesy::LocalTangentPlane plane_;
  DvlStart start_;
  bool aligned_ = false;
  bool started_ = false;  ///< the position is known (kOrigin: at alignment)
  std::optional<geodesy::Geodetic> queued_fix_;  ///< kFirstGpsFix: the start, before D4
  std::uint32_t previous_timer_ = 0;
  double t_s_ = 0.0;  ///< AHRS time since alignment, accumulated from the timer [s]
  std::optional<Vec3> queued_velocity_;
  std::optional<double> queued_depth_;
  std::optional<Vec3> v_b_;       ///< held DVL velocity
  double v_b_time_s_ = 0.0;       ///< its stamp t_k [s]
  Vec3 dv_b_ = Vec3::Zero();      ///< v̇_b [m/s²]
  Vec3 p_n_ = Vec3::Zero();
  Vec3 v_n_ = Vec3::Zero();
  AttitudeStatus last_status_ = AttitudeStatus::kOk;
  std::vector<Innovation> innovations_;
  DvlNavigatorStats stats_;
};

}  // namespace nav::estimator

// SPDX-License-Identifier: MIT
// Loosely coupled AHRS + GPS navigator: the configured attitude source
// (attitude_filter.hpp; by default the complementary filter of complementary_attitude.hpp) feeds the specific force, rotated into NED, to a
// position/velocity Kalman filter (pv_model.hpp) corrected by GPS position and velocity
// and by depth.
//
// Time comes only from the sensor data: the interval between two AHRS samples is the
// difference of their 3DM-GX3 timer fields (uint32 ticks of 1/62500 s, modulo 2^32).
// GPS fixes and depths carry no time usable against that timer, so they are queued and
// applied at the next AHRS sample, after its predict step:
//
//   AHRS sample k:  [align once] → attitude step (A4..A9) → KF predict (K1, K2)
//                   → every GPS fix and depth queued since sample k−1, in arrival order
//                     (K3..K7 with M7, M8, M9)
//
// The first GPS position fix anchors the local NED plane (p_n = 0 at the fix) and starts
// the KF; depths before it have no plane to live in and are counted and dropped. No I/O,
// no clocks.
#pragma once

#include <cstdint>
#include <optional>
#include <variant>
#include <vector>

#include <memory>

#include "nav/common/geodesy.hpp"
#include "nav/estimator/attitude_filter.hpp"
#include "nav/estimator/filter_params.hpp"
#include "nav/estimator/position_velocity_filter.hpp"

namespace nav::estimator {

inline constexpr double kAhrsTicksPerSecond = 62500.0;  ///< 3DM-GX3-25 timer rate [ticks/s]

/// Interval between two AHRS timer values, handling the wrap at 2^32 [s]. A timer that went
/// backwards yields an interval of about 19 h, which the navigator treats as a reset.
double ahrs_dt_s(std::uint32_t previous_ticks, std::uint32_t current_ticks);

/// One AHRS sample in SI units, sensor frame = body frame (FRD).
struct AhrsSample {
  std::uint32_t timer_ticks = 0;  ///< device timer [1/62500 s], wraps at 2^32
  Vec3 omega_b_radps = Vec3::Zero();  ///< angular rate, body [rad/s]
  Vec3 f_b_mps2 = Vec3::Zero();       ///< specific force, body [m/s²]
  Vec3 m_b_tesla = Vec3::Zero();      ///< magnetic field, body [T]
};

/// A GPS position fix.
struct GpsPosition {
  geodesy::Geodetic position;  ///< lat/lon [rad], alt_m = height above mean sea level [m]
};

/// A GPS horizontal velocity from speed and course over ground.
struct GpsVelocity {
  double sog_mps = 0.0;  ///< speed over ground [m/s]
  double cog_rad = 0.0;  ///< course over ground from true North, + towards East [rad]
};

/// A depth measurement, e.g. from a pressure sensor.
struct DepthMeasurement {
  double depth_m = 0.0;  ///< depth below mean sea level [m], + down
};

/// Counters for the exit summary and tests.
struct NavigatorStats {
  std::uint64_t ahrs_samples = 0;           ///< samples given to on_ahrs()
  std::uint64_t ahrs_rejected_invalid = 0;  ///< samples with NaN/Inf (or unusable alignment)
  std::uint64_t dt_resets = 0;              ///< intervals <= 0 or > max_dt_s (no propagation)
  std::uint64_t gps_position_fused = 0;     ///< position updates fused (incl. the anchor)
  std::uint64_t gps_velocity_fused = 0;     ///< velocity updates fused
  std::uint64_t gps_rejected_invalid = 0;   ///< GPS inputs with NaN/Inf or out of range
  std::uint64_t gps_rejected_gate = 0;      ///< GPS updates above their NIS gate
  std::uint64_t gps_velocity_unanchored = 0;  ///< velocities before the first position fix
  std::uint64_t gps_queue_dropped = 0;      ///< fixes (GPS or depth) dropped because no AHRS
                                            ///< sample came
  std::uint64_t depth_fused = 0;            ///< depth updates fused
  std::uint64_t depth_unanchored = 0;       ///< depths before the first position fix (dropped)
  std::uint64_t depth_rejected_invalid = 0; ///< depths with NaN/Inf
  std::uint64_t numerical_faults = 0;       ///< updates refused for numerical health
};

/// The navigator's current estimate.
struct NavSolution {
  bool attitude_valid = false;  ///< aligned from a first usable AHRS sample
  bool position_valid = false;  ///< a GPS fix has anchored and started the KF
  Quat q_nb = Quat::Identity();             ///< attitude body→NED
  geodesy::Geodetic position;               ///< lat/lon [rad], alt_m above MSL [m]
  Vec3 p_n = Vec3::Zero();                  ///< position w.r.t. the anchor, NED [m]
  Vec3 v_n = Vec3::Zero();                  ///< velocity, NED [m/s]
  Vec3 p_std_m = Vec3::Zero();              ///< 1-sigma of p_n per axis [m]
};

/// AHRS-driven loosely coupled navigator; see the file comment for the processing order.
class Navigator {
 public:
  /// params must pass validate(); `kind` selects the attitude source (attitude_filter.hpp).
  explicit Navigator(const FilterParams& params,
                     AttitudeFilterKind kind = AttitudeFilterKind::kMahony);

  /// Queues a position fix for the next AHRS sample.
  void add_gps_position(const GpsPosition& fix);
  /// Queues a velocity fix for the next AHRS sample.
  void add_gps_velocity(const GpsVelocity& fix);
  /// Queues a depth below mean sea level [m, + down] for the next AHRS sample.
  void add_depth(double depth_m);

  /// Processes one AHRS sample and then the queued GPS fixes and depths.
  void on_ahrs(const AhrsSample& sample);

  /// The current estimate.
  NavSolution solution() const;
  const NavigatorStats& stats() const { return stats_; }
  /// Status of the attitude step of the last AHRS sample (kOk when it made none).
  AttitudeStatus last_attitude_status() const { return last_status_; }
  const AttitudeFilter& attitude() const { return *attitude_; }
  /// The position/velocity filter, once the first fix started it.
  const std::optional<PositionVelocityFilter>& position_velocity() const { return kf_; }
  /// Report of the last GPS position update (nullopt before the first one after anchoring).
  const std::optional<UpdateReport<3>>& last_position_report() const { return last_pos_; }
  /// Report of the last GPS velocity update.
  const std::optional<UpdateReport<2>>& last_velocity_report() const { return last_vel_; }
  /// The measurement updates of the last AHRS sample, in the order made: the attitude
  /// source's, then the queued fixes' ("gps-position" [m], "gps-velocity" [m/s], "depth" [m]).
  const std::vector<Innovation>& innovations() const { return innovations_; }
  /// Report of the last depth update (nullopt before the first one after anchoring).
  const std::optional<UpdateReport<1>>& last_depth_report() const { return last_depth_; }

  /// Most fixes kept while waiting for an AHRS sample; older ones are dropped (counted).
  static constexpr std::size_t kMaxQueuedFixes = 64;

 private:
  void apply_queued_fixes();
  void apply(const GpsPosition& fix);
  void apply(const GpsVelocity& fix);
  void apply(const DepthMeasurement& depth);
  template <typename Fix>
  void enqueue(const Fix& fix);
  template <int M>
  void count(const UpdateReport<M>& report, std::uint64_t& fused_counter);

  FilterParams params_;
  std::unique_ptr<AttitudeFilter> attitude_;
  AttitudeStatus last_status_ = AttitudeStatus::kOk;
  bool aligned_ = false;
  std::uint32_t previous_timer_ = 0;
  std::optional<geodesy::LocalTangentPlane> plane_;  ///< set by the first position fix
  std::optional<PositionVelocityFilter> kf_;         ///< started with the plane
  double gravity_mps2_ = 0.0;                        ///< normal gravity at the anchor
  std::vector<std::variant<GpsPosition, GpsVelocity, DepthMeasurement>> queue_;
  std::optional<UpdateReport<3>> last_pos_;
  std::optional<UpdateReport<2>> last_vel_;
  std::optional<UpdateReport<1>> last_depth_;
  std::vector<Innovation> innovations_;
  NavigatorStats stats_;
};

}  // namespace nav::estimator

// SPDX-License-Identifier: MIT
// A P1 navigator (p1_types.hpp) driven as navd drives its other navigators: time from the
// AHRS timer, GPS fixes in geodetic coordinates queued until the next AHRS sample, position
// in the local NED plane of the configured origin.
//
//   AHRS sample k:  first usable sample: remember its timer (the navigator's initial state is
//                   the configured one, valid from this sample on); no step
//                   later samples: dt_k from the timer (ahrs_dt_s); dt_k ∉ (0, max_dt_s]
//                   skips the step (counted: a gap or a timer reset) → IMU step (on_imu)
//                   → every GPS fix queued since sample k−1, in arrival order, as
//                     p̃_n = plane.to_ned(fix) (on_gps_position)
//   innovations():  those of the IMU step and of every fix of the last sample, in that order
//
// The plane is the configured origin (origin_lat_deg, origin_lon_deg, −origin_depth_m),
// where the navigator's initial position (P1Params::initial_p_n_m) is expressed. No I/O, no
// clocks.
#pragma once

#include <cstdint>
#include <memory>
#include <string_view>
#include <vector>

#include "nav/common/geodesy.hpp"
#include "nav/common/result.hpp"
#include "nav/estimator/navigator.hpp"
#include "nav/estimator/p1_types.hpp"

namespace nav::estimator {

/// The P1 navigator named `name` ("ins", "ekf15", "upf15", "mfins"); an error names the known ones.
Result<std::unique_ptr<P1Navigator>> make_p1_navigator(std::string_view name,
                                                       const P1Params& params);

/// The names make_p1_navigator knows, comma separated.
std::string p1_navigator_names();

/// Counters of the driver itself (the navigator's own are P1Navigator::stats()).
struct P1DriverStats {
  std::uint64_t ahrs_samples = 0;      ///< samples given to on_ahrs()
  std::uint64_t dt_resets = 0;         ///< intervals ∉ (0, max_dt_s]: no step
  std::uint64_t gps_queued = 0;        ///< fixes queued
  std::uint64_t gps_queue_dropped = 0; ///< fixes dropped: kMaxQueuedFixes waiting already
};

/// See the file comment.
class P1Driver {
 public:
  P1Driver(std::unique_ptr<P1Navigator> navigator, const geodesy::Geodetic& origin,
           double max_dt_s);

  /// Queues a position fix for the next AHRS sample.
  void add_gps_position(const GpsPosition& fix);
  /// Steps the navigator with one AHRS sample, then applies the queued fixes.
  void on_ahrs(const AhrsSample& sample);

  /// The estimate as navd's other navigators give it (position also geodetic).
  NavSolution solution() const;
  /// The navigator's own solution, with its covariances.
  P1Solution p1_solution() const { return navigator_->solution(); }
  /// The updates made at the last AHRS sample (IMU step, then each fix).
  const std::vector<Innovation>& innovations() const { return innovations_; }
  const P1Navigator& navigator() const { return *navigator_; }
  const P1DriverStats& stats() const { return stats_; }

  /// Most fixes kept while waiting for an AHRS sample; older ones are dropped (counted).
  static constexpr std::size_t kMaxQueuedFixes = 64;

 private:
  std::unique_ptr<P1Navigator> navigator_;
  geodesy::LocalTangentPlane plane_;
  double max_dt_s_;
  bool started_ = false;
  std::uint32_t previous_timer_ = 0;
  std::vector<GpsPosition> queue_;
  std::vector<Innovation> innovations_;
  P1DriverStats stats_;
};

}  // namespace nav::estimator

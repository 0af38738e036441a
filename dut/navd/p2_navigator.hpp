// SPDX-License-Identifier: MIT
// navd's `navigator: p2`: paper P2's cooperative localisation of N vehicles, as one vehicle
// runs it. Pure (no I/O, no clock): navd_app.cpp hands it the AHRS samples, DVL velocities,
// depths and GPS fixes of its own navigation, the iUSBL fixes of its own device, and the
// state reports the other vehicles send over the acoustic modem; it gives the cooperative
// solution, and the report of its own navigation to send.
//
// Vehicles are numbered by their --vehicle-id, 1..N (p2_vehicles); vehicle id k is joint
// state block k − 1, its state report carries id k and its iUSBL pings carry acoustic address
// k. Time is mission time, the common time base of every vehicle (seconds since the scenario
// started): the AHRS timer's t = ((timer − p2_timer_start) mod 2³²) / 62 500 (runs shorter
// than 19 h), the iUSBL's measurement time, a state report's t_ms.
//
//   own navigation   DVL dead reckoning (dvl_navigator.hpp) started at the first GPS fix at
//                    the surface, attitude from the configured source. At each AHRS sample k
//                    with a valid position, its state x_k = [N, E, D, ψ, θ] on the plane of
//                    origin_lat_deg/origin_lon_deg/origin_depth_m:
//                      first:  init(t_k, own, x_k, P0 = diag(p2_initial_*²))
//                      then:   increment(t_k, own, x_k − x_{k−1} (ψ wrapped), t_k − t_{k−1})
//                    (papers.md's reading of eq 10: the motion model is the navigation's
//                    increment, not f(X̂) = X̂, which would discard the fixes' corrections.)
//                    Its own covariance P_nav = P0 + Σ Q Δt is what the vehicle reports.
//   peer reports     the peer's own navigation (not its cooperative estimate: the vehicles'
//                    navigation errors are independent, the cooperative ones are not). The
//                    first inits its block with the report's covariance; each later one is
//                    the increment since the previous, cut linearly at the emission times of
//                    the pending fixes of that peer inside it, so that a fix compares the
//                    peer's state at the ping's emission, not at its previous report. A
//                    report not newer than the previous one of its sender is dropped.
//   timeliness       a fix or report valid more than 1 s after the own last sample, or
//                    older than p2_history_s before it, is counted as untimely and dropped.
//   iUSBL fixes      USBLLONG + NVBRELATT of one ping → p2_fix.hpp's six observations at the
//                    emission t_e, with the own navigation's velocity. The experiment's set
//                    (p2_experiment) waits for the observed peer's report covering t_e and
//                    is then fused at t_e (p2_timed_filter.hpp re-runs what came after); a
//                    fix whose t_e a report already covers is fused at once. Experiment 1
//                    fuses none: the solution is the navigation.
//   solution         the own block of the joint state: position N, E, D, heading ψ, pitch θ;
//                    roll and velocity from the own navigation; the position covariance for
//                    $PNVBCOV.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <vector>

#include "config_p2.hpp"
#include "nav/common/geodesy.hpp"
#include "nav/estimator/dvl_navigator.hpp"
#include "nav/estimator/p2_timed_filter.hpp"
#include "nav/protocols/evologics_usbl.hpp"
#include "nav/protocols/navd_state.hpp"

namespace nav::dut {

/// What the P2 navigator heard, for navd's exit summary.
struct P2NavigatorCounts {
  std::uint64_t fixes = 0;          ///< iUSBL fixes (USBLLONG + NVBRELATT pairs) given
  std::uint64_t fixes_bad = 0;      ///< fixes p2_fix refused (not one ping, not finite, ...)
  std::uint64_t fixes_unknown = 0;  ///< fixes of an address that is no other vehicle's id
  std::uint64_t fixes_early = 0;    ///< fixes before the own navigation started
  std::uint64_t fixes_behind_report = 0;  ///< fixes fused after a report covering them
  std::uint64_t fixes_unmatched = 0;  ///< fixes before the peer's first report, or waiting
                                      ///< longer than p2_history_s for one
  std::uint64_t reports = 0;        ///< state reports of other vehicles used
  std::uint64_t reports_unknown = 0;  ///< reports of an id outside 1..N, or this vehicle's
  std::uint64_t reports_partial = 0;  ///< reports without attitude or covariance
  std::uint64_t reports_stale = 0;    ///< reports not newer than their sender's previous one
  std::uint64_t untimely = 0;  ///< fixes and reports valid more than kMaxAheadS after the own
                               ///< last sample, or older than p2_history_s before it
};

class P2Navigator {
 public:
  /// Contract: validate(config) and estimator::validate(params) passed; 1 ≤ own_id ≤
  /// config.vehicles.
  P2Navigator(const estimator::FilterParams& params, estimator::AttitudeFilterKind attitude,
              const P2Config& config, int own_id);

  void add_dvl_velocity(const Vec3& v_b_mps) { nav_.add_dvl_velocity(v_b_mps); }
  void add_depth(double depth_m) { nav_.add_depth(depth_m); }
  void add_gps_position(const estimator::GpsPosition& fix) { nav_.add_gps_position(fix); }

  /// Steps the own navigation and gives the filter its increment.
  void on_ahrs(const estimator::AhrsSample& sample);
  /// One ping of the own iUSBL.
  void on_fix(const protocols::evologics::UsblLong& l,
              const protocols::evologics::RelativeAttitude& a);
  /// Another vehicle's state report.
  void on_report(const protocols::navd_state::StateReport& r);

  /// The cooperative estimate (position_valid once the own navigation started).
  estimator::NavSolution solution() const;
  /// Covariance of the own position, NED [m²]; nullopt before the own navigation started.
  std::optional<Mat3> position_covariance() const;
  /// The state report of the own navigation at the last AHRS sample (nullopt before it
  /// started, or when not encodable).
  std::optional<protocols::navd_state::StateReport> own_report() const;

  /// Data valid this long after the own last sample are refused: on one time base only a
  /// wrong clock or sender makes them, and one would hold the filter's history hostage [s].
  static constexpr double kMaxAheadS = 1.0;

  /// Mission time of the last AHRS sample [s].
  double mission_time_s() const { return t_s_; }
  const estimator::DvlNavigator& navigation() const { return nav_; }
  const estimator::P2TimedFilter& filter() const { return filter_; }
  const P2NavigatorCounts& counts() const { return counts_; }

 private:
  /// A vehicle's navigation state as last heard (own: last sample; peer: last report).
  struct Track {
    bool started = false;
    double t_s = 0.0;
    estimator::P2Vec x = estimator::P2Vec::Zero();
  };
  /// Whether data valid at t_s may enter the filter (else counted as untimely).
  bool timely(double t_s) const;
  /// Navigation state [N, E, D, ψ, θ] of a position and attitude on the plane.
  estimator::P2Vec state_of(const geodesy::Geodetic& g, double psi, double theta) const;

  P2Config config_;
  int own_;  ///< own block index (id − 1)
  estimator::DvlNavigator nav_;
  estimator::P2TimedFilter filter_;
  estimator::P2ObservationSet set_;
  geodesy::LocalTangentPlane plane_;
  double t_s_ = 0.0;
  Track own_track_;
  estimator::P2Mat P_nav_ = estimator::P2Mat::Zero();  ///< own navigation's covariance
  std::vector<Track> peers_;                           ///< by block index
  /// A fix waiting for the observed peer's report covering its emission.
  struct PendingFix {
    double t_s = 0.0;  ///< emission [s]
    estimator::P2Measurement m;
  };
  std::vector<std::deque<PendingFix>> pending_;  ///< by observed block, in time order
  P2NavigatorCounts counts_;
};

}  // namespace nav::dut

// SPDX-License-Identifier: MIT
// The steps are stated in p2_navigator.hpp.
#include "p2_navigator.hpp"

#include <algorithm>
#include <cmath>

#include "nav/common/ensure.hpp"
#include "nav/common/frames.hpp"
#include "nav/common/units.hpp"
#include "p2_fix.hpp"

namespace nav::dut {
namespace {

using estimator::P2Mat;
using estimator::P2Slice;
using estimator::P2Vec;
namespace state = protocols::navd_state;

/// Mission time of an AHRS timer value [s] (wraps at 2³² ticks, 19 h).
double mission_time_of(std::uint32_t timer_ticks, double timer_start_ticks) {
  const auto start = static_cast<std::uint32_t>(timer_start_ticks);
  return static_cast<double>(static_cast<std::uint32_t>(timer_ticks - start)) /
         estimator::kAhrsTicksPerSecond;
}

/// x_b − x_a with the heading difference wrapped to (−π, π].
P2Vec difference(const P2Vec& x_b, const P2Vec& x_a) {
  P2Vec d = x_b - x_a;
  d(P2Slice::kPsi) = wrap_pi(d(P2Slice::kPsi));
  return d;
}

}  // namespace

P2Navigator::P2Navigator(const estimator::FilterParams& params,
                         estimator::AttitudeFilterKind attitude, const P2Config& config,
                         int own_id)
    : config_(config),
      own_(own_id - 1),
      nav_(params, attitude, estimator::DvlStart::kFirstGpsFix),
      filter_(config.filter, config.vehicles),
      set_(estimator::P2ObservationSet::experiment(config.experiment)),
      plane_({units::deg_to_rad(params.origin_lat_deg), units::deg_to_rad(params.origin_lon_deg),
              -params.origin_depth_m}),
      peers_(static_cast<std::size_t>(config.vehicles)),
      pending_(static_cast<std::size_t>(config.vehicles)) {
  NAV_ENSURE(own_id >= 1 && own_id <= config.vehicles, "P2Navigator: own id out of 1..N");
}

bool P2Navigator::timely(double t_s) const {
  return t_s <= t_s_ + kMaxAheadS && t_s >= t_s_ - config_.filter.history_s;
}

P2Vec P2Navigator::state_of(const geodesy::Geodetic& g, double psi, double theta) const {
  P2Vec x;
  x.segment<3>(P2Slice::kPos) = plane_.to_ned(g);
  x(P2Slice::kPsi) = wrap_pi(psi);
  x(P2Slice::kTheta) = theta;
  return x;
}

void P2Navigator::on_ahrs(const estimator::AhrsSample& sample) {
  nav_.on_ahrs(sample);
  t_s_ = mission_time_of(sample.timer_ticks, config_.timer_start_ticks);
  const estimator::NavSolution s = nav_.solution();
  if (!s.position_valid) return;
  const Euler e = euler_from_quat(s.q_nb);
  const P2Vec x = state_of(s.position, e.yaw, e.pitch);
  if (!x.allFinite()) return;
  if (!own_track_.started) {
    P2Vec sigma;
    sigma << config_.initial_position_std_m, config_.initial_position_std_m,
        config_.initial_position_std_m, config_.initial_heading_std_rad,
        config_.initial_pitch_std_rad;
    P_nav_ = sigma.array().square().matrix().asDiagonal();
    if (!filter_.init_vehicle(t_s_, own_, x, P_nav_)) return;
    own_track_ = {true, t_s_, x};
    return;
  }
  const double dt = t_s_ - own_track_.t_s;
  if (dt <= 0.0) return;  // a timer that did not advance: nothing to add
  filter_.increment(t_s_, own_, difference(x, own_track_.x), dt);
  const P2Vec q = config_.filter.process_noise_rthz;
  P_nav_ += (q.array().square() * dt).matrix().asDiagonal();  // what the filter's F2 adds
  own_track_ = {true, t_s_, x};
}

void P2Navigator::on_fix(const protocols::evologics::UsblLong& l,
                         const protocols::evologics::RelativeAttitude& a) {
  ++counts_.fixes;
  const auto fix = p2_fix(l, a, nav_.solution().v_n);
  if (!fix) {
    ++counts_.fixes_bad;
    return;
  }
  const int j = fix->remote_address - 1;
  if (j < 0 || j >= config_.vehicles || j == own_) {
    ++counts_.fixes_unknown;
    return;
  }
  if (!own_track_.started) {
    ++counts_.fixes_early;
    return;
  }
  if (!timely(fix->t_emitted_s)) {
    ++counts_.untimely;
    return;
  }
  if (set_.empty()) return;  // experiment 1: navigation only
  estimator::P2Measurement m;
  m.observer = own_;
  m.observed = j;
  m.set = set_;
  m.z = fix->z;
  const Track& peer = peers_[static_cast<std::size_t>(j)];
  if (peer.started && fix->t_emitted_s <= peer.t_s) {
    // The peer's increment over the emission was given whole: the fix sees its state at the
    // report before (rare: fixes arrive a travel time late, reports a packet's air time).
    ++counts_.fixes_behind_report;
    filter_.fix(fix->t_emitted_s, m);
    return;
  }
  auto& pending = pending_[static_cast<std::size_t>(j)];
  const auto at = std::upper_bound(
      pending.begin(), pending.end(), fix->t_emitted_s,
      [](double t, const PendingFix& p) { return t < p.t_s; });
  pending.insert(at, PendingFix{fix->t_emitted_s, m});
  // A peer that stopped reporting: its fixes are dropped when the filter could no longer
  // take them.
  while (!pending.empty() && pending.front().t_s < t_s_ - config_.filter.history_s) {
    pending.pop_front();
    ++counts_.fixes_unmatched;
  }
}

void P2Navigator::on_report(const state::StateReport& r) {
  const int j = static_cast<int>(r.vehicle_id) - 1;
  if (j < 0 || j >= config_.vehicles || j == own_) {
    ++counts_.reports_unknown;
    return;
  }
  if (!r.attitude_valid || !r.covariance_valid) {
    ++counts_.reports_partial;
    return;
  }
  if (!timely(r.t_s)) {
    ++counts_.untimely;
    return;
  }
  const geodesy::Geodetic g{units::deg_to_rad(r.lat_deg), units::deg_to_rad(r.lon_deg),
                            -r.depth_m};
  const P2Vec x = state_of(g, r.heading_rad, r.pitch_rad);
  Track& peer = peers_[static_cast<std::size_t>(j)];
  auto& pending = pending_[static_cast<std::size_t>(j)];
  if (!peer.started) {
    if (!filter_.init_vehicle(r.t_s, j, x, r.covariance)) {
      ++counts_.reports_partial;
      return;
    }
    ++counts_.reports;
    peer = {true, r.t_s, x};
    // Fixes before the peer's first state cannot be compared with anything.
    while (!pending.empty() && pending.front().t_s < r.t_s) {
      pending.pop_front();
      ++counts_.fixes_unmatched;
    }
    return;
  }
  const double dt = r.t_s - peer.t_s;
  if (!(dt > 0.0)) {
    ++counts_.reports_stale;
    return;
  }
  ++counts_.reports;
  // The increment since the previous report, cut at the pending fixes of this peer inside
  // it (linear in between), each fix given after the increment up to its emission.
  const P2Vec dx = difference(x, peer.x);
  double t_from = peer.t_s;
  while (!pending.empty() && pending.front().t_s <= r.t_s) {
    const PendingFix& f = pending.front();
    if (f.t_s > t_from) {
      filter_.increment(f.t_s, j, dx * ((f.t_s - t_from) / dt), f.t_s - t_from);
      t_from = f.t_s;
    }
    filter_.fix(f.t_s, f.m);
    pending.pop_front();
  }
  if (r.t_s > t_from) filter_.increment(r.t_s, j, dx * ((r.t_s - t_from) / dt), r.t_s - t_from);
  peer = {true, r.t_s, x};
}

estimator::NavSolution P2Navigator::solution() const {
  estimator::NavSolution s = nav_.solution();
  if (!own_track_.started) {  // started only once the filter took the own block
    s.position_valid = false;
    return s;
  }
  const P2Vec x = filter_.ekf().state(own_);
  s.p_n = x.segment<3>(P2Slice::kPos);
  s.position = plane_.to_geodetic(s.p_n);
  Euler e = euler_from_quat(s.q_nb);
  e.yaw = x(P2Slice::kPsi);
  e.pitch = x(P2Slice::kTheta);
  s.q_nb = quat_from_euler(e);
  s.p_std_m = filter_.ekf().covariance(own_).diagonal().head<3>().cwiseMax(0.0).cwiseSqrt();
  return s;
}

std::optional<Mat3> P2Navigator::position_covariance() const {
  if (!own_track_.started) return std::nullopt;
  return filter_.ekf().covariance(own_).topLeftCorner<3, 3>();
}

std::optional<state::StateReport> P2Navigator::own_report() const {
  if (!own_track_.started) return std::nullopt;
  const estimator::NavSolution s = nav_.solution();
  state::StateReport r;
  r.vehicle_id = static_cast<std::uint8_t>(own_ + 1);
  r.t_s = own_track_.t_s;
  r.lat_deg = units::rad_to_deg(s.position.lat_rad);
  r.lon_deg = units::rad_to_deg(s.position.lon_rad);
  r.depth_m = -s.position.alt_m;
  r.heading_rad = own_track_.x(P2Slice::kPsi);
  r.pitch_rad = own_track_.x(P2Slice::kTheta);
  r.attitude_valid = true;
  r.covariance_valid = true;
  r.covariance = P_nav_;
  if (!state::encodable(r)) return std::nullopt;
  return r;
}

}  // namespace nav::dut

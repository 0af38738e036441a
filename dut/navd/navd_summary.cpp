// SPDX-License-Identifier: MIT
// navd's exit summary: the one line on stderr with every port's counters
// (docs/dut-contract.md §7).
#include <string>

#include "navd_app.hpp"

namespace nav::dut {
namespace {

std::string rejects_text(const RejectCounts& r) {
  return "checksum=" + std::to_string(r.checksum) + " framing=" + std::to_string(r.framing) +
         " sync_bytes=" + std::to_string(r.sync_bytes) +
         " overflow_bytes=" + std::to_string(r.overflow_bytes);
}

}  // namespace

std::string NavdApp::stats_line(const std::string& reason) const {
  std::string s = "navd: stopped (" + reason + "): ahrs packets=" +
                  std::to_string(ahrs_decoder_.messages()) + " rejects{" +
                  rejects_text(ahrs_decoder_.rejects()) + "}";
  if (gps_) {
    s += "; gps sentences=" + std::to_string(gps_decoder_.messages()) +
         " gga=" + std::to_string(gps_counts_.gga) + " rmc=" + std::to_string(gps_counts_.rmc) +
         " vtg=" + std::to_string(gps_counts_.vtg) + " hdt=" + std::to_string(gps_counts_.hdt) +
         " zda=" + std::to_string(gps_counts_.zda) + " other=" + std::to_string(gps_counts_.other) +
         " no_fix=" + std::to_string(gps_counts_.no_fix) +
         " incomplete=" + std::to_string(gps_counts_.incomplete) +
         " bad_fields=" + std::to_string(gps_counts_.bad_fields) + " rejects{" +
         rejects_text(gps_decoder_.rejects()) + "}";
  }
  for (const auto& e : extras_) {
    s += "; input " + e.input.name() + "=" + std::string(protocol_name(e.input.protocol())) +
         " " + e.input.counters_text();
    if (e.poller) {
      s += " poll{" + e.poller->counters_text() +
           " write_errors=" + std::to_string(e.write_errors) + "}";
    }
  }
  if (modem_link_) {
    s += "; modem{" + modem_link_->counters_text() +
         " id=" + std::to_string(modem_link_->vehicle_id()) + "}";
  }
  if (state_link_) {
    s += "; modem{" + state_link_->counters_text() +
         " id=" + std::to_string(state_link_->vehicle_id()) + "}";
  }
  if (can_) {
    s += "; can{iface=" + can_->socket.ifname() + " " + can_->input.counters_text() + "}";
  }
  s += "; solutions written=" + std::to_string(out_.written()) +
       " dropped=" + std::to_string(out_.dropped()) +
       " unsent=" + std::to_string(out_.queued());
  if (p1_nav_) {
    const auto& d = p1_nav_->stats();
    const auto& nav = p1_nav_->navigator().stats();
    s += "; " + std::string(p1_nav_->navigator().name()) +
         " imu_samples=" + std::to_string(nav.imu_samples) +
         " imu_invalid=" + std::to_string(nav.imu_rejected_invalid) +
         " dt_resets=" + std::to_string(d.dt_resets) +
         " gps_fused=" + std::to_string(nav.gps_fused) +
         " gps_rejected=" + std::to_string(nav.gps_rejected_invalid + nav.gps_rejected_gate) +
         " gps_queue_dropped=" + std::to_string(d.gps_queue_dropped) +
         " mag_fused=" + std::to_string(nav.mag_fused) +
         " gravity_fused=" + std::to_string(nav.gravity_fused) +
         " numerical_faults=" + std::to_string(nav.numerical_faults);
    return s;
  }
  if (p3_nav_) {
    const P3NavigatorCounts& c = p3_nav_->counts();
    s += "; " + std::string(p3_method_name(p3_nav_->config().method)) +
         " steps=" + std::to_string(c.steps) + " updates=" + std::to_string(c.updates) +
         " x_used=" + std::to_string(c.x_used) +
         " gated=" + std::to_string(p3_nav_->kinematic().gated()) +
         " reseeds=" + std::to_string(p3_nav_->kinematic().reseeds()) +
         " depths=" + std::to_string(c.depths) +
         " steep_pitch=" + std::to_string(c.steep_pitch) +
         " wheel_samples=" + std::to_string(c.wheel_samples) +
         " wheel_invalid=" + std::to_string(c.wheel_invalid) +
         " faults=" + std::to_string(c.faults) +
         " ebimu_wrong_length=" + std::to_string(p3_wrong_length_);
    return s;
  }
  if (p4_nav_) {
    const P4NavigatorCounts& c = p4_nav_->counts();
    s += "; " + std::string(p4_method_name(p4_nav_->config().method)) +
         " frames=" + std::to_string(c.frames) +
         " frames_invalid=" + std::to_string(c.frames_invalid) +
         " dt_resets=" + std::to_string(c.dt_resets) + " fixes=" + std::to_string(c.fixes) +
         " gps_fused=" + std::to_string(c.gps_fused) +
         " gps_rejected=" + std::to_string(c.gps_rejected) +
         " compass_fused=" + std::to_string(c.compass_fused) +
         " compass_rejected=" + std::to_string(c.compass_rejected) +
         " velocity_fused=" + std::to_string(c.velocity_fused) +
         " velocity_rejected=" + std::to_string(c.velocity_rejected) +
         " predict_faults=" + std::to_string(c.predict_faults) +
         " denoised=" + std::to_string(c.denoised) +
         " startup_raw=" + std::to_string(c.startup_raw) +
         " latency_samples=" + std::to_string(p4_nav_->latency_samples());
    return s;
  }
  if (gps_nav_) {
    const auto& nav = gps_nav_->stats();
    s += "; filter ahrs_invalid=" + std::to_string(nav.ahrs_rejected_invalid) +
         " dt_resets=" + std::to_string(nav.dt_resets) +
         " gps_pos_fused=" + std::to_string(nav.gps_position_fused) +
         " gps_vel_fused=" + std::to_string(nav.gps_velocity_fused) +
         " gps_rejected=" + std::to_string(nav.gps_rejected_invalid + nav.gps_rejected_gate) +
         " depth_fused=" + std::to_string(nav.depth_fused) +
         " depth_unanchored=" + std::to_string(nav.depth_unanchored) +
         " depth_rejected=" + std::to_string(nav.depth_rejected_invalid) +
         " numerical_faults=" + std::to_string(nav.numerical_faults);
  } else {
    const estimator::DvlNavigator& dr = p2_nav_ ? p2_nav_->navigation() : *dvl_nav_;
    const auto& nav = dr.stats();
    s += "; dead_reckoning ahrs_invalid=" + std::to_string(nav.ahrs_rejected_invalid) +
         " dt_resets=" + std::to_string(nav.dt_resets) +
         " dvl_used=" + std::to_string(nav.dvl_used) +
         " dvl_superseded=" + std::to_string(nav.dvl_superseded) +
         " dvl_rejected=" + std::to_string(nav.dvl_rejected_invalid) +
         " stale_samples=" + std::to_string(nav.stale_samples) +
         " depth_used=" + std::to_string(nav.depth_used) +
         " depth_rejected=" + std::to_string(nav.depth_rejected_invalid);
    if (p2_nav_) {
      const P2NavigatorCounts& c = p2_nav_->counts();
      const estimator::P2TimedCounters f = p2_nav_->filter().counters();
      s += " gps_used=" + std::to_string(nav.gps_used) +
           " gps_ignored=" + std::to_string(nav.gps_ignored) +
           "; p2 fixes=" + std::to_string(c.fixes) + " fused=" + std::to_string(f.fixes_fused) +
           " refused=" + std::to_string(f.fixes_refused) +
           " bad=" + std::to_string(c.fixes_bad) + " unknown=" + std::to_string(c.fixes_unknown) +
           " early=" + std::to_string(c.fixes_early) +
           " behind_report=" + std::to_string(c.fixes_behind_report) +
           " unmatched=" + std::to_string(c.fixes_unmatched) +
           " reports=" + std::to_string(c.reports) +
           " reports_unknown=" + std::to_string(c.reports_unknown) +
           " reports_partial=" + std::to_string(c.reports_partial) +
           " reports_stale=" + std::to_string(c.reports_stale) +
           " untimely=" + std::to_string(c.untimely) +
           " reordered=" + std::to_string(f.reordered) +
           " too_late=" + std::to_string(f.too_late) + " invalid=" + std::to_string(f.invalid);
    }
  }
  const estimator::AttitudeFilter& att =
      gps_nav_ ? gps_nav_->attitude()
               : (p2_nav_ ? p2_nav_->navigation().attitude() : dvl_nav_->attitude());
  const estimator::AttitudeStats& a = att.stats();
  s += "; attitude " + std::string(estimator::attitude_filter_name(att.kind())) +
       " steps=" + std::to_string(a.steps) +
       " rejected_invalid=" + std::to_string(a.rejected_invalid) +
       " numerical_faults=" + std::to_string(a.numerical_faults) +
       " singular=" + std::to_string(a.singular) +
       " accel_rejected=" + std::to_string(a.accel_rejected) +
       " mag_rejected=" + std::to_string(a.mag_rejected);
  return s;
}

}  // namespace nav::dut

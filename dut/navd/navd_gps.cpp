// SPDX-License-Identifier: MIT
// navd's GPS port: each decoded NMEA sentence counted, and the fixes handed to the navigator
// that uses them (gps-ins: position and velocity; P1: position; p2: the start of the dead
// reckoning; P4: the RMC's position and speed/course).
#include "navd_app.hpp"

#include "nav/common/units.hpp"

namespace nav::dut {

void NavdApp::handle_gps(const protocols::nmea::Sentence& s) {
  namespace nmea = protocols::nmea;
  if (s.type == "GGA") {
    const auto gga = nmea::decode_gga(s);
    if (!gga) {
      ++gps_counts_.bad_fields;
      return;
    }
    ++gps_counts_.gga;
    if (gga->quality == 0) {
      ++gps_counts_.no_fix;
      return;
    }
    if (!gga->lat_deg || !gga->lon_deg || !gga->alt_msl_m) {
      ++gps_counts_.incomplete;
      return;
    }
    estimator::GpsPosition fix;
    fix.position.lat_rad = units::deg_to_rad(*gga->lat_deg);
    fix.position.lon_rad = units::deg_to_rad(*gga->lon_deg);
    fix.position.alt_m = *gga->alt_msl_m;
    if (gps_nav_) gps_nav_->add_gps_position(fix);
    if (p1_nav_) p1_nav_->add_gps_position(fix);
    if (p2_nav_) p2_nav_->add_gps_position(fix);
  } else if (s.type == "RMC") {
    const auto rmc = nmea::decode_rmc(s);
    if (!rmc) {
      ++gps_counts_.bad_fields;
      return;
    }
    ++gps_counts_.rmc;
    if (!rmc->valid) {
      ++gps_counts_.no_fix;
      return;
    }
    if (p4_nav_) {
      // Paper P4's GPS is RMC (GPRMC): its position on the datum's plane, and its speed and
      // course when the receiver gave them (the navigator fuses them with p4_rmc_velocity).
      if (!rmc->lat_deg || !rmc->lon_deg) {
        ++gps_counts_.incomplete;
        return;
      }
      p4_nav_->on_gps(p4_nav_->rmc_fix(*rmc));
      return;
    }
    if (!rmc->sog_kn || !rmc->cog_deg) {
      ++gps_counts_.incomplete;  // receivers leave COG empty when barely moving
      return;
    }
    estimator::GpsVelocity fix;
    fix.sog_mps = *rmc->sog_kn * units::kKnotToMps;
    fix.cog_rad = units::deg_to_rad(*rmc->cog_deg);
    if (gps_nav_) gps_nav_->add_gps_velocity(fix);
  } else if (s.type == "VTG") {
    // Counted only: RMC supplies SOG/COG, and a receiver sending both would fuse twice.
    if (nmea::decode_vtg(s)) {
      ++gps_counts_.vtg;
    } else {
      ++gps_counts_.bad_fields;
    }
  } else if (s.type == "HDT") {
    if (const auto hdt = nmea::decode_hdt(s)) {
      ++gps_counts_.hdt;
      if (hdt->heading_deg) last_heading_deg_ = hdt->heading_deg;
    } else {
      ++gps_counts_.bad_fields;
    }
  } else if (s.type == "ZDA") {
    if (nmea::decode_zda(s)) {
      ++gps_counts_.zda;
    } else {
      ++gps_counts_.bad_fields;
    }
  } else {
    ++gps_counts_.other;
  }
}

}  // namespace nav::dut

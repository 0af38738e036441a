// SPDX-License-Identifier: MIT
#include "navd_app.hpp"

#include <poll.h>
#include <sys/signalfd.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>

#include "nav/common/frames.hpp"
#include "nav/common/units.hpp"
#include "nav/protocols/navd_solution.hpp"

namespace nav::dut {
namespace {

static_assert(estimator::kAhrsTicksPerSecond == protocols::gx3::kTicksPerSecond,
              "navigator and codec must agree on the GX3 timer rate");

Vec3 to_vec(const std::array<float, 3>& a) {
  return {static_cast<double>(a[0]), static_cast<double>(a[1]), static_cast<double>(a[2])};
}

/// SI sample from a 0xCB packet (unit conversion at the codec boundary).
estimator::AhrsSample to_sample(const protocols::gx3::AccelRateMag& m) {
  estimator::AhrsSample s;
  s.timer_ticks = m.timer_ticks;
  s.omega_b_radps = to_vec(m.rate_radps);
  s.f_b_mps2 = to_vec(m.accel_g) * units::kStandardGravity;
  s.m_b_tesla = to_vec(m.mag_gauss) * units::kGaussToTesla;
  return s;
}

/// The $PNVBSOL of the navigator's estimate. A non-finite or out-of-range estimate is
/// reported as DEGRADED with empty position fields rather than as numbers.
protocols::navd::Solution to_solution(const estimator::NavSolution& nav, std::uint32_t tag,
                                      std::uint64_t seq) {
  protocols::navd::Solution s;
  s.input = "AHRS";
  s.trigger_tag = tag;
  s.seq = seq;
  s.status = nav.position_valid ? "OK" : "ALIGNING";
  const Euler e = euler_from_quat(nav.q_nb);
  if (std::isfinite(e.roll) && std::isfinite(e.pitch) && std::isfinite(e.yaw)) {
    s.roll_deg = units::rad_to_deg(e.roll);
    s.pitch_deg = units::rad_to_deg(e.pitch);
    s.yaw_deg = units::rad_to_deg(e.yaw);
  } else {
    s.status = "DEGRADED";
  }
  if (nav.position_valid) {
    s.lat_deg = units::rad_to_deg(nav.position.lat_rad);
    s.lon_deg = units::rad_to_deg(nav.position.lon_rad);
    s.depth_m = -nav.position.alt_m;
    s.vn_mps = nav.v_n.x();
    s.ve_mps = nav.v_n.y();
    s.vd_mps = nav.v_n.z();
    const bool finite = std::isfinite(s.lat_deg) && std::isfinite(s.lon_deg) &&
                        std::isfinite(s.depth_m) && nav.v_n.allFinite();
    if (finite && std::abs(s.lat_deg) <= 90.0 && std::abs(s.lon_deg) <= 180.0) {
      s.position_valid = true;
    } else {
      s.status = "DEGRADED";
    }
  }
  return s;
}

/// The codec's view of a received SocketCAN frame.
protocols::can::Frame to_can_frame(const transport::CanFrame& f) {
  protocols::can::Frame out;
  out.id = f.id;
  out.extended = f.extended;
  out.rtr = f.rtr;
  out.dlc = f.dlc;
  out.data = f.data;
  return out;
}

std::string rejects_text(const RejectCounts& r) {
  return "checksum=" + std::to_string(r.checksum) + " framing=" + std::to_string(r.framing) +
         " sync_bytes=" + std::to_string(r.sync_bytes) +
         " overflow_bytes=" + std::to_string(r.overflow_bytes);
}

}  // namespace

NavdApp::NavdApp(const NavdOptions& options, const NavdConfig& config,
                 transport::SerialPort ahrs, std::optional<transport::SerialPort> gps,
                 std::vector<ExtraPort> extras, std::optional<transport::SerialPort> modem,
                 std::optional<CanPort> can, transport::SerialPort output, int signal_fd)
    : options_(options),
      ahrs_(std::move(ahrs)),
      gps_(std::move(gps)),
      output_(std::move(output)),
      signal_fd_(signal_fd),
      gps_open_(gps_.has_value()),
      ahrs_decoder_(&protocols::gx3::parse, protocols::gx3::kCmdAccelRateMag, kInputBufferBytes),
      gps_decoder_(&protocols::nmea::parse, static_cast<std::uint8_t>('$'), kInputBufferBytes),
      out_(output_, kOutputQueueBytes),
      params_(config.filter),
      can_(std::move(can)),
      can_open_(can_.has_value()) {
  const estimator::FilterParams& params = config.filter;
  if (config.navigator == NavigatorKind::kDvl) {
    dvl_nav_.emplace(params, config.attitude);
  } else {
    gps_nav_.emplace(params, config.attitude);
  }
  if (modem) {
    modem_ = std::move(modem);
    modem_open_ = true;
    modem_link_.emplace(static_cast<std::uint8_t>(options.vehicle_id),
                        config.navd.modem_period_s, kInputBufferBytes);
  }
  extras_.reserve(extras.size());
  for (auto& e : extras) {
    Extra x{std::move(e.port), AidingInput(e.spec.name, e.spec.protocol, kInputBufferBytes),
            true, std::nullopt, 0};
    if (e.spec.protocol == InputProtocol::kKeller) x.poller.emplace(params.depth_poll_period_s);
    extras_.push_back(std::move(x));
  }
}

void NavdApp::write_request(Extra& e, const protocols::Bytes& request) {
  if (request.empty() || !e.open) return;
  // A request is a few bytes on an otherwise idle line: it fits unless nobody reads the bus.
  // A short write garbles this request only (the device drops it by CRC); it then times out.
  auto n = e.port.write_some(request);
  if (!n || *n != request.size()) ++e.write_errors;
}

void NavdApp::handle_keller_answers() {
  for (auto& e : extras_) {
    if (!e.poller) continue;
    for (const auto& answer : e.input.take_keller_answers()) {
      if (const auto p1_bar = e.poller->on_answer(answer)) {
        const double depth_m = depth_from_p1_bar(*p1_bar, params_.depth_atmosphere_pa,
                                                 params_.depth_density_kgpm3);
        if (gps_nav_) gps_nav_->add_depth(depth_m);
        if (dvl_nav_) dvl_nav_->add_depth(depth_m);
      }
    }
  }
}

void NavdApp::handle_dvl_velocities() {
  for (auto& e : extras_) {
    if (!e.input.is_dvl()) continue;
    const auto v = e.input.take_velocity();
    if (v && dvl_nav_) dvl_nav_->add_dvl_velocity(Vec3((*v)[0], (*v)[1], (*v)[2]));
  }
}

estimator::NavSolution NavdApp::nav_solution() const {
  return gps_nav_ ? gps_nav_->solution() : dvl_nav_->solution();
}

estimator::AttitudeStatus NavdApp::attitude_status() const {
  return gps_nav_ ? gps_nav_->last_attitude_status() : dvl_nav_->last_attitude_status();
}

void NavdApp::write_modem(const std::string& sentence) {
  if (sentence.empty()) return;
  bool whole = false;
  if (modem_open_) {
    // One report every modem_period_s (~60 bytes): the line takes it unless nobody reads it
    // (or a real modem stopped reading its serial side). Never wait: a short write garbles
    // this report only (receivers drop it by checksum), and it counts as dropped.
    const auto bytes = std::span(reinterpret_cast<const std::uint8_t*>(sentence.data()),
                                 sentence.size());
    const auto n = modem_->write_some(bytes);
    if (!n) {
      std::fprintf(stderr, "navd: modem closed: %s\n", n.error().detail.c_str());
      modem_open_ = false;
    } else {
      whole = *n == sentence.size();
    }
  }
  modem_link_->on_written(whole);
}

void NavdApp::handle_modem_bytes(protocols::ByteSpan bytes) {
  for (const auto& p : modem_link_->feed(bytes)) {
    std::fprintf(stderr,
                 "navd: modem peer %u t=%.3f s lat=%.6f lon=%.6f depth=%.2f m std=%.1f m\n",
                 static_cast<unsigned>(p.vehicle_id), p.t_s, p.lat_deg, p.lon_deg, p.depth_m,
                 p.horizontal_std_m);
  }
}

void NavdApp::read_can() {
  for (std::size_t n = 0; can_open_ && n < kCanFramesPerWake; ++n) {
    auto r = can_->socket.receive();
    if (!r) {
      std::fprintf(stderr, "navd: CAN closed: %s\n", r.error().detail.c_str());
      can_open_ = false;
      break;
    }
    if (!*r) break;  // nothing waiting
    can_->input.feed(to_can_frame((*r)->frame));
  }
}

template <typename Sink>
void NavdApp::read_port(transport::SerialPort& port, bool& open, Sink&& sink) {
  std::array<std::uint8_t, 4096> chunk{};
  std::size_t total = 0;
  while (open && total < kReadPerWakeBytes) {
    auto n = port.read_some(chunk);
    if (!n) {
      std::fprintf(stderr, "navd: input closed: %s\n", n.error().detail.c_str());
      open = false;
      break;
    }
    if (*n == 0) break;  // EAGAIN: everything readable now has been read
    total += *n;
    sink(protocols::ByteSpan(chunk.data(), *n));
  }
}

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

bool NavdApp::signal_pending(int timeout_ms) {
  pollfd p{signal_fd_, POLLIN, 0};
  if (::poll(&p, 1, timeout_ms) > 0 && (p.revents & POLLIN) != 0) {
    signalfd_siginfo info{};
    if (::read(signal_fd_, &info, sizeof info) == static_cast<ssize_t>(sizeof info)) {
      const char* name = sigabbrev_np(static_cast<int>(info.ssi_signo));
      stop_reason_ = std::string("SIG") + (name != nullptr ? name : "?");
    } else {
      stop_reason_ = "signal";
    }
    return true;
  }
  return false;
}

bool NavdApp::wait_delay() {
  if (options_.delay_ms <= 0) return true;
  // Sleeping on the signalfd keeps SIGTERM prompt even with a long delay.
  return !signal_pending(options_.delay_ms);
}

bool NavdApp::handle_ahrs(const protocols::gx3::AccelRateMag& m) {
  // Requests due at this sample go out before its solution (lockstep: see navd_app.hpp).
  for (auto& e : extras_) {
    if (e.poller) write_request(e, e.poller->on_ahrs(m.timer_ticks));
  }
  if (gps_nav_) gps_nav_->on_ahrs(to_sample(m));
  if (dvl_nav_) dvl_nav_->on_ahrs(to_sample(m));
  const estimator::NavSolution nav = nav_solution();
  // The position report due at this sample, from its estimate, also before its solution.
  if (modem_link_) write_modem(modem_link_->on_ahrs(m.timer_ticks, nav));
  auto solution = to_solution(nav, m.timer_ticks, seq_++);
  // A numerical fault of the attitude filter at this sample (recovered) is reported.
  if (attitude_status() == estimator::AttitudeStatus::kNumericalFault) {
    solution.status = "DEGRADED";
  }
  if (!wait_delay()) return false;
  if (auto ok = out_.push(protocols::navd::encode(solution)); !ok) {
    stop_reason_ = "output closed: " + ok.error().detail;
    return false;
  }
  return true;
}

std::string NavdApp::run() {
  std::vector<protocols::gx3::AccelRateMag> ahrs_msgs;
  std::vector<protocols::nmea::Sentence> gps_msgs;
  constexpr std::size_t kFixedFds = 6;
  std::vector<pollfd> fds;
  // Keller sensors are initialised as soon as navd runs (the bench answers a request made
  // during the DUT's start-up as at scenario time 0).
  for (auto& e : extras_) {
    if (e.poller) write_request(e, e.poller->start());
  }
  while (stop_reason_.empty()) {
    // Index 0 signals, 1 AHRS, 2 GPS, 3 output, 4 modem, 5 CAN, 6.. the --input ports; a
    // closed input is skipped (fd -1).
    fds.resize(kFixedFds + extras_.size());
    fds[0] = {signal_fd_, POLLIN, 0};
    fds[1] = {ahrs_open_ ? ahrs_.fd() : -1, POLLIN, 0};
    fds[2] = {gps_open_ ? gps_->fd() : -1, POLLIN, 0};
    fds[3] = {output_.fd(), static_cast<short>(out_.empty() ? 0 : POLLOUT), 0};
    fds[4] = {modem_open_ ? modem_->fd() : -1, POLLIN, 0};
    fds[5] = {can_open_ ? can_->socket.fd() : -1, POLLIN, 0};
    for (std::size_t i = 0; i < extras_.size(); ++i) {
      fds[kFixedFds + i] = {extras_[i].open ? extras_[i].port.fd() : -1, POLLIN, 0};
    }
    if (::poll(fds.data(), fds.size(), -1) < 0) {
      if (errno == EINTR) continue;
      stop_reason_ = std::string("poll failed: ") + std::strerror(errno);
      break;
    }
    if ((fds[0].revents & POLLIN) != 0 && signal_pending(0)) break;

    constexpr short kReadable = POLLIN | POLLHUP | POLLERR | POLLNVAL;
    ahrs_msgs.clear();
    gps_msgs.clear();
    // Trigger port first: aiding bytes that preceded a trigger seen now are readable below.
    if ((fds[1].revents & kReadable) != 0) {
      read_port(ahrs_, ahrs_open_,
                [&](protocols::ByteSpan b) { ahrs_decoder_.feed(b, ahrs_msgs); });
    }
    if ((fds[2].revents & kReadable) != 0) {
      read_port(*gps_, gps_open_, [&](protocols::ByteSpan b) { gps_decoder_.feed(b, gps_msgs); });
    }
    // --input messages are handled (counted, kept) as they decode: before any AHRS packet.
    for (std::size_t i = 0; i < extras_.size(); ++i) {
      if ((fds[kFixedFds + i].revents & kReadable) == 0) continue;
      Extra& e = extras_[i];
      read_port(e.port, e.open, [&e](protocols::ByteSpan b) { e.input.feed(b); });
    }
    // CAN frames are decoded and counted as they are read (not fused): before any AHRS packet.
    if ((fds[5].revents & kReadable) != 0) read_can();
    // Peer reports are only counted, kept and logged: their order against AHRS is moot.
    if ((fds[4].revents & kReadable) != 0) {
      read_port(*modem_, modem_open_, [this](protocols::ByteSpan b) { handle_modem_bytes(b); });
    }

    for (const auto& s : gps_msgs) handle_gps(s);
    handle_keller_answers();
    handle_dvl_velocities();
    for (const auto& m : ahrs_msgs) {
      if (!handle_ahrs(m)) break;
    }
    if (!stop_reason_.empty()) break;

    if ((fds[3].revents & (POLLHUP | POLLERR | POLLNVAL)) != 0) {
      stop_reason_ = "output hang-up";
      break;
    }
    if (auto ok = out_.flush(); !ok) {
      stop_reason_ = "output closed: " + ok.error().detail;
      break;
    }
    const bool extra_open =
        std::any_of(extras_.begin(), extras_.end(), [](const Extra& e) { return e.open; });
    if (!ahrs_open_ && !gps_open_ && !extra_open && !modem_open_ && !can_open_) {
      stop_reason_ = "all inputs closed";
    }
  }
  (void)out_.flush();  // best effort, never blocking
  if (ahrs_open_) {
    // Stop the GX3's continuous mode (no reply); best effort, never blocking.
    (void)ahrs_.write_some(protocols::gx3::encode_stop_continuous());
  }
  return stop_reason_;
}

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
  if (can_) {
    s += "; can{iface=" + can_->socket.ifname() + " " + can_->input.counters_text() + "}";
  }
  s += "; solutions written=" + std::to_string(out_.written()) +
       " dropped=" + std::to_string(out_.dropped()) +
       " unsent=" + std::to_string(out_.queued());
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
    const auto& nav = dvl_nav_->stats();
    s += "; dead_reckoning ahrs_invalid=" + std::to_string(nav.ahrs_rejected_invalid) +
         " dt_resets=" + std::to_string(nav.dt_resets) +
         " dvl_used=" + std::to_string(nav.dvl_used) +
         " dvl_superseded=" + std::to_string(nav.dvl_superseded) +
         " dvl_rejected=" + std::to_string(nav.dvl_rejected_invalid) +
         " stale_samples=" + std::to_string(nav.stale_samples) +
         " depth_used=" + std::to_string(nav.depth_used) +
         " depth_rejected=" + std::to_string(nav.depth_rejected_invalid);
  }
  const estimator::AttitudeFilter& att =
      gps_nav_ ? gps_nav_->attitude() : dvl_nav_->attitude();
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

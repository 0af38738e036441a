// SPDX-License-Identifier: MIT
#include "navd_app.hpp"

#include <systemd/sd-daemon.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "nav/common/ensure.hpp"
#include "nav/common/frames.hpp"
#include "nav/common/units.hpp"
#include "nav/protocols/navd_solution.hpp"
#include "solution_covariance.hpp"

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

/// The codec's view of a received SocketCAN frame.
protocols::can::Frame to_can_frame(const transport::CanFrame& f) {
  protocols::can::Frame out;
  out.id = f.id;
  out.extended = f.extended;
  out.rtr = f.rtr;
  out.error = f.error;
  out.dlc = f.dlc;
  out.data = f.data;
  return out;
}

}  // namespace

protocols::navd::Solution to_solution(const estimator::NavSolution& nav, std::uint64_t tag,
                                      std::uint64_t seq, const char* input) {
  protocols::navd::Solution s;
  s.input = input;
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

using Wait = DescriptorWatch::WaitType;

NavdApp::NavdApp(boost::asio::io_context& io, boost::asio::signal_set& signals,
                 const NavdOptions& options, const NavdConfig& config,
                 std::optional<transport::SerialPort> ahrs,
                 std::optional<transport::SerialPort> gps,
                 std::vector<ExtraPort> extras, std::optional<transport::SerialPort> modem,
                 std::optional<CanPort> can, transport::SerialPort output)
    : io_(io),
      signals_(signals),
      delay_timer_(io),
      options_(options),
      ahrs_(std::move(ahrs)),
      gps_(std::move(gps)),
      output_(std::move(output)),
      output_watch_(io, output_.fd()),
      ahrs_open_(ahrs_.has_value()),
      gps_open_(gps_.has_value()),
      ahrs_decoder_(&protocols::gx3::parse, protocols::gx3::kCmdAccelRateMag, kInputBufferBytes),
      gps_decoder_(&protocols::nmea::parse, static_cast<std::uint8_t>('$'), kInputBufferBytes),
      out_(output_, kOutputQueueBytes),
      params_(config.filter),
      can_(std::move(can)),
      can_open_(can_.has_value()) {
  if (ahrs_) ahrs_watch_.emplace(io, ahrs_->fd());
  if (gps_) gps_watch_.emplace(io, gps_->fd());
  if (can_) can_watch_.emplace(io, can_->socket.fd());
  const estimator::FilterParams& params = config.filter;
  if (config.navigator == NavigatorKind::kDvl) {
    dvl_nav_.emplace(params, config.attitude);
  } else if (config.navigator == NavigatorKind::kP1) {
    // main() checked the name and the parameters when it loaded the config.
    auto nav = estimator::make_p1_navigator(config.p1_navigator, config.p1);
    NAV_ENSURE(nav.has_value(), "navd: a P1 navigator from a checked config");
    const geodesy::Geodetic origin{units::deg_to_rad(params.origin_lat_deg),
                                   units::deg_to_rad(params.origin_lon_deg),
                                   -params.origin_depth_m};
    p1_nav_.emplace(std::move(*nav), origin, config.p1.max_dt_s);
  } else if (config.navigator == NavigatorKind::kP2) {
    // main() checked the config and that --vehicle-id is one of the p2 vehicles.
    p2_nav_.emplace(params, config.attitude, config.p2, options.vehicle_id);
  } else if (config.navigator == NavigatorKind::kP3) {
    p3_nav_.emplace(params, config.p3);
  } else if (config.navigator == NavigatorKind::kP4) {
    p4_nav_.emplace(params, config.p4);
  } else {
    gps_nav_.emplace(params, config.attitude);
  }
  if (modem) {
    modem_ = std::move(modem);
    modem_watch_.emplace(io, modem_->fd());
    modem_open_ = true;
    const auto id = static_cast<std::uint8_t>(options.vehicle_id);
    if (p2_nav_) {
      state_link_.emplace(id, config.navd.modem_period_s, kInputBufferBytes);
    } else {
      modem_link_.emplace(id, config.navd.modem_period_s, kInputBufferBytes);
    }
  }
  extras_.reserve(extras.size());
  for (auto& e : extras) {
    auto watch = std::make_unique<DescriptorWatch>(io, e.port.fd());
    Extra x{std::move(e.port), std::move(watch),
            AidingInput(e.spec.name, e.spec.protocol, kInputBufferBytes), true, std::nullopt, 0};
    if (e.spec.protocol == InputProtocol::kKeller) x.poller.emplace(params.depth_poll_period_s);
    if (p3_nav_ && !p3_trigger_ && e.spec.protocol == InputProtocol::kEbimu) {
      p3_trigger_ = extras_.size();
    }
    if (p4_nav_ && !p4_trigger_ && e.spec.protocol == InputProtocol::kBeaconIns) {
      p4_trigger_ = extras_.size();
    }
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

void NavdApp::write_due_requests(std::uint32_t timer_ticks) {
  for (auto& e : extras_) {
    if (e.poller) write_request(e, e.poller->on_ahrs(timer_ticks));
  }
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
        if (p2_nav_) p2_nav_->add_depth(depth_m);
        if (p3_nav_) p3_nav_->add_depth(depth_m);
      }
    }
  }
}

void NavdApp::handle_dvl_velocities() {
  for (auto& e : extras_) {
    if (!e.input.is_dvl()) continue;
    const auto v = e.input.take_velocity();
    if (!v) continue;
    const Vec3 v_b((*v)[0], (*v)[1], (*v)[2]);
    if (dvl_nav_) dvl_nav_->add_dvl_velocity(v_b);
    if (p2_nav_) p2_nav_->add_dvl_velocity(v_b);
  }
}

void NavdApp::handle_p2() {
  for (auto& e : extras_) {
    for (const auto& f : e.input.take_relative_fixes()) {
      if (p2_nav_) p2_nav_->on_fix(f.position, f.attitude);
    }
  }
  for (const auto& r : reports_) {
    if (p2_nav_) p2_nav_->on_report(r);
  }
  reports_.clear();
}

estimator::NavSolution NavdApp::nav_solution() const {
  if (p3_nav_) return p3_nav_->solution();
  if (p4_nav_) return p4_nav_->solution();
  if (p1_nav_) return p1_nav_->solution();
  if (p2_nav_) return p2_nav_->solution();
  return gps_nav_ ? gps_nav_->solution() : dvl_nav_->solution();
}

estimator::AttitudeStatus NavdApp::attitude_status() const {
  if (p1_nav_ || p3_nav_ || p4_nav_) return estimator::AttitudeStatus::kOk;  // they count theirs
  if (p2_nav_) return p2_nav_->navigation().last_attitude_status();
  return gps_nav_ ? gps_nav_->last_attitude_status() : dvl_nav_->last_attitude_status();
}

bool NavdApp::write_modem(protocols::ByteSpan report) {
  if (!modem_open_) return false;
  // One report every modem_period_s (~60 bytes): the line takes it unless nobody reads it
  // (or a real modem stopped reading its serial side). Never wait: a short write garbles
  // this report only (receivers drop it by checksum or CRC), and it counts as dropped.
  const auto n = modem_->write_some(report);
  if (!n) {
    std::fprintf(stderr, "navd: modem closed: %s\n", n.error().detail.c_str());
    modem_open_ = false;
    return false;
  }
  return *n == report.size();
}

void NavdApp::handle_modem_bytes(protocols::ByteSpan bytes) {
  if (state_link_) {
    for (auto& r : state_link_->feed(bytes)) reports_.push_back(r);
    return;
  }
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

bool NavdApp::wait_delay() {
  if (options_.delay_ms <= 0) return true;
  // Sleeping on the io_context keeps SIGTERM prompt even with a long delay. Port handlers
  // that run meanwhile only mark their ports for the next wake-up.
  delay_over_ = false;
  delay_timer_.expires_after(std::chrono::milliseconds(options_.delay_ms));
  delay_timer_.async_wait([this](const boost::system::error_code& ec) {
    if (!ec) delay_over_ = true;
  });
  while (!delay_over_ && stop_reason_.empty()) io_.run_one();
  if (!delay_over_) delay_timer_.cancel();
  return stop_reason_.empty();
}

bool NavdApp::handle_ahrs(const protocols::gx3::AccelRateMag& m) {
  write_due_requests(m.timer_ticks);
  if (gps_nav_) gps_nav_->on_ahrs(to_sample(m));
  if (dvl_nav_) dvl_nav_->on_ahrs(to_sample(m));
  if (p1_nav_) p1_nav_->on_ahrs(to_sample(m));
  if (p2_nav_) p2_nav_->on_ahrs(to_sample(m));
  const estimator::NavSolution nav = nav_solution();
  // The position report due at this sample, from its estimate, also before its solution.
  if (modem_link_) {
    const std::string report = modem_link_->on_ahrs(m.timer_ticks, nav);
    if (!report.empty()) {
      modem_link_->on_written(write_modem(std::span(
          reinterpret_cast<const std::uint8_t*>(report.data()), report.size())));
    }
  }
  if (state_link_) {
    const protocols::Bytes report = state_link_->on_ahrs(m.timer_ticks, p2_nav_->own_report());
    if (!report.empty()) state_link_->on_written(write_modem(report));
  }
  auto solution = to_solution(nav, m.timer_ticks, seq_++);
  // A numerical fault of the attitude filter at this sample (recovered) is reported.
  if (attitude_status() == estimator::AttitudeStatus::kNumericalFault) {
    solution.status = "DEGRADED";
  }
  // The innovations of the updates made at this sample, then its covariance when the
  // navigator keeps one (neither with a DEGRADED solution), then the solution, in one write:
  // the bench has them when the solution arrives, and a trigger costs one pty hand-off back
  // (docs/design-notes.md, campaign speed).
  std::string stated;
  if (p1_nav_) {
    stated = solution_innovations(m.timer_ticks, p1_nav_->innovations());
    if (const auto cov = solution_covariance(m.timer_ticks, p1_nav_->p1_solution())) {
      stated += protocols::navd::encode(*cov);
    }
  } else if (p2_nav_) {
    stated = solution_innovations(m.timer_ticks, p2_nav_->navigation().innovations());
    if (solution.status != "DEGRADED") {
      const auto cov = solution_covariance(m.timer_ticks, p2_nav_->position_covariance());
      if (cov) stated += protocols::navd::encode(*cov);
    }
  } else if (solution.status != "DEGRADED") {
    stated = solution_innovations(
        m.timer_ticks, gps_nav_ ? gps_nav_->innovations() : dvl_nav_->innovations());
    const auto cov = solution_covariance(
        m.timer_ticks, nav, gps_nav_ ? gps_nav_->attitude() : dvl_nav_->attitude(),
        gps_nav_ && gps_nav_->position_velocity() ? &*gps_nav_->position_velocity() : nullptr);
    if (cov) stated += protocols::navd::encode(*cov);
  }
  return answer(std::move(stated), solution);
}

bool NavdApp::answer(std::string stated, const protocols::navd::Solution& solution) {
  if (!wait_delay()) return false;
  stated += protocols::navd::encode(solution);
  if (auto ok = out_.push(std::move(stated)); !ok) {
    stop_reason_ = "output closed: " + ok.error().detail;
    return false;
  }
  return true;
}

void NavdApp::arm_waits() {
  if (ahrs_open_) ahrs_watch_->arm(Wait::wait_read);
  if (gps_open_) gps_watch_->arm(Wait::wait_read);
  for (auto& e : extras_) {
    if (e.open) e.watch->arm(Wait::wait_read);
  }
  if (can_open_) can_watch_->arm(Wait::wait_read);
  if (modem_open_) modem_watch_->arm(Wait::wait_read);
  output_watch_.arm(Wait::wait_error);
  if (!out_.empty()) output_watch_.arm(Wait::wait_write);
}

bool NavdApp::woken() const {
  const bool extra = std::any_of(extras_.begin(), extras_.end(),
                                 [](const Extra& e) { return e.watch->ready(Wait::wait_read); });
  return !stop_reason_.empty() || (ahrs_watch_ && ahrs_watch_->ready(Wait::wait_read)) || extra ||
         (gps_watch_ && gps_watch_->ready(Wait::wait_read)) ||
         (can_watch_ && can_watch_->ready(Wait::wait_read)) ||
         (modem_watch_ && modem_watch_->ready(Wait::wait_read)) ||
         output_watch_.ready(Wait::wait_error) || output_watch_.ready(Wait::wait_write);
}

void NavdApp::wait_for_wake() {
  // run_one() sleeps only while no handler is ready (one may be left from the --delay-ms
  // sleep), and may run one that marks nothing (the io_context's own bookkeeping); poll()
  // then runs every other handler ready now, so each ready port is marked. run_one() returns
  // 0 only with nothing left to wait for, which the signal wait rules out while navd runs.
  while (!woken() && io_.run_one() > 0) {
  }
  io_.poll();
}

void NavdApp::handle_wake() {
  ahrs_msgs_.clear();
  gps_msgs_.clear();
  // Every serial port is read at every wake, marked ready or not: a pty hands its input to
  // the reader through the kernel's flip-buffer work, so bytes the bench wrote before a
  // trigger may not be marked ready yet when the trigger wakes navd, while a read flushes
  // that work first (n_tty_read). The trigger's port first: aiding bytes that preceded a
  // trigger seen now are readable below (DUT contract §5).
  if (ahrs_watch_) {
    ahrs_watch_->take(Wait::wait_read);
    read_port(*ahrs_, ahrs_open_,
              [this](protocols::ByteSpan b) { ahrs_decoder_.feed(b, ahrs_msgs_); });
  }
  const std::optional<std::size_t> extra_trigger = p3_trigger_ ? p3_trigger_ : p4_trigger_;
  const auto read_extra = [this](std::size_t i) {
    auto& e = extras_[i];
    e.watch->take(Wait::wait_read);
    read_port(e.port, e.open, [&e](protocols::ByteSpan b) { e.input.feed(b); });
  };
  if (extra_trigger) read_extra(*extra_trigger);
  if (gps_watch_) {
    gps_watch_->take(Wait::wait_read);
    read_port(*gps_, gps_open_, [this](protocols::ByteSpan b) { gps_decoder_.feed(b, gps_msgs_); });
  }
  // --input messages are handled (counted, kept) as they decode: before any trigger.
  for (std::size_t i = 0; i < extras_.size(); ++i) {
    if (i != extra_trigger) read_extra(i);
  }
  // CAN frames are decoded and counted as they are read: before any trigger of this wake.
  // The socket is read at every wake too, marked ready or not (a receive that finds nothing
  // costs one system call): a readiness missed under load left frames waiting, the socket's
  // queue filled, and the frames after it were lost (a golden P3 run lost 35 s of wheels).
  if (can_watch_) {
    can_watch_->take(Wait::wait_read);
    read_can();
  }
  // $PNVBPOS are only counted, kept and logged: their order against AHRS is moot. State
  // reports (p2) wait for handle_p2(), after the iUSBL fixes of this wake.
  if (modem_watch_) {
    modem_watch_->take(Wait::wait_read);
    read_port(*modem_, modem_open_, [this](protocols::ByteSpan b) { handle_modem_bytes(b); });
  }

  for (const auto& s : gps_msgs_) handle_gps(s);
  handle_keller_answers();
  handle_dvl_velocities();
  handle_p2();
  handle_wheels();
  for (const auto& m : ahrs_msgs_) {
    if (!handle_ahrs(m)) return;
  }
  if (p3_trigger_) {
    for (const auto& line : extras_[*p3_trigger_].input.take_ebimu_lines()) {
      if (!handle_ebimu(line)) return;
    }
  }
  for (std::size_t i = 0; i < extras_.size(); ++i) {
    // Only the trigger's frames are answered; other beacon inputs' are dropped (counted).
    auto frames = extras_[i].input.take_beacon_frames();
    if (!p4_trigger_ || i != *p4_trigger_) continue;
    for (const auto& frame : frames) {
      if (!handle_beacon(frame)) return;
    }
  }

  (void)output_watch_.take(Wait::wait_write);  // flushed below whatever woke us
  if (output_watch_.take(Wait::wait_error)) {
    stop_reason_ = "output hang-up";
    return;
  }
  if (auto ok = out_.flush(); !ok) {
    stop_reason_ = "output closed: " + ok.error().detail;
    return;
  }
  const bool extra_open =
      std::any_of(extras_.begin(), extras_.end(), [](const Extra& e) { return e.open; });
  if (!ahrs_open_ && !gps_open_ && !extra_open && !modem_open_ && !can_open_) {
    stop_reason_ = "all inputs closed";
  }
}

std::string NavdApp::run() {
  // Keller sensors are initialised as soon as navd runs (the bench answers a request made
  // during the DUT's start-up as at scenario time 0).
  for (auto& e : extras_) {
    if (e.poller) write_request(e, e.poller->start());
  }
  signals_.async_wait([this](const boost::system::error_code& ec, int signal_number) {
    if (ec) return;  // cancelled: navd is stopping anyway
    const char* name = sigabbrev_np(signal_number);
    stop_reason_ = std::string("SIG") + (name != nullptr ? name : "?");
  });
  // Every port is open and configured: the bench may start sending (a lockstep run starts
  // at once instead of after the whole dut.startup). Nothing happens without NOTIFY_SOCKET.
  (void)sd_notify(0, "READY=1");
  while (stop_reason_.empty()) {
    arm_waits();
    wait_for_wake();
    if (!stop_reason_.empty()) break;  // a signal: before reading anything of this wake
    handle_wake();
  }
  (void)out_.flush();  // best effort, never blocking
  if (ahrs_open_) {
    // Stop the GX3's continuous mode (no reply); best effort, never blocking.
    (void)ahrs_->write_some(protocols::gx3::encode_stop_continuous());
  }
  return stop_reason_;
}

}  // namespace nav::dut

// SPDX-License-Identifier: MIT
// Crawler wheel encoder emulator (wheel_encoder_emulator.hpp).
//
// Reference: papers.md P3 (Heo, Lee, Kim 2013), differential-drive odometry, eq (3):
// delta_s = R (w_r + w_l) dT / 2, delta_theta = R (w_r - w_l) dT / b with theta positive to
// port (counter-clockwise seen from above). The truth's body frame is FRD, whose yaw rate
// r = omega_b.z is positive to STARBOARD, so with u = (R_nb^T v_n).x the forward body velocity:
//
//   v_l(t) = u + r b / 2,   v_r(t) = u - r b / 2                       wheel ground speed [m/s]
//   (the paper's v_l = v - w b/2, v_r = v + w b/2 with w = -r, the port-positive rate)
//   w_j(t) = (1 + slip_j(t)) v_j(t) / R                                 wheel rate [rad/s]
//   phi_j(t_k) = phi_j(t_{k-1}) + (1 + slip_j(t_{k-1})) / R * integral of v_j over
//                [t_{k-1}, t_k]   (composite Simpson on sub-steps of at most 5 ms, so the
//                angle is the integral of the truth to well below a tick), phi_j(0) = 0
//   TickCount_j(t_k) = (floor((phi_j(t_k) + s_a n_angle) cpr / 2 pi) + start_j) mod 2^32
//                      (cpr from the DBC; s_a the angle noise, read and not accumulated)
//   WheelSpeed_j(t_k) = w_j(t_k) + s_w n_speed, clipped to the signal's DBC range
//   MsgCounter_j = k mod 2^length (the DBC's counter length), Valid = 1
//   slip_j(t_k) = slip_j + walk_j(t_k), walk_j(0) = 0,
//   walk_j(t_k) = walk_j(t_{k-1}) + walk_std sqrt(t_k - t_{k-1}) n_walk
// Sample times t_k = k / rate (sample_times()), per wheel; rate = cfg.rate_hz or 1 / the
// wheel message's GenMsgCycleTime. Each frame is queued at t_k + latency.
//
// Draws: wheel j has its own engine, mt19937_64 seeded with device_seed(seed, DBC message
// name constant, "WheelEncoderLeft" / "WheelEncoderRight"); each frame draws n_walk (also at
// k = 0, where it advances nothing) then n_speed, also when a standard deviation is 0. The
// angle noise n_angle has an engine of its own per wheel (device_seed(seed, "<message>/angle")),
// drawn only when s_a > 0, so that streams made without it stay as they were.
//
// Slip acts on the wheel's rotation, so the encoder sees it in TickCount and WheelSpeed alike:
// a 5 % slip makes the ticks 5 % more than the ground distance needs.
#include "nav/emulators/wheel_encoder_emulator.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <string>

#include "nav/common/ensure.hpp"
#include "nav/common/frames.hpp"
#include "nav/emulators/device.hpp"

namespace nav::emulators {
namespace {

namespace we = protocols::wheel_encoder;

constexpr Duration kMaxSubStep{std::chrono::milliseconds(5)};  ///< Simpson sub-step bound

/// Ground speeds of the left and right wheel at t [m/s].
std::array<double, 2> wheel_speeds(const Truth& truth, Duration t, double track_m) {
  const TruthSample s = truth.at(t);
  const double u = (s.q_nb.conjugate() * s.v_n).x();
  const double r = s.omega_b.z();
  return {u + r * track_m / 2.0, u - r * track_m / 2.0};
}

/// Integral of wheel j's ground speed over [a, b] by composite Simpson [m].
double wheel_distance(const Truth& truth, Duration a, Duration b, double track_m,
                      std::size_t j) {
  if (b <= a) return 0.0;
  std::int64_t n = ((b - a).count() + kMaxSubStep.count() - 1) / kMaxSubStep.count();
  if (n % 2 != 0) ++n;
  const double h_s = to_seconds(b - a) / static_cast<double>(n);
  double sum = 0.0;
  for (std::int64_t i = 0; i <= n; ++i) {
    const Duration t = a + (b - a) * i / n;
    const double w = (i == 0 || i == n) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0);
    sum += w * wheel_speeds(truth, t, track_m)[j];
  }
  return sum * h_s / 3.0;
}

/// The codec's dbc::Frame as a classic CAN frame (the crawler DBC's DLC is 8).
protocols::can::Frame to_can(const protocols::dbc::Frame& f) {
  NAV_ENSURE(f.data.size() <= protocols::can::kMaxDataLength,
             "wheel encoder DBC message longer than a classic CAN frame");
  protocols::can::Frame c;
  c.id = f.id;
  c.extended = f.extended;
  c.dlc = static_cast<std::uint8_t>(f.data.size());
  std::copy(f.data.begin(), f.data.end(), c.data.begin());
  return c;
}

}  // namespace

std::vector<CanWireFrame> generate_wheel_encoders(const WheelEncoderConfig& cfg,
                                                  const we::WheelEncoderCodec& codec,
                                                  const Truth& truth,
                                                  Duration duration, std::uint64_t seed) {
  NAV_ENSURE(std::isfinite(cfg.wheel_radius_m) && cfg.wheel_radius_m > 0.0,
             "wheel encoder wheel_radius_m must be > 0");
  NAV_ENSURE(std::isfinite(cfg.track_width_m) && cfg.track_width_m > 0.0,
             "wheel encoder track_width_m must be > 0");
  NAV_ENSURE(!cfg.rate_hz || (std::isfinite(*cfg.rate_hz) && *cfg.rate_hz > 0.0),
             "wheel encoder rate_hz must be > 0");
  NAV_ENSURE(cfg.latency.count() >= 0, "wheel encoder latency must be >= 0");
  NAV_ENSURE(std::isfinite(cfg.speed_std_radps) && cfg.speed_std_radps >= 0.0,
             "wheel encoder speed_std_radps must be >= 0");
  NAV_ENSURE(std::isfinite(cfg.angle_std_rad) && cfg.angle_std_rad >= 0.0,
             "wheel encoder angle_std_rad must be >= 0");
  NAV_ENSURE(std::isfinite(cfg.slip.left) && std::isfinite(cfg.slip.right) &&
                 cfg.slip.left > -1.0 && cfg.slip.right > -1.0,
             "wheel encoder slip fractions must be finite and > -1");
  NAV_ENSURE(std::isfinite(cfg.slip.walk_std) && cfg.slip.walk_std >= 0.0,
             "wheel encoder slip walk_std must be >= 0");

  std::vector<CanWireFrame> out;
  for (const we::Wheel wheel : {we::Wheel::kLeft, we::Wheel::kRight}) {
    const bool left = wheel == we::Wheel::kLeft;
    const std::size_t j = left ? 0 : 1;
    std::mt19937_64 rng(device_seed(seed, left ? we::kLeftMessage : we::kRightMessage));
    std::mt19937_64 angle_rng(
        device_seed(seed, std::string(left ? we::kLeftMessage : we::kRightMessage) + "/angle"));
    const double rate_hz =
        cfg.rate_hz ? *cfg.rate_hz
                    : 1e3 / static_cast<double>(codec.cycle_time(wheel).count());
    const double counts_per_rad = 1.0 / codec.angle_per_tick(wheel);
    const std::uint32_t start = left ? cfg.start_ticks_left : cfg.start_ticks_right;
    const double slip0 = left ? cfg.slip.left : cfg.slip.right;
    const std::uint32_t counter_modulus = codec.counter_modulus(wheel);
    const protocols::dbc::Signal* speed_signal =
        codec.message(wheel).find_signal(we::kSpeedSignal);
    const bool speed_range = speed_signal->minimum != 0.0 || speed_signal->maximum != 0.0;

    double angle_rad = 0.0;
    double walk = 0.0;
    std::optional<Duration> t_prev;
    std::uint64_t k = 0;
    for (const Duration t : sample_times(rate_hz, duration)) {
      const double n_walk = standard_normal(rng);
      const double n_speed = standard_normal(rng);
      if (t_prev) {
        angle_rad += (1.0 + slip0 + walk) / cfg.wheel_radius_m *
                     wheel_distance(truth, *t_prev, t, cfg.track_width_m, j);
        walk += cfg.slip.walk_std * std::sqrt(to_seconds(t - *t_prev)) * n_walk;
      }
      t_prev = t;
      const double slip = slip0 + walk;

      we::WheelEncoderSample sample;
      sample.wheel = wheel;
      const double read_rad =
          angle_rad + (cfg.angle_std_rad > 0.0 ? cfg.angle_std_rad * standard_normal(angle_rng)
                                               : 0.0);
      const auto whole_ticks = static_cast<std::int64_t>(std::floor(read_rad * counts_per_rad));
      sample.ticks = static_cast<std::uint32_t>(whole_ticks) + start;  // mod 2^32
      double omega = (1.0 + slip) * wheel_speeds(truth, t, cfg.track_width_m)[j] /
                         cfg.wheel_radius_m +
                     cfg.speed_std_radps * n_speed;
      if (speed_range) omega = std::clamp(omega, speed_signal->minimum, speed_signal->maximum);
      sample.omega = omega;
      sample.counter = static_cast<std::uint8_t>(k % counter_modulus);
      sample.valid = true;
      const auto frame = codec.encode(sample);
      NAV_ENSURE(frame.has_value(), "wheel encoder frame does not fit the DBC: " +
                                        (frame ? std::string() : frame.error().detail));
      out.push_back(CanWireFrame{t, t + cfg.latency, to_can(*frame)});
      ++k;
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const CanWireFrame& a, const CanWireFrame& b) {
    return a.t_ready < b.t_ready;
  });
  return out;
}

}  // namespace nav::emulators

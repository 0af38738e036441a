// SPDX-License-Identifier: MIT
// The hand-guided truth kind (see hand_guided_truth.hpp for H1..H5).
#include "nav/emulators/hand_guided_truth.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <utility>

#include "nav/common/ensure.hpp"

namespace nav::emulators {
namespace {

std::string num(double v) {
  std::array<char, 32> buf{};
  std::snprintf(buf.data(), buf.size(), "%.6g", v);
  return buf.data();
}

/// A band's own checks; the error names it ("hand_guided.sway: ...").
Result<void> check_band(const char* name, const BandSpec& b) {
  const std::string where = std::string("hand_guided.") + name + ": ";
  if (!std::isfinite(b.rms) || b.rms < 0.0) {
    return fail(ErrorCode::kInvalidArgument, where + "rms must be finite and >= 0 (got " +
                                                 num(b.rms) + ")");
  }
  if (!std::isfinite(b.f_lo_hz) || !std::isfinite(b.f_hi_hz) || b.f_lo_hz <= 0.0 ||
      b.f_hi_hz < b.f_lo_hz) {
    return fail(ErrorCode::kInvalidArgument, where + "band must satisfy 0 < low <= high (got " +
                                                 num(b.f_lo_hz) + " Hz to " + num(b.f_hi_hz) +
                                                 " Hz)");
  }
  if (b.components < 1) {
    return fail(ErrorCode::kInvalidArgument, where + "needs at least one component");
  }
  return {};
}

}  // namespace

Result<HandGuidedTruth> HandGuidedTruth::build(std::shared_ptr<const Truth> nominal,
                                               const HandGuidedSpec& spec, std::uint64_t seed,
                                               double gravity_mps2, Duration horizon) {
  NAV_ENSURE(nominal != nullptr, "a hand-guided rig needs its nominal path");
  const std::array<std::pair<const char*, const BandSpec*>, 7> bands{{{"speed", &spec.speed},
                                                                      {"sway", &spec.sway},
                                                                      {"heave", &spec.heave},
                                                                      {"roll", &spec.roll},
                                                                      {"pitch", &spec.pitch},
                                                                      {"yaw", &spec.yaw},
                                                                      {"shake", &spec.shake}}};
  for (const auto& [name, band] : bands) {
    if (auto r = check_band(name, *band); !r) return tl::unexpected(r.error());
  }
  HandGuidedTruth h;
  h.nominal_ = std::move(nominal);
  h.gravity_mps2_ = gravity_mps2;
  std::mt19937_64 rng(seed);
  h.speed_ = BandLimitedSignal(spec.speed, rng);
  h.sway_n_ = BandLimitedSignal(spec.sway, rng);
  h.sway_e_ = BandLimitedSignal(spec.sway, rng);
  h.heave_ = BandLimitedSignal(spec.heave, rng);
  h.shake_n_ = BandLimitedSignal(spec.shake, rng);
  h.shake_e_ = BandLimitedSignal(spec.shake, rng);
  h.shake_d_ = BandLimitedSignal(spec.shake, rng);
  h.roll_ = BandLimitedSignal(spec.roll, rng);
  h.pitch_ = BandLimitedSignal(spec.pitch, rng);
  h.yaw_ = BandLimitedSignal(spec.yaw, rng);
  h.delta0_s_ = h.speed_.at(0.0).x;
  h.offset0_n_ = Vec3{h.sway_n_.at(0.0).x + h.shake_n_.at(0.0).x,
                      h.sway_e_.at(0.0).x + h.shake_e_.at(0.0).x,
                      h.heave_.at(0.0).x + h.shake_d_.at(0.0).x};

  // H1: the warped time must keep running forward (and so stays >= 0, as tau(0) = 0).
  if (spec.speed.rms > 0.0) {
    const double step_s = 1.0 / (20.0 * spec.speed.f_hi_hz);
    const double end_s = to_seconds(horizon);
    for (double t = 0.0; t <= end_s; t += step_s) {
      const double tau_dot = 1.0 + h.speed_.at(t).dx;
      if (tau_dot <= 0.0) {
        return fail(ErrorCode::kInvalidArgument,
                    "hand_guided.speed: a speed variation of rms " + num(spec.speed.rms) +
                        " stops the rig or runs it backwards at t = " + num(t) +
                        " s (this seed); lower its rms");
      }
    }
  }
  return h;
}

TruthSample HandGuidedTruth::at(Duration t) const {
  NAV_ENSURE(t.count() >= 0, "truth is defined for t >= 0 only");
  const double t_s = to_seconds(t);
  const SignalValue delta = speed_.at(t_s);
  const double tau_s = t_s + delta.x - delta0_s_;  // H1
  const double tau_dot = 1.0 + delta.dx;
  const double tau_ddot = delta.ddx;
  const TruthSample b = nominal_->at(from_seconds(std::max(tau_s, 0.0)));

  const SignalValue sn = sway_n_.at(t_s), se = sway_e_.at(t_s), sd = heave_.at(t_s);
  const SignalValue kn = shake_n_.at(t_s), ke = shake_e_.at(t_s), kd = shake_d_.at(t_s);
  const Vec3 d = Vec3{sn.x + kn.x, se.x + ke.x, sd.x + kd.x} - offset0_n_;
  const Vec3 d_dot{sn.dx + kn.dx, se.dx + ke.dx, sd.dx + kd.dx};
  const Vec3 d_ddot{sn.ddx + kn.ddx, se.ddx + ke.ddx, sd.ddx + kd.ddx};

  TruthSample out;
  out.t = t;
  out.p_n = b.p_n + d;                                                     // H2
  out.v_n = b.v_n * tau_dot + d_dot;
  out.a_n = b.a_n * tau_dot * tau_dot + b.v_n * tau_ddot + d_ddot;
  out.distance_m = b.distance_m;

  const SignalValue r = roll_.at(t_s), p = pitch_.at(t_s), y = yaw_.at(t_s);
  const Quat q_w = quat_from_euler(Euler{r.x, p.x, y.x});
  out.q_nb = b.q_nb * q_w;                                                 // H3
  out.omega_b = q_w.toRotationMatrix().transpose() * b.omega_b * tau_dot +  // H4
                euler_rate_to_body(r.x, p.x, Vec3{r.dx, p.dx, y.dx});

  const Vec3 g_n{0.0, 0.0, gravity_mps2_};
  out.f_b = out.q_nb.toRotationMatrix().transpose() * (out.a_n - g_n);     // H5
  return out;
}

}  // namespace nav::emulators

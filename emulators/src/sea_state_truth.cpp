// SPDX-License-Identifier: MIT
// The sea-state truth kind (see sea_state_truth.hpp for SS1..SS11).
#include "nav/emulators/sea_state_truth.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
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

tl::unexpected<Error> invalid(const char* field, const std::string& what) {
  return fail(ErrorCode::kInvalidArgument, std::string("sea.") + field + ": " + what);
}

/// The spec's own checks; the error names the field.
Result<void> check(const SeaSpec& spec) {
  const JonswapSpec& j = spec.spectrum;
  if (!std::isfinite(j.significant_height_m) || j.significant_height_m < 0.0) {
    return invalid("significant_height", "must be finite and >= 0 (got " +
                                             num(j.significant_height_m) + " m)");
  }
  if (!std::isfinite(j.peak_period_s) || j.peak_period_s <= 0.0) {
    return invalid("peak_period", "must be finite and > 0 (got " + num(j.peak_period_s) + " s)");
  }
  if (!std::isfinite(j.gamma) || j.gamma < 1.0 || j.gamma > 7.0) {
    return invalid("gamma", "must be in [1, 7], DNV-RP-C205's range for JONSWAP (got " +
                                num(j.gamma) + "); 1 is Pierson-Moskowitz");
  }
  if (!std::isfinite(spec.from_rad)) return invalid("from", "must be finite");
  if (spec.components < 1 || spec.components > 4096) {
    return invalid("components", "must be 1 .. 4096 (got " + std::to_string(spec.components) +
                                     ")");
  }
  if (!std::isfinite(spec.wind.speed_mps) || spec.wind.speed_mps < 0.0) {
    return invalid("wind.speed", "must be finite and >= 0 (got " + num(spec.wind.speed_mps) +
                                     " m/s)");
  }
  if (!std::isfinite(spec.wind.from_rad)) return invalid("wind.from", "must be finite");
  if (!std::isfinite(spec.wind.drift_factor) || spec.wind.drift_factor < 0.0 ||
      spec.wind.drift_factor > 0.1) {
    return invalid("wind.drift_factor",
                   "must be in [0, 0.1] (got " + num(spec.wind.drift_factor) + ")");
  }
  return {};
}

/// The rate of the ZYX yaw of an attitude with body rate omega_b (inverse Euler kinematics).
double yaw_rate(const Euler& e, const Vec3& omega_b) {
  return (std::sin(e.roll) * omega_b.y() + std::cos(e.roll) * omega_b.z()) / std::cos(e.pitch);
}

}  // namespace

Result<SeaStateTruth> SeaStateTruth::build(std::shared_ptr<const Truth> nominal,
                                           const SeaSpec& spec, std::uint64_t seed,
                                           double gravity_mps2) {
  if (auto r = check(spec); !r) return tl::unexpected(r.error());
  if (!std::isfinite(gravity_mps2) || gravity_mps2 <= 0.0) {
    return fail(ErrorCode::kInvalidArgument, "sea: gravity must be finite and > 0");
  }
  std::mt19937_64 rng(seed);
  return with_components(std::move(nominal),
                         discretise_jonswap(spec.spectrum, spec.components, rng), spec,
                         gravity_mps2);
}

SeaStateTruth SeaStateTruth::with_components(std::shared_ptr<const Truth> nominal,
                                             std::vector<WaveComponent> components,
                                             const SeaSpec& spec, double gravity_mps2) {
  NAV_ENSURE(nominal != nullptr, "a craft in waves needs its nominal path");
  NAV_ENSURE(std::isfinite(gravity_mps2) && gravity_mps2 > 0.0, "gravity must be > 0");
  NAV_ENSURE(std::isfinite(spec.from_rad) && std::isfinite(spec.wind.from_rad) &&
                 std::isfinite(spec.wind.speed_mps) && std::isfinite(spec.wind.drift_factor),
             "sea directions and wind must be finite");
  SeaStateTruth sea;
  sea.nominal_ = std::move(nominal);
  sea.gravity_mps2_ = gravity_mps2;
  sea.components_ = std::move(components);
  for (const WaveComponent& c : sea.components_) {
    NAV_ENSURE(std::isfinite(c.amplitude_m) && std::isfinite(c.phase_rad) &&
                   std::isfinite(c.omega_radps) && c.omega_radps > 0.0,
               "a wave component needs a finite amplitude and phase and w > 0");
    sea.k_.push_back(c.omega_radps * c.omega_radps / gravity_mps2);        // SS1
  }
  sea.beta_rad_ = spec.from_rad + std::numbers::pi;
  sea.d_n_ = Vec3{std::cos(sea.beta_rad_), std::sin(sea.beta_rad_), 0.0};
  const double wind_to_rad = spec.wind.from_rad + std::numbers::pi;        // SS9
  sea.wind_n_ = spec.wind.speed_mps * Vec3{std::cos(wind_to_rad), std::sin(wind_to_rad), 0.0};
  sea.water_n_ = spec.wind.drift_factor * sea.wind_n_;
  sea.free_drift_ = spec.free_drift;

  const TruthSample b = sea.nominal_->at(Duration::zero());
  const Waves w0 = sea.waves(0.0, b.p_n, b.v_n, b.a_n);
  sea.offset0_n_ = Vec3{w0.xi * sea.d_n_.x(), w0.xi * sea.d_n_.y(), -w0.eta};
  return sea;
}

SeaStateTruth::Waves SeaStateTruth::waves(double t_s, const Vec3& x_n, const Vec3& v_n,
                                          const Vec3& a_n) const {
  const double dx = d_n_.dot(x_n);
  const double dv = d_n_.dot(v_n);
  const double da = d_n_.dot(a_n);
  Waves w;
  for (std::size_t i = 0; i < components_.size(); ++i) {
    const WaveComponent& c = components_[i];
    const double k = k_[i];
    const double th = k * dx - c.omega_radps * t_s + c.phase_rad;          // SS2
    const double th1 = k * dv - c.omega_radps;
    const double th2 = k * da;
    const double cs = std::cos(th);
    const double sn = std::sin(th);
    const double a = c.amplitude_m;
    w.eta += a * cs;                                                       // SS3
    w.eta_dot -= a * sn * th1;
    w.eta_ddot -= a * (cs * th1 * th1 + sn * th2);
    w.xi -= a * sn;
    w.xi_dot -= a * cs * th1;
    w.xi_ddot += a * (sn * th1 * th1 - cs * th2);
    w.s += a * k * sn;                                                     // SS5
    w.s_dot += a * k * cs * th1;
  }
  return w;
}

TruthSample SeaStateTruth::at(Duration t) const {
  NAV_ENSURE(t.count() >= 0, "truth is defined for t >= 0 only");
  const double t_s = to_seconds(t);
  const TruthSample b = nominal_->at(t);
  const Vec3 drift_n = free_drift_ ? water_n_ : Vec3::Zero();
  const Vec3 x_n = b.p_n + drift_n * t_s;
  const Vec3 x_dot_n = b.v_n + drift_n;
  const Waves w = waves(t_s, x_n, x_dot_n, b.a_n);

  TruthSample out;
  out.t = t;
  const Vec3 d = d_n_;
  out.p_n = x_n + Vec3{w.xi * d.x(), w.xi * d.y(), -w.eta} - offset0_n_;        // SS4
  out.v_n = x_dot_n + Vec3{w.xi_dot * d.x(), w.xi_dot * d.y(), -w.eta_dot};
  out.a_n = b.a_n + Vec3{w.xi_ddot * d.x(), w.xi_ddot * d.y(), -w.eta_ddot};
  out.distance_m = b.distance_m;

  const Euler e = euler_from_quat(b.q_nb);
  const double psi_dot = yaw_rate(e, b.omega_b);
  const double delta = beta_rad_ - e.yaw;
  const double cd = std::cos(delta);
  const double sd = std::sin(delta);
  const double sx = -w.s * cd;                                                   // SS5
  const double sy = -w.s * sd;
  const double sx_dot = -w.s_dot * cd - w.s * sd * psi_dot;
  const double sy_dot = -w.s_dot * sd + w.s * cd * psi_dot;
  const double c = std::sqrt(1.0 + sx * sx);
  const double u = -sy / c;
  const double u_dot = -sy_dot / c + sy * sx * sx_dot / (c * c * c);
  const double pitch_w = std::atan(sx);                                          // SS6
  const double pitch_w_dot = sx_dot / (1.0 + sx * sx);
  const double roll_w = std::atan(u);
  const double roll_w_dot = u_dot / (1.0 + u * u);

  const Quat q_w = quat_from_euler(Euler{roll_w, pitch_w, 0.0});
  out.q_nb = b.q_nb * q_w;                                                       // SS7
  out.omega_b = q_w.toRotationMatrix().transpose() * b.omega_b +
                euler_rate_to_body(roll_w, pitch_w, Vec3{roll_w_dot, pitch_w_dot, 0.0});

  const Vec3 g_n{0.0, 0.0, gravity_mps2_};
  out.f_b = out.q_nb.toRotationMatrix().transpose() * (out.a_n - g_n);           // SS8
  return out;
}

SeaStateTruth::Waves SeaStateTruth::waves_at(Duration t) const {
  NAV_ENSURE(t.count() >= 0, "truth is defined for t >= 0 only");
  const double t_s = to_seconds(t);
  const TruthSample b = nominal_->at(t);
  const Vec3 drift_n = free_drift_ ? water_n_ : Vec3::Zero();
  return waves(t_s, b.p_n + drift_n * t_s, b.v_n + drift_n, b.a_n);
}

Vec3 SeaStateTruth::water_velocity_n(Duration t) const {
  const Waves w = waves_at(t);
  return water_n_ + Vec3{w.xi_dot * d_n_.x(), w.xi_dot * d_n_.y(), -w.eta_dot};  // SS10
}

double SeaStateTruth::surface_depth_m(Duration t) const {
  return -waves_at(t).eta - offset0_n_.z();                                      // SS11
}

}  // namespace nav::emulators

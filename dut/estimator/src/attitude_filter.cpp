// SPDX-License-Identifier: MIT
#include "nav/estimator/attitude_filter.hpp"

#include <array>
#include <cmath>
#include <string>

#include "nav/common/ensure.hpp"
#include "nav/estimator/complementary_attitude.hpp"
#include "nav/estimator/euler_attitude.hpp"
#include "nav/estimator/quat_eskf.hpp"

namespace nav::estimator {
namespace {

struct KindName {
  AttitudeFilterKind kind;
  std::string_view name;
};

constexpr std::array<KindName, 6> kKinds{{
    {AttitudeFilterKind::kMahony, "mahony"},
    {AttitudeFilterKind::kRaw, "raw"},
    {AttitudeFilterKind::kEkf, "ekf"},
    {AttitudeFilterKind::kUkf, "ukf"},
    {AttitudeFilterKind::kCf, "cf"},
    {AttitudeFilterKind::kEskf, "eskf"},
}};

/// The existing quaternion complementary filter behind the common interface.
class MahonyAttitude final : public AttitudeFilter {
 public:
  explicit MahonyAttitude(const FilterParams& params)
      : filter_(params), declination_rad_(params.magnetic_declination_rad) {}

  bool initialise(const Vec3& f_b_mps2, const Vec3& m_b_tesla) override {
    const auto q = ComplementaryAttitude::align(f_b_mps2, m_b_tesla, declination_rad_);
    if (!q) return false;
    filter_.reset(*q);
    return true;
  }

  AttitudeStatus step(const AttitudeInput& in) override {
    if (!std::isfinite(in.dt_s) || in.dt_s <= 0.0) return record(AttitudeStatus::kRejectedInvalid);
    const StepStatus s = filter_.step(in.omega_b_radps, in.f_b_mps2, in.m_b_tesla, in.dt_s);
    return record(s == StepStatus::kApplied ? AttitudeStatus::kOk
                                            : AttitudeStatus::kRejectedInvalid);
  }

  Quat q_nb() const override { return filter_.q_nb(); }
  AttitudeFilterKind kind() const override { return AttitudeFilterKind::kMahony; }

 private:
  ComplementaryAttitude filter_;
  double declination_rad_;
};

}  // namespace

EskfParams eskf_params(const FilterParams& p) {
  EskfParams e;
  e.gyro_noise_radps_rthz = p.eskf_gyro_noise_radps_rthz;
  e.gyro_bias_walk_radps2_rthz = p.eskf_gyro_bias_walk_radps2_rthz;
  e.initial_tilt_std_rad = p.eskf_initial_tilt_std_rad;
  e.initial_yaw_std_rad = p.eskf_initial_yaw_std_rad;
  e.initial_gyro_bias_std_radps = p.eskf_initial_gyro_bias_std_radps;
  e.gyro_bias_limit_radps = p.gyro_bias_limit_radps;
  e.accel_std_mps2 = p.eskf_accel_std_mps2;
  e.accel_gate_mps2 = p.accel_gate_mps2;
  e.mag_field_n_tesla =
      Vec3(p.eskf_mag_field_north_t, p.eskf_mag_field_east_t, p.eskf_mag_field_down_t);
  e.initial_hard_iron_std_tesla = p.eskf_initial_hard_iron_std_t;
  e.hard_iron_walk_tesla_rts = p.eskf_hard_iron_walk_t_rts;
  e.mag_std_tesla = p.eskf_mag_std_t;
  e.mag_norm_gate = p.eskf_mag_norm_gate;
  e.mag_inclination_gate_rad = p.eskf_mag_inclination_gate_rad;
  e.mag_gate_nis = p.eskf_mag_gate_nis;
  e.declination_rad = p.magnetic_declination_rad;
  return e;
}

std::string_view attitude_filter_name(AttitudeFilterKind kind) {
  for (const auto& k : kKinds) {
    if (k.kind == kind) return k.name;
  }
  return "unknown";
}

std::string attitude_filter_names() {
  std::string out;
  for (const auto& k : kKinds) {
    if (!out.empty()) out += ", ";
    out += k.name;
  }
  return out;
}

Result<AttitudeFilterKind> parse_attitude_filter(std::string_view name) {
  for (const auto& k : kKinds) {
    if (k.name == name) return k.kind;
  }
  return fail(ErrorCode::kInvalidArgument, "unknown attitude filter '" + std::string(name) +
                                               "' (expected one of " + attitude_filter_names() +
                                               ")");
}

std::unique_ptr<AttitudeFilter> make_attitude_filter(AttitudeFilterKind kind,
                                                     const FilterParams& params) {
  NAV_ENSURE(validate(params).has_value(), "filter parameters must be validated first");
  const double decl = params.magnetic_declination_rad;
  switch (kind) {
    case AttitudeFilterKind::kMahony: return std::make_unique<MahonyAttitude>(params);
    case AttitudeFilterKind::kRaw: return std::make_unique<p0::RawAttitude>(decl);
    case AttitudeFilterKind::kEkf: return std::make_unique<p0::EulerEkf>(p0::EkfParams{}, decl);
    case AttitudeFilterKind::kUkf: return std::make_unique<p0::EulerUkf>(p0::UkfParams{}, decl);
    case AttitudeFilterKind::kCf: return std::make_unique<p0::EulerCf>(p0::CfParams{}, decl);
    case AttitudeFilterKind::kEskf: return std::make_unique<QuatEskf>(eskf_params(params));
  }
  NAV_ENSURE(false, "unknown attitude filter kind");
  return nullptr;
}

}  // namespace nav::estimator

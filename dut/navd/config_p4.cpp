// SPDX-License-Identifier: MIT
#include "config_p4.hpp"

#include "config_number.hpp"

#include <array>
#include <cmath>
#include <cstdio>

#include "nav/common/format.hpp"

namespace nav::dut {
namespace {

using Rule = P4Field::Rule;

// A double member of P4Config.
#define NAV_P4_SCALAR(member) \
  [](const P4Config& c) { return c.member; }, [](P4Config& c, double v) { c.member = v; }

constexpr int kMaxCompassEvery = 1000000;

const std::array<P4Field, 19> kFields = {{
    {"p4_kappa", "kappa of the paper's unscented transform (alpha 1, beta 0), > -6 [-]",
     NAV_P4_SCALAR(filter.kappa), Rule::kKappa},
    {"p4_accel_noise_mps2_rthz",
     "q_a, horizontal acceleration white noise: the sensor's plus the wave tilt the level "
     "model leaves out (B6) [m/s^2/sqrt(Hz)]",
     NAV_P4_SCALAR(filter.accel_noise_density_mps2_rthz), Rule::kPositive},
    {"p4_gyro_noise_radps_rthz", "q_g, yaw-gyro white noise (B7) [rad/s/sqrt(Hz)]",
     NAV_P4_SCALAR(filter.gyro_noise_density_radps_rthz), Rule::kPositive},
    {"p4_gyro_bias_walk_radps_rtsec", "q_b, yaw-gyro bias random walk (B7) [rad/s/sqrt(s)]",
     NAV_P4_SCALAR(filter.gyro_bias_walk_radps_rtsec), Rule::kPositive},
    {"p4_gps_position_std_m", "sigma_p, RMC position noise per horizontal axis (B8) [m]",
     NAV_P4_SCALAR(filter.gps_position_std_m), Rule::kPositive},
    {"p4_compass_std_rad", "sigma_c, compass heading noise (B9) [rad]",
     NAV_P4_SCALAR(filter.compass_std_rad), Rule::kPositive},
    {"p4_gps_velocity_std_mps",
     "sigma_v, RMC velocity noise per axis (B10, with p4_rmc_velocity) [m/s]",
     NAV_P4_SCALAR(filter.gps_velocity_std_mps), Rule::kPositive},
    {"p4_gps_position_gate_nis", "NIS gate of the position update, 0 = none (chi2 2 dof) [-]",
     NAV_P4_SCALAR(filter.gps_position_gate_nis), Rule::kNonNegative},
    {"p4_compass_gate_nis", "NIS gate of the compass update, 0 = none (chi2 1 dof) [-]",
     NAV_P4_SCALAR(filter.compass_gate_nis), Rule::kNonNegative},
    {"p4_gps_velocity_gate_nis", "NIS gate of the RMC velocity update, 0 = none [-]",
     NAV_P4_SCALAR(filter.gps_velocity_gate_nis), Rule::kNonNegative},
    {"p4_initial_position_std_m", "sigma of the start's position per axis (B11) [m]",
     NAV_P4_SCALAR(filter.initial_position_std_m), Rule::kPositive},
    {"p4_initial_velocity_std_mps", "sigma of the start's velocity per axis (B11) [m/s]",
     NAV_P4_SCALAR(filter.initial_velocity_std_mps), Rule::kPositive},
    {"p4_initial_heading_std_rad", "sigma of the start's heading, one compass reading (B11) [rad]",
     NAV_P4_SCALAR(filter.initial_heading_std_rad), Rule::kPositive},
    {"p4_initial_gyro_bias_std_radps", "sigma of the start's yaw-gyro bias (B11) [rad/s]",
     NAV_P4_SCALAR(filter.initial_gyro_bias_std_radps), Rule::kPositive},
    {"p4_max_dt_s",
     "longest frame interval predicted over; a longer one (or <= 0) skips the step [s]",
     NAV_P4_SCALAR(filter.max_dt_s), Rule::kPositive},
    {"p4_compass_every",
     "fuse the compass at every N-th beacon frame, whole, >= 1 (50: ~1 Hz at 50 Hz frames, "
     "as its tilt and thruster errors are correlated over seconds) [frames]",
     [](const P4Config& c) { return static_cast<double>(c.compass_every); },
     [](P4Config& c, double v) { c.compass_every = whole_or_invalid(v, 1, kMaxCompassEvery); },
     Rule::kOther},
    {"p4_dwt_window",
     "W, samples per de-noised block (p4-dwt-ukf), even, in [2L, 4096] (L: the wavelet's "
     "taps) [samples]",
     [](const P4Config& c) { return static_cast<double>(c.dwt.window); },
     [](P4Config& c, double v) { c.dwt.window = whole_or_invalid(v, 2, 4096); }, Rule::kOther},
    {"p4_dwt_lambda_mps2",
     "lambda of the soft threshold with p4_dwt_threshold: fixed, >= 0 [m/s^2]",
     NAV_P4_SCALAR(dwt.threshold.lambda), Rule::kNonNegative},
    {"p4_vertical_std_m",
     "sigma of the depth stated in $PNVBCOV (the filter is planar, depth 0): the heave, Hs/4 "
     "[m]",
     NAV_P4_SCALAR(vertical_std_m), Rule::kPositive},
}};

#undef NAV_P4_SCALAR

Result<void> bad(const std::string& what) { return fail(ErrorCode::kInvalidArgument, what); }

const std::array<P4ChoiceField, 3> kChoices = {{
    {"p4_rmc_velocity", "true or false: fuse RMC speed/course as the NED velocity (B10)",
     [](const P4Config& c) { return std::string(c.rmc_velocity ? "true" : "false"); },
     [](P4Config& c, const std::string& v) -> Result<void> {
       if (v == "true") {
         c.rmc_velocity = true;
       } else if (v == "false") {
         c.rmc_velocity = false;
       } else {
         return bad("p4_rmc_velocity expects true or false, not '" + v + "'");
       }
       return {};
     }},
    {"p4_dwt_wavelet", "haar, db4 or sym4: the de-noiser's filter bank (p4-dwt-ukf)",
     [](const P4Config& c) { return std::string(estimator::to_string(c.dwt.wavelet)); },
     [](P4Config& c, const std::string& v) -> Result<void> {
       for (const auto w : {estimator::Wavelet::kHaar, estimator::Wavelet::kDb4,
                            estimator::Wavelet::kSym4}) {
         if (v == estimator::to_string(w)) {
           c.dwt.wavelet = w;
           return {};
         }
       }
       return bad("unknown p4_dwt_wavelet '" + v + "' (expected haar, db4 or sym4)");
     }},
    {"p4_dwt_threshold",
     "universal (lambda = sigma sqrt(2 ln W), sigma from the window's detail coefficients by "
     "MAD) or fixed (p4_dwt_lambda_mps2)",
     [](const P4Config& c) {
       return std::string(c.dwt.threshold.rule == estimator::ThresholdRule::kFixed ? "fixed"
                                                                                    : "universal");
     },
     [](P4Config& c, const std::string& v) -> Result<void> {
       if (v == "universal") {
         c.dwt.threshold.rule = estimator::ThresholdRule::kUniversalMad;
       } else if (v == "fixed") {
         c.dwt.threshold.rule = estimator::ThresholdRule::kFixed;
       } else {
         return bad("unknown p4_dwt_threshold '" + v + "' (expected universal or fixed)");
       }
       return {};
     }},
}};

}  // namespace

const char* p4_method_name(P4Method m) {
  switch (m) {
    case P4Method::kUkf: return "p4-ukf";
    case P4Method::kDwtUkf: return "p4-dwt-ukf";
  }
  return "?";
}

Result<void> validate(const P4Config& c) {
  for (const P4Field& f : kFields) {
    const double v = f.get(c);
    const std::string got = " (got " + format_g(v) + ")";
    switch (f.rule) {
      case Rule::kPositive:
        if (!(std::isfinite(v) && v > 0.0)) {
          return bad(std::string(f.name) + " must be finite and > 0" + got);
        }
        break;
      case Rule::kNonNegative:
        if (!(std::isfinite(v) && v >= 0.0)) {
          return bad(std::string(f.name) + " must be finite and >= 0" + got);
        }
        break;
      case Rule::kKappa:
        if (!(std::isfinite(v) && v > -static_cast<double>(estimator::P4Idx::kDim))) {
          return bad(std::string(f.name) + " must be finite and > -6" + got);
        }
        break;
      case Rule::kOther: break;
    }
  }
  if (c.compass_every < 1) {
    return bad("p4_compass_every must be a whole number in [1, " +
               std::to_string(kMaxCompassEvery) + "]");
  }
  const int L = estimator::filter_bank(c.dwt.wavelet).length;
  const int W = c.dwt.window;
  if (W % 2 != 0 || W < 2 * L || W > 4096 || !estimator::validate(c.dwt)) {
    return bad("p4_dwt_window must be an even whole number in [" + std::to_string(2 * L) +
               ", 4096] for p4_dwt_wavelet " + estimator::to_string(c.dwt.wavelet));
  }
  // What the estimator's own checks ask, in case they ask more than the keys above.
  if (auto ok = estimator::validate(c.filter); !ok) return bad("p4_*: " + ok.error().detail);
  return {};
}

std::span<const P4Field> p4_fields() { return kFields; }

const P4Field* find_p4_field(const std::string& key) {
  for (const auto& f : kFields) {
    if (key == f.name) return &f;
  }
  return nullptr;
}

std::span<const P4ChoiceField> p4_choice_fields() { return kChoices; }

const P4ChoiceField* find_p4_choice_field(const std::string& key) {
  for (const auto& f : kChoices) {
    if (key == f.name) return &f;
  }
  return nullptr;
}

}  // namespace nav::dut

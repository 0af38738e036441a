// SPDX-License-Identifier: MIT
// The keys of navd's config file that set paper P4's sea-surface beacon navigators
// (navigator: p4-ukf, p4-dwt-ukf; p4_navigator.hpp): the UKF's noises, gates and start
// (P4UkfParams, passed through), how often the compass is fused, whether RMC speed/course is
// fused, the accelerometer de-noiser (DwtDenoiserConfig, p4-dwt-ukf only) and the vertical
// standard deviation stated in $PNVBCOV.
//
// Most keys are numbers (P4Field, like the other papers'); four take a name or a boolean
// (P4ChoiceField): p4_rmc_velocity (true/false), p4_dwt_wavelet (haar, db4, sym4),
// p4_dwt_threshold (universal, fixed).
#pragma once

#include <span>
#include <string>

#include "nav/common/result.hpp"
#include "nav/estimator/dwt_denoiser.hpp"
#include "nav/estimator/p4_beacon_ukf.hpp"

namespace nav::dut {

/// Which of paper P4's two navigators runs.
enum class P4Method {
  kUkf,     ///< "p4-ukf": the UKF driven by the raw accelerometer (the paper's "without DWT")
  kDwtUkf,  ///< "p4-dwt-ukf": f_x, f_y each de-noised by a level-1 DWT first (the paper's method)
};

/// navigator: p4-ukf, p4-dwt-ukf.
struct P4Config {
  P4Method method = P4Method::kDwtUkf;
  estimator::P4UkfParams filter;  ///< the UKF's noises, gates, start and max_dt_s
  /// The compass is fused at every N-th beacon frame (frames counted from the first). Its
  /// errors (tilt of an uncompensated compass in the waves, the thrusters' field) are
  /// correlated over seconds, so fusing it at every 50 Hz frame as if independent would make
  /// the filter trust it ~50 times too much: default 50, ~1 Hz at 50 Hz frames [frames].
  int compass_every = 50;
  bool rmc_velocity = false;  ///< fuse RMC speed/course as [v_N, v_E] (B10)
  /// f_x and f_y de-noisers of p4-dwt-ukf (wavelet, window W, threshold rule).
  estimator::DwtDenoiserConfig dwt;
  /// σ of the depth stated in $PNVBCOV: the filter is planar and states depth 0 (mean sea
  /// level); a floating beacon heaves about it with σ = Hs/4, 0.15 m in the paper's sea
  /// (Hs 0.6 m). Stated so that the 3×3 position covariance is positive definite [m].
  double vertical_std_m = 0.15;
};

/// The navigator name of a method ("p4-ukf", "p4-dwt-ukf").
const char* p4_method_name(P4Method m);

/// Every field in range, or an error naming the key.
Result<void> validate(const P4Config& c);

/// One numeric P4Config quantity by name.
struct P4Field {
  /// What validate() asks of the value.
  enum class Rule {
    kPositive,     ///< finite, > 0
    kNonNegative,  ///< finite, >= 0 (a gate: 0 = none)
    kKappa,        ///< finite, > −n (n = 6)
    kOther,        ///< checked by validate() as a whole (counts, the window)
  };
  const char* name;                     ///< e.g. "p4_compass_every"
  const char* doc;                      ///< one line with its unit
  double (*get)(const P4Config&);       ///< its value
  void (*set)(P4Config&, double);       ///< sets it
  Rule rule;                            ///< what validate() asks
};

/// Every numeric P4 key.
std::span<const P4Field> p4_fields();

/// The numeric P4 field named `key`, or nullptr.
const P4Field* find_p4_field(const std::string& key);

/// One P4Config setting given by a name or a boolean.
struct P4ChoiceField {
  const char* name;                      ///< e.g. "p4_dwt_wavelet"
  const char* doc;                       ///< one line naming the choices
  std::string (*get)(const P4Config&);   ///< its value as written in a config
  /// Sets it from the YAML scalar; the error is the reason only (the caller locates it).
  Result<void> (*set)(P4Config&, const std::string&);
};

/// Every P4 key that takes a name or a boolean.
std::span<const P4ChoiceField> p4_choice_fields();

/// The P4 choice field named `key`, or nullptr.
const P4ChoiceField* find_p4_choice_field(const std::string& key);

}  // namespace nav::dut

// SPDX-License-Identifier: MIT
// What the USBL emulator (a fixed transceiver) and the iUSBL emulator (a device on a vehicle)
// share: the acoustic travel time to a moving end, the usbl_outliers faults' draws and the
// signal figures their USBLLONG lines report. Private to nav_emulators.
#pragma once

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "nav/emulators/device.hpp"
#include "nav/emulators/measurement_faults.hpp"

namespace nav::emulators::detail {

inline constexpr int kIntegrity = 150;         ///< reported signal integrity (>= 100: good) [-]
inline constexpr double kRssiAt1m_db = -35.0;  ///< RSSI at 1 m range [dB]

/// Received signal strength at slant range r by spherical spreading [dB].
inline int rssi_db(double r_m) {
  return static_cast<int>(std::lround(kRssiAt1m_db - 20.0 * std::log10(std::max(r_m, 1.0))));
}

/// One-way travel time of a signal leaving a fixed point p at t to `moving` [s]:
/// tau = |p_moving(t + tau) − p| / c, by fixed-point iteration from |p_moving(t) − p| / c (a
/// contraction with factor |v| / c << 1; stopped at |d tau| < 1e-12 s or after 50 steps).
inline double one_way_time_s(const Truth& moving, Duration t, const Vec3& p, double c) {
  double tau = (moving.at(t).p_n - p).norm() / c;
  for (int it = 0; it < 50; ++it) {
    const double next = (moving.at(t + from_seconds(tau)).p_n - p).norm() / c;
    const double step = std::abs(next - tau);
    tau = next;
    if (step < 1e-12) break;
  }
  return tau;
}

/// The usbl_outliers faults of a fix valid at t: for each such fault in list order whose
/// window holds t, draws u, m1, m2, m3 from `rng` (also when its probability is 0) and, iff
/// u < probability, adds outlier_std_m [m1, m2, m3] to the returned displacement [m]. `hit`:
/// whether any did.
inline Vec3 usbl_fault_outliers(const std::vector<MeasurementFault>& faults, Duration t,
                                std::mt19937_64& rng, bool& hit) {
  Vec3 d = Vec3::Zero();
  hit = false;
  for (const MeasurementFault& f : faults) {
    if (f.kind != MeasurementFault::Kind::kUsblOutliers || !f.active(t)) continue;
    const bool now = unit_uniform(rng) < f.probability;
    Vec3 m;
    for (int j = 0; j < 3; ++j) m[j] = standard_normal(rng);
    if (now) {
      d += f.outlier_std_m * m;
      hit = true;
    }
  }
  return d;
}

}  // namespace nav::emulators::detail

// SPDX-License-Identifier: MIT
// Shared by the estimator tests: NAV_ENSURE throws (so GoogleTest reports a contract
// violation instead of aborting), and sensor readings synthesised from a true attitude.
#pragma once

#include <stdexcept>
#include <string>

#include "nav/common/ensure.hpp"
#include "nav/common/frames.hpp"
#include "nav/common/units.hpp"

namespace nav::estimator::testing {

inline void throwing_handler(const char* file, int line, const char* condition,
                             const std::string& message) {
  throw std::logic_error(std::string(file) + ":" + std::to_string(line) + ": " + condition +
                         ": " + message);
}

/// Installs the throwing handler for the lifetime of the test binary.
struct EnsureThrows {
  EnsureThrows() { set_ensure_handler(&throwing_handler); }
};
inline const EnsureThrows kEnsureThrows{};

/// Earth field at the datum, NED [T] (0.2 G North, 0.4 G down), as the emulator's default.
inline Vec3 earth_field_n() { return Vec3(2.0e-5, 0.0, 4.0e-5); }

/// Specific force of a vehicle at rest with attitude q_nb, body [m/s²].
inline Vec3 static_specific_force_b(const Quat& q_nb) {
  return q_nb.conjugate() * Vec3(0.0, 0.0, -units::kStandardGravity);
}

/// Field m_n seen in the body frame of attitude q_nb [T].
inline Vec3 field_b(const Quat& q_nb, const Vec3& m_n) { return q_nb.conjugate() * m_n; }

}  // namespace nav::estimator::testing

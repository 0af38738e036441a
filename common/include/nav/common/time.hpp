// SPDX-License-Identifier: MIT
// Time base of navbench: integer nanoseconds, never floating-point seconds in storage.
#pragma once

#include <chrono>
#include <cstdint>
#include <ctime>

namespace nav {

/// A duration or a time since an epoch [ns]. Scenario time counts from the scenario start.
using Duration = std::chrono::nanoseconds;
/// A point in time as nanoseconds since an epoch named by the caller (scenario start or
/// CLOCK_MONOTONIC's epoch).
using Timestamp = std::chrono::nanoseconds;

/// Seconds as double, for math kernels and reports only [s].
constexpr double to_seconds(Duration d) { return static_cast<double>(d.count()) * 1e-9; }
/// The same, divided rather than multiplied: the nearest double, so that a time written in a
/// scenario reads back as written in reports (7.5 s is 7.5, not 7.500000000000001) [s].
constexpr double to_seconds_exact(Duration d) { return static_cast<double>(d.count()) / 1e9; }

/// Nearest integer nanoseconds of a time in seconds [s].
constexpr Duration from_seconds(double s) {
  const double ns = s * 1e9;
  return Duration{static_cast<std::int64_t>(ns < 0 ? ns - 0.5 : ns + 0.5)};
}

/// CLOCK_MONOTONIC now [ns since the clock's epoch].
inline Timestamp monotonic_now() {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return Timestamp{static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000LL + ts.tv_nsec};
}

/// Converts a CLOCK_MONOTONIC time to a timespec for clock_nanosleep(TIMER_ABSTIME).
inline timespec to_timespec(Timestamp t) {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(t.count() / 1'000'000'000LL);
  ts.tv_nsec = static_cast<long>(t.count() % 1'000'000'000LL);
  return ts;
}

}  // namespace nav

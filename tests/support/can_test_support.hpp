// SPDX-License-Identifier: MIT
// Helpers shared by the tests that run on a live vcan0 (ctest label vcan, through
// scripts/with-vcan): CI detection, programs on PATH, skip-or-fail under CI, frames received
// from a CanSocket until a count or a timeout, codec frames as SocketCAN frames.
//
// Run directly without vcan0 or can-utils, the cases skip (REQUIRE_OR_SKIP), except under CI
// (CI=true or 1), where a missing prerequisite is a failure.
#pragma once

#include <net/if.h>
#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "nav/transport/can_socket.hpp"

namespace nav::test_support {

/// The interface every vcan test uses.
inline constexpr const char* kVcanIface = "vcan0";

/// True when the environment says CI (CI=true or CI=1, any case).
inline bool running_in_ci() {
  const char* ci = std::getenv("CI");
  if (ci == nullptr) return false;
  std::string v(ci);
  std::transform(v.begin(), v.end(), v.begin(), [](unsigned char c) { return std::tolower(c); });
  return v == "true" || v == "1";
}

/// The path of executable `name` in $PATH (or /usr/bin:/bin without one) followed by
/// `extra_dirs` (colon-separated, starting with ':'); empty if not found.
inline std::string find_program(const std::string& name, const std::string& extra_dirs = "") {
  const char* path = std::getenv("PATH");
  std::string dirs = path != nullptr ? path : "/usr/bin:/bin";
  dirs += extra_dirs;
  std::size_t start = 0;
  while (start <= dirs.size()) {
    const std::size_t end = std::min(dirs.find(':', start), dirs.size());
    const std::string candidate = dirs.substr(start, end - start) + "/" + name;
    if (::access(candidate.c_str(), X_OK) == 0) return candidate;
    start = end + 1;
  }
  return {};
}

/// True when executable `name` is in $PATH.
inline bool program_on_path(const std::string& name) { return !find_program(name).empty(); }

/// A frame received from a CanSocket.
struct Heard {
  transport::CanFrame frame;
  double t_s = 0;  ///< kernel receive time [s since the epoch]; 0 if not stamped
};

/// Receives from `socket` until `count` frames arrived or `timeout_s` passed.
inline std::vector<Heard> receive_frames(transport::CanSocket& socket, std::size_t count,
                                         double timeout_s) {
  std::vector<Heard> got;
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (got.size() < count && std::chrono::steady_clock::now() < deadline) {
    auto r = socket.receive();
    if (!r) {
      ADD_FAILURE() << r.error().detail;
      break;
    }
    if (r->has_value()) {
      const auto& rx = **r;
      got.push_back({rx.frame, rx.kernel_time ? static_cast<double>(rx.kernel_time->count()) * 1e-9
                                              : 0.0});
      continue;
    }
    pollfd p{socket.fd(), POLLIN, 0};
    (void)::poll(&p, 1, 50);
  }
  return got;
}

/// The SocketCAN frame of a codec frame (protocols::can::Frame: id, extended, rtr, length(),
/// data).
template <class CodecFrame>
transport::CanFrame to_socket(const CodecFrame& f) {
  transport::CanFrame out;
  out.id = f.id;
  out.extended = f.extended;
  out.rtr = f.rtr;
  out.dlc = static_cast<std::uint8_t>(f.length());
  out.data = f.data;
  return out;
}

}  // namespace nav::test_support

/// Skips the test when `cond` is false, or fails it under CI.
#define REQUIRE_OR_SKIP(cond, why)                                                    \
  do {                                                                                \
    if (!(cond)) {                                                                    \
      if (::nav::test_support::running_in_ci()) FAIL() << (why) << " (CI=true: not skipped)"; \
      GTEST_SKIP() << (why);                                                          \
    }                                                                                 \
  } while (0)

/// Skips (or fails under CI) when vcan0 is absent.
#define REQUIRE_VCAN()                                                                 \
  REQUIRE_OR_SKIP(::if_nametoindex(::nav::test_support::kVcanIface) != 0,              \
                  "no vcan0 here: run through scripts/with-vcan (ctest -L vcan)")

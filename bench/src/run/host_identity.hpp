// SPDX-License-Identifier: MIT
// The machine a run ran on, for its report. Private to nav_bench.
#pragma once

#include <sys/utsname.h>

#include <string>

namespace nav::bench::detail {

struct HostIdentity {
  std::string name;    ///< node name, e.g. "bench-3"
  std::string kernel;  ///< "Linux 6.1.0-18-amd64 #1 SMP PREEMPT_DYNAMIC ... x86_64"
};

inline HostIdentity host_identity() {
  utsname u{};
  if (::uname(&u) != 0) return {};
  return {u.nodename, std::string(u.sysname) + " " + u.release + " " + u.version + " " + u.machine};
}

}  // namespace nav::bench::detail

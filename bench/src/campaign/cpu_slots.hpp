// SPDX-License-Identifier: MIT
// A local lockstep campaign's runs, each on a CPU of its own. A lockstep run is one chain of
// wake-ups (the bench, the kernel's pty worker, the DUT); with two runs at a time on two CPUs,
// the scheduler otherwise moves them across each other's CPUs at every hand-off. Pinning each
// child `navbench run` (and so the DUT it starts, which inherits it) to its own CPU of the
// campaign's allowed set: the 100-run P0 campaign (-j 2, 2-vCPU VM) took 120 s pinned against
// 148 s unpinned, run back to back (design-notes.md, "Campaign speed").
// Only when the runs at a time fit the CPUs, and only in lockstep: realtime runs are judged
// on their timing and keep the scheduler's choice. Private to nav_bench's campaign/.
#pragma once

#include <sched.h>
#include <sys/types.h>

#include <vector>

namespace nav::bench::detail {

class CpuSlots {
 public:
  /// Slots for `jobs` runs at a time; none (pin does nothing) unless enabled and the
  /// campaign's allowed CPUs are at least `jobs`.
  CpuSlots(bool enabled, unsigned jobs) {
    cpu_set_t allowed;
    CPU_ZERO(&allowed);
    if (!enabled || ::sched_getaffinity(0, sizeof allowed, &allowed) != 0) return;
    for (int c = 0; c < CPU_SETSIZE; ++c) {
      if (CPU_ISSET(c, &allowed)) cpus_.push_back(c);
    }
    if (cpus_.size() < jobs) cpus_.clear();
    owner_.assign(cpus_.size(), -1);
  }

  /// Pins a child to a free CPU (best effort: a failure leaves it unpinned).
  void pin(pid_t pid) {
    for (std::size_t k = 0; k < cpus_.size(); ++k) {
      if (owner_[k] >= 0) continue;
      cpu_set_t one;
      CPU_ZERO(&one);
      CPU_SET(cpus_[k], &one);
      if (::sched_setaffinity(pid, sizeof one, &one) == 0) owner_[k] = pid;
      return;
    }
  }

  /// The child has ended: its CPU is free.
  void release(pid_t pid) {
    for (auto& o : owner_) {
      if (o == pid) o = -1;
    }
  }

 private:
  std::vector<int> cpus_;
  std::vector<pid_t> owner_;
};

}  // namespace nav::bench::detail

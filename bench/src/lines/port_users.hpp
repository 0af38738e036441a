// SPDX-License-Identifier: MIT
// Whether a process other than the bench has a path open, from /proc/<pid>/fd (what fuser(1)
// reads). A run asks at scenario time 0 whether the DUTs opened their ptys: a port a DUT
// opens later loses what was written before (LibSerial flushes a port it opens). Private to
// nav_bench.
#pragma once

#include <string>
#include <vector>

namespace nav::bench {

/// The paths of `paths` that no process but this one has open. Linux only; a path that cannot
/// be resolved counts as open (nothing to say about it).
std::vector<std::string> paths_not_opened_elsewhere(const std::vector<std::string>& paths);

}  // namespace nav::bench

// SPDX-License-Identifier: MIT
// Child processes of the lateness benchmark: started with posix_spawnp, stdout and stderr to
// files, waited for with their CPU time.
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

namespace nav::benchmarks {

struct Child {
  pid_t pid = -1;
};

struct Finished {
  int exit_code = -1;  ///< 128 + signal when a signal ended it
  double cpu_s = 0.0;  ///< user + system, its waited-for children included
};

/// Starts argv (argv[0] looked up in PATH) with stdout to out and stderr to err; throws when
/// it cannot be started.
Child start(const std::vector<std::string>& argv, const std::filesystem::path& out,
            const std::filesystem::path& err);

/// Waits for it to end.
Finished wait(Child c);

/// Sends sig, then waits for it to end.
Finished stop(Child c, int sig);

/// Starts argv and waits; throws (with the end of err) unless it exited with one of `ok`.
Finished run(const std::vector<std::string>& argv, const std::filesystem::path& log_stem,
             std::vector<int> ok = {0});

}  // namespace nav::benchmarks

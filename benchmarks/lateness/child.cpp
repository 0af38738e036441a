// SPDX-License-Identifier: MIT
#include "child.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <stdexcept>

extern char** environ;

namespace nav::benchmarks {

Child start(const std::vector<std::string>& argv, const std::filesystem::path& out,
            const std::filesystem::path& err) {
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&fa, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = -1;
  const int rc = ::posix_spawnp(&pid, args[0], &fa, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) throw std::runtime_error("cannot start " + argv[0]);
  return Child{pid};
}

Finished wait(Child c) {
  int status = 0;
  rusage u{};
  ::wait4(c.pid, &status, 0, &u);
  Finished f;
  f.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  f.cpu_s = static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
            static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec) * 1e-6;
  return f;
}

Finished stop(Child c, int sig) {
  ::kill(c.pid, sig);
  return wait(c);
}

Finished run(const std::vector<std::string>& argv, const std::filesystem::path& log_stem,
             std::vector<int> ok) {
  const auto out = log_stem.string() + ".out", err = log_stem.string() + ".err";
  const Finished f = wait(start(argv, out, err));
  if (std::find(ok.begin(), ok.end(), f.exit_code) == ok.end()) {
    std::ifstream in(err);
    std::ostringstream text;
    text << in.rdbuf();
    throw std::runtime_error(argv[0] + " " + (argv.size() > 1 ? argv[1] : "") + " exited with " +
                             std::to_string(f.exit_code) + ": " + text.str().substr(0, 400) +
                             " (" + err + ")");
  }
  return f;
}

}  // namespace nav::benchmarks

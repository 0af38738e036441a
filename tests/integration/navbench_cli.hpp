// SPDX-License-Identifier: MIT
// Runs the navbench executable as a child process, as a user would.
#pragma once

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "source_paths.hpp"

extern char** environ;

namespace nav::testing {

struct ProcessResult {
  int exit_code = -1;
  std::string out, err;
  double wall_s = 0.0;
};

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

/// A fresh empty folder for one test.
inline std::filesystem::path fresh_dir(const std::string& name) {
  const auto d = std::filesystem::path(::testing::TempDir()) / ("navbench-" + name + "-" +
                                                                 std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

/// Starts `navbench args...` in `cwd` with stdout and stderr to cwd/stdout.txt and
/// cwd/stderr.txt; returns its pid (-1 when it could not be started).
inline pid_t start_navbench(const std::vector<std::string>& args,
                            const std::filesystem::path& cwd) {
  const std::string exe = nav::test_paths::binary_dir() + "/navbench";
  const auto out_path = cwd / "stdout.txt";
  const auto err_path = cwd / "stderr.txt";
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&fa, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addchdir_np(&fa, cwd.c_str());
  std::vector<char*> argv{const_cast<char*>(exe.c_str())};
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = -1;
  if (::posix_spawn(&pid, exe.c_str(), &fa, nullptr, argv.data(), environ) != 0) pid = -1;
  posix_spawn_file_actions_destroy(&fa);
  return pid;
}

/// Waits for a navbench started by start_navbench in cwd; its exit code (128 + signal when a
/// signal ended it) and what it printed.
inline ProcessResult finish_navbench(pid_t pid, const std::filesystem::path& cwd) {
  ProcessResult r;
  int status = 0;
  ::waitpid(pid, &status, 0);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  r.out = slurp(cwd / "stdout.txt");
  r.err = slurp(cwd / "stderr.txt");
  return r;
}

/// Runs `navbench args...` with stdout/stderr captured; the working directory is `cwd`.
inline ProcessResult run_navbench(const std::vector<std::string>& args,
                                  const std::filesystem::path& cwd) {
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = start_navbench(args, cwd);
  if (pid < 0) return {};
  ProcessResult r = finish_navbench(pid, cwd);
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

inline std::string source_path(const std::string& rel) {
  return nav::test_paths::source_dir() + "/" + rel;
}

}  // namespace nav::testing

// SPDX-License-Identifier: MIT
#include "nav/bench/dut_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <string_view>
#include <thread>
#include <utility>

extern char** environ;

namespace nav::bench {
namespace {

bool executable(const std::filesystem::path& p) {
  struct stat st {};
  return ::stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(p.c_str(), X_OK) == 0;
}

}  // namespace

std::optional<std::string> DutProcess::resolve(const std::string& program) {
  if (program.empty()) return std::nullopt;
  if (program.find('/') != std::string::npos) {
    return executable(program) ? std::optional(program) : std::nullopt;
  }
  std::error_code ec;
  const auto self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const auto beside = self.parent_path() / program;
    if (executable(beside)) return beside.string();
  }
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "/usr/local/bin:/usr/bin:/bin");
  for (std::string dir; std::getline(dirs, dir, ':');) {
    const auto candidate = std::filesystem::path(dir.empty() ? "." : dir) / program;
    if (executable(candidate)) return candidate.string();
  }
  return std::nullopt;
}

Result<pid_t> spawn_logged(const std::string& program, const std::vector<std::string>& argv,
                           const std::string& log_path, LogMode mode,
                           const std::vector<std::string>& environment) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  const int log_flags = O_WRONLY | O_CREAT | (mode == LogMode::kAppend ? O_APPEND : O_TRUNC);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log_path.c_str(), log_flags, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  sigset_t none, all;
  sigemptyset(&none);
  sigfillset(&all);
  posix_spawnattr_setsigmask(&attr, &none);
  posix_spawnattr_setsigdefault(&attr, &all);
  posix_spawnattr_setpgroup(&attr, 0);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF |
                                      POSIX_SPAWN_SETPGROUP);
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  std::vector<char*> env;
  const auto name_of = [](std::string_view v) { return v.substr(0, v.find('=') + 1); };
  for (char** e = environ; *e != nullptr; ++e) {
    const std::string_view name = name_of(*e);
    if (std::none_of(environment.begin(), environment.end(),
                     [&](const std::string& x) { return name_of(x) == name; })) {
      env.push_back(*e);
    }
  }
  for (const auto& x : environment) env.push_back(const_cast<char*>(x.c_str()));
  env.push_back(nullptr);
  pid_t pid = -1;
  const int rc = ::posix_spawn(&pid, program.c_str(), &actions, &attr, args.data(), env.data());
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attr);
  if (rc != 0) return tl::unexpected(io_error("cannot start " + program, rc));
  return pid;
}

Result<DutProcess> DutProcess::start(const std::vector<std::string>& argv,
                                     const std::string& log_path,
                                     const std::vector<std::string>& environment) {
  if (argv.empty()) return fail(ErrorCode::kInvalidArgument, "empty DUT command");
  const auto program = resolve(argv[0]);
  if (!program) return fail(ErrorCode::kNotFound, "DUT program not found: " + argv[0]);

  const auto pid = spawn_logged(*program, argv, log_path, LogMode::kAppend, environment);
  if (!pid) return tl::unexpected(pid.error());
  auto guard = GroupGuard::watch(*pid, std::chrono::milliseconds(500));
  if (!guard) {
    ::kill(-*pid, SIGKILL);
    ::waitpid(*pid, nullptr, 0);
    return tl::unexpected(guard.error());
  }
  return DutProcess(*pid, std::move(*guard));
}

DutProcess::DutProcess(DutProcess&& o) noexcept
    : pid_(std::exchange(o.pid_, -1)), exit_(std::move(o.exit_)), guard_(std::move(o.guard_)) {}

DutProcess::~DutProcess() {
  if (pid_ > 0) stop(0.5);  // ends what is left of its group, running or not
}

void DutProcess::end_group() {
  // The child is reaped; processes it started in its group may live on (a DUT script whose
  // estimator ignores SIGTERM). While any does, the group id cannot go to another process.
  if (::kill(-pid_, 0) == 0) ::kill(-pid_, SIGKILL);
  guard_.release();
}

void DutProcess::record_status(int status) {
  if (WIFEXITED(status)) {
    exit_ = "exited with status " + std::to_string(WEXITSTATUS(status));
  } else if (WIFSIGNALED(status)) {
    exit_ = "killed by signal " + std::to_string(WTERMSIG(status)) + " (" +
            ::strsignal(WTERMSIG(status)) + ")";
  } else {
    exit_ = "ended with wait status " + std::to_string(status);
  }
}

bool DutProcess::running() {
  if (!exit_.empty() || pid_ <= 0) return false;
  int status = 0;
  const pid_t r = ::waitpid(pid_, &status, WNOHANG);
  if (r == 0) return true;
  if (r == pid_) record_status(status);
  else exit_ = "lost (waitpid failed)";
  return false;
}

void DutProcess::stop(double grace_s) {
  if (running()) {
    ::kill(-pid_, SIGTERM);
    const auto deadline =
        std::chrono::steady_clock::now() + std::chrono::duration<double>(grace_s);
    while (std::chrono::steady_clock::now() < deadline && running()) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    if (running()) {
      ::kill(-pid_, SIGKILL);
      int status = 0;
      if (::waitpid(pid_, &status, 0) == pid_) record_status(status);
    }
  }
  if (pid_ > 0) end_group();
}

bool DutProcess::kill_now(double reap_s) {
  if (pid_ <= 0) return true;
  if (running()) {
    ::kill(-pid_, SIGKILL);
    const auto deadline =
        std::chrono::steady_clock::now() + std::chrono::duration<double>(reap_s);
    while (running() && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    if (running()) return false;  // still ending (a process in uninterruptible sleep)
  }
  end_group();
  pid_ = -1;  // done with: its pid, free again, may name another process later
  return true;
}

}  // namespace nav::bench

// SPDX-License-Identifier: MIT
// scripts/with-vcan as its callers see it: usage and harness errors exit 125 with one line on
// stderr (no kernel booted), and a command run through it keeps its exit status, stdout,
// stderr, working directory and NAV_* variables, with no stdin at all (as under CI), and is
// stopped with 124 when WITH_VCAN_TIMEOUT runs out. The run cases boot user-mode Linux on a
// kernel without CAN (about 1.5 s each); they skip when neither the host nor user-mode Linux
// can provide vcan0, except under CI (CI=true), where scripts/setup installs it.
#include <fcntl.h>
#include <net/if.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "source_paths.hpp"

extern char** environ;

namespace nav::testing {
namespace {

namespace fs = std::filesystem;

const std::string kScript = nav::test_paths::source_dir() + "/scripts/with-vcan";

bool running_in_ci() {
  const char* ci = std::getenv("CI");
  if (ci == nullptr) return false;
  std::string v(ci);
  std::transform(v.begin(), v.end(), v.begin(), [](unsigned char c) { return std::tolower(c); });
  return v == "true" || v == "1";
}

struct Outcome {
  int status = -1;  ///< exit status, or -1 when it did not exit normally
  std::string out;
  std::string err;
  double wall_s = 0;
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Runs the harness with `args` in `cwd`, stdin closed, the environment plus `env` (an
/// empty value removes the variable), stdout and stderr to files.
Outcome run_harness(const std::vector<std::string>& args,
                    const std::map<std::string, std::string>& env = {},
                    const fs::path& cwd = fs::current_path()) {
  const fs::path dir = fs::temp_directory_path() /
                       ("with_vcan_test." + std::to_string(::getpid()) + "." +
                        std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()));
  fs::create_directories(dir);
  const std::string out_path = (dir / "out").string();
  const std::string err_path = (dir / "err").string();

  std::vector<std::string> env_strings;
  for (char** e = environ; *e != nullptr; ++e) {
    const std::string kv = *e;
    if (env.count(kv.substr(0, kv.find('='))) == 0) env_strings.push_back(kv);
  }
  for (const auto& [k, v] : env) {
    if (!v.empty()) env_strings.push_back(k + "=" + v);
  }
  std::vector<char*> envp;
  for (auto& s : env_strings) envp.push_back(s.data());
  envp.push_back(nullptr);
  std::vector<std::string> argv_strings{kScript};
  argv_strings.insert(argv_strings.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& s : argv_strings) argv.push_back(s.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addclose(&fa, 0);  // CI gives no stdin at all
  posix_spawn_file_actions_addopen(&fa, 1, out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&fa, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addchdir_np(&fa, cwd.c_str());
  Outcome o;
  const auto t0 = std::chrono::steady_clock::now();
  pid_t pid = -1;
  if (::posix_spawn(&pid, kScript.c_str(), &fa, nullptr, argv.data(), envp.data()) == 0) {
    int ws = 0;
    if (::waitpid(pid, &ws, 0) == pid && WIFEXITED(ws)) o.status = WEXITSTATUS(ws);
  }
  posix_spawn_file_actions_destroy(&fa);
  o.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  o.out = slurp(out_path);
  o.err = slurp(err_path);
  fs::remove_all(dir);
  return o;
}

/// One line, from the harness: "with-vcan: ...\n".
void expect_one_harness_line(const std::string& err) {
  EXPECT_EQ(err.rfind("with-vcan: ", 0), 0u) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
}

TEST(WithVcanUsage, HelpExplainsAndExitsZero) {
  const Outcome o = run_harness({"--help"});
  EXPECT_EQ(o.status, 0);
  EXPECT_NE(o.out.find("Usage: scripts/with-vcan"), std::string::npos) << o.out;
  EXPECT_NE(o.out.find("WITH_VCAN_TIMEOUT"), std::string::npos);
  EXPECT_NE(o.out.find("125"), std::string::npos);
  EXPECT_TRUE(o.err.empty()) << o.err;
}

TEST(WithVcanUsage, HarnessErrorsExit125WithOneLine) {
  struct Case {
    std::vector<std::string> args;
    std::map<std::string, std::string> env;
    std::string says;
  };
  const std::vector<Case> cases = {
      {{}, {}, "no command given"},
      {{"--frobnicate", "true"}, {}, "unknown option --frobnicate"},
      {{"true"}, {{"WITH_VCAN_TIMEOUT", "soon"}}, "WITH_VCAN_TIMEOUT"},
      {{"true"}, {{"WITH_VCAN_MODE", "vm"}}, "WITH_VCAN_MODE"},
      {{"true"},
       {{"WITH_VCAN_MODE", "uml"}, {"WITH_VCAN_UML", "/nonexistent/linux.uml"}},
       "user-mode Linux (/nonexistent/linux.uml) is not installed"},
  };
  for (const auto& c : cases) {
    const Outcome o = run_harness(c.args, c.env);
    EXPECT_EQ(o.status, 125) << c.says;
    expect_one_harness_line(o.err);
    EXPECT_NE(o.err.find(c.says), std::string::npos) << o.err;
    EXPECT_TRUE(o.out.empty()) << o.out;
  }
}

bool harness_can_run() {
  return ::if_nametoindex("vcan0") != 0 || ::access("/usr/bin/linux.uml", X_OK) == 0;
}

/// The harness's own answer, once per test program: empty when it can give vcan0 here, else
/// why not (exit 77: user-mode Linux cannot run on this host's CPU).
const std::string& why_no_vcan_here();

class WithVcanRun : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!harness_can_run()) {
      if (running_in_ci()) FAIL() << "no vcan0 and no /usr/bin/linux.uml (CI=true: not skipped)";
      GTEST_SKIP() << "no vcan0 and no user-mode Linux: run scripts/setup";
    }
    // Installed but unable to boot on this CPU: nothing can provide vcan0 here, CI or not.
    if (!why_no_vcan_here().empty()) GTEST_SKIP() << why_no_vcan_here();
  }
};

const std::string& why_no_vcan_here() {
  static const std::string why = [] {
    const Outcome o = run_harness({"true"}, {{"WITH_VCAN_VERBOSE", ""}});
    return o.status == 77 ? o.err : std::string();
  }();
  return why;
}

TEST_F(WithVcanRun, PassesStatusStreamsDirectoryAndEnvironment) {
  // A working directory with a blank in its name; the command checks what it sees and
  // answers with its exit status (90.. on a mismatch).
  const fs::path cwd = fs::temp_directory_path() / ("with vcan cwd." + std::to_string(::getpid()));
  fs::create_directories(cwd);
  const std::string script =
      "ip link show vcan0 | grep -q UP || exit 90\n"
      "test \"$(pwd)\" = \"$NAV_EXPECT_CWD\" || exit 91\n"
      "test \"$NAV_PROBE\" = \"a b'c\" || exit 92\n"
      "test \"$GTEST_PROBE\" = 1 || exit 93\n"
      "printf 'to stdout\\n'; printf 'to stderr\\n' >&2\n"
      "exit 7\n";
  const Outcome o = run_harness({"sh", "-c", script},
                                {{"NAV_PROBE", "a b'c"},
                                 {"GTEST_PROBE", "1"},
                                 {"NAV_EXPECT_CWD", fs::canonical(cwd).string()},
                                 {"WITH_VCAN_VERBOSE", ""}},
                                cwd);
  fs::remove_all(cwd);
  EXPECT_EQ(o.status, 7) << o.err;
  EXPECT_EQ(o.out, "to stdout\n");
  EXPECT_EQ(o.err, "to stderr\n");
}

TEST_F(WithVcanRun, MissingCommandIs127AsInAShell) {
  const Outcome o = run_harness({"navbench-no-such-program"}, {{"WITH_VCAN_VERBOSE", ""}});
  EXPECT_EQ(o.status, 127) << o.err;
}

TEST_F(WithVcanRun, TimeoutStopsTheCommandWith124) {
  const Outcome o = run_harness({"sleep", "60"},
                                {{"WITH_VCAN_TIMEOUT", "3"}, {"WITH_VCAN_VERBOSE", ""}});
  EXPECT_EQ(o.status, 124);
  expect_one_harness_line(o.err);
  EXPECT_NE(o.err.find("timed out after 3 s"), std::string::npos) << o.err;
  EXPECT_LT(o.wall_s, 20.0);
}

}  // namespace
}  // namespace nav::testing

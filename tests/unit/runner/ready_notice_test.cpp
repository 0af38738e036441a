// SPDX-License-Identifier: MIT
// A DUT's readiness (bench/src/run/ready_notice.hpp), said with libsystemd's own sd_notify():
// READY=1 from the DUT's process group counts, from another group or without READY=1 it does
// not; the DUT finds the socket in its environment, which replaces one it would inherit.
#include <sys/wait.h>
#include <systemd/sd-daemon.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "nav/bench/dut_process.hpp"
#include "run/ready_notice.hpp"

namespace nav::bench {
namespace {

/// sd_notify(state) from a child process in a process group of its own; returns its pid.
pid_t notify_from_other_group(const ReadyNotice& notice, const char* state) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::setpgid(0, 0);
    ::setenv("NOTIFY_SOCKET", notice.environment().substr(14).c_str(), 1);
    ::_exit(sd_notify(0, state) > 0 ? 0 : 1);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "sd_notify failed";
  return pid;
}

TEST(ReadyNotice, ReadyIsOneLineThatSaysReadyEquals1) {
  EXPECT_TRUE(says_ready("READY=1"));
  EXPECT_TRUE(says_ready("READY=1\n"));
  EXPECT_TRUE(says_ready("STATUS=ports open\nREADY=1\nMAINPID=42"));
  EXPECT_FALSE(says_ready("READY=0"));
  EXPECT_FALSE(says_ready("READY=10"));
  EXPECT_FALSE(says_ready("NOTREADY=1"));
  EXPECT_FALSE(says_ready("STATUS=READY=1"));
  EXPECT_FALSE(says_ready(""));
}

TEST(ReadyNotice, SdNotifyFromTheDutsGroupMakesItReady) {
  auto notice = ReadyNotice::open();
  ASSERT_TRUE(notice) << notice.error().detail;
  const std::string env = notice->environment();
  ASSERT_EQ(env.rfind("NOTIFY_SOCKET=@", 0), 0u) << env;
  EXPECT_FALSE(notice->read(::getpgrp()));  // nothing sent yet
  ASSERT_EQ(::setenv("NOTIFY_SOCKET", env.substr(14).c_str(), 1), 0);
  EXPECT_GT(sd_notify(0, "STATUS=opening the ports"), 0);
  EXPECT_FALSE(notice->read(::getpgrp()));
  EXPECT_GT(sd_notify(0, "STATUS=running\nREADY=1"), 0);
  ::unsetenv("NOTIFY_SOCKET");
  EXPECT_TRUE(notice->read(::getpgrp()));
  EXPECT_TRUE(notice->ready());
  EXPECT_TRUE(notice->read(::getpgrp()));  // it stays ready
}

TEST(ReadyNotice, AProcessOfAnotherGroupDoesNotCount) {
  auto notice = ReadyNotice::open();
  ASSERT_TRUE(notice) << notice.error().detail;
  (void)notify_from_other_group(*notice, "READY=1");
  EXPECT_FALSE(notice->read(::getpgrp()));
  EXPECT_FALSE(notice->ready());
  // The same datagram, were the child's group the DUT's.
  auto again = ReadyNotice::open();
  ASSERT_TRUE(again);
  const pid_t other = notify_from_other_group(*again, "READY=1");
  EXPECT_TRUE(again->read(other));
}

TEST(ReadyNotice, TwoSocketsHaveTwoNames) {
  auto a = ReadyNotice::open();
  auto b = ReadyNotice::open();
  ASSERT_TRUE(a && b);
  EXPECT_NE(a->environment(), b->environment());
}

TEST(DutProcessEnvironment, TheGivenVariableReplacesAnInheritedOne) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("navbench-ready-env-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  ASSERT_EQ(::setenv("NOTIFY_SOCKET", "/run/systemd/notify", 1), 0);
  const std::string log = (dir / "env.log").string();
  auto p = DutProcess::start({"/bin/sh", "-c", "env | grep -c '^NOTIFY_SOCKET='; echo \"$NOTIFY_SOCKET\""},
                             log, {"NOTIFY_SOCKET=@abc"});
  ::unsetenv("NOTIFY_SOCKET");
  ASSERT_TRUE(p) << p.error().detail;
  for (int i = 0; i < 500 && p->running(); ++i) ::usleep(10'000);
  ASSERT_FALSE(p->running());
  std::ifstream in(log);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), "1\n@abc\n");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace nav::bench

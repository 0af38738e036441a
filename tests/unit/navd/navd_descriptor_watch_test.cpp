// SPDX-License-Identifier: MIT
// DescriptorWatch, the readiness marks navd's loop reads its ports by: on pipes and a pty,
// a wait marks only when its descriptor is ready; one run_one() + poll() marks every
// descriptor ready then; bytes left unread are reported again after re-arming (navd reads
// at most kReadPerWakeBytes per wake); a hang-up completes the error wait; the descriptor
// is given back, not closed. Like navd's pending signal wait, a work guard keeps each
// io_context from running out of work (and stopping) between wake-ups.
#include <fcntl.h>
#include <unistd.h>

#include <array>

#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <gtest/gtest.h>

#include "descriptor_watch.hpp"
#include "nav/transport/pty.hpp"

namespace nav::dut {
namespace {

using Wait = DescriptorWatch::WaitType;

/// An io_context that, like navd's, always has work pending.
struct Loop {
  boost::asio::io_context io;
  boost::asio::executor_work_guard<boost::asio::io_context::executor_type> work =
      boost::asio::make_work_guard(io);
  /// One wake-up as navd's loop has it.
  void wake() {
    io.run_one();
    io.poll();
  }
};

/// A pipe whose ends close with the test.
struct Pipe {
  Pipe() {
    EXPECT_EQ(::pipe2(fds.data(), O_NONBLOCK | O_CLOEXEC), 0);
  }
  ~Pipe() {
    for (int fd : fds) ::close(fd);
  }
  int read_end() const { return fds[0]; }
  int write_end() const { return fds[1]; }
  std::array<int, 2> fds{-1, -1};
};

TEST(DescriptorWatch, MarksOnlyWhenReadableAndUntilTaken) {
  Loop loop;
  Pipe p;
  DescriptorWatch w(loop.io, p.read_end());
  w.arm(Wait::wait_read);
  loop.io.poll();
  EXPECT_FALSE(w.ready(Wait::wait_read));

  ASSERT_EQ(::write(p.write_end(), "x", 1), 1);
  loop.wake();
  EXPECT_TRUE(w.ready(Wait::wait_read));
  EXPECT_FALSE(w.ready(Wait::wait_write));
  EXPECT_TRUE(w.take(Wait::wait_read));
  EXPECT_FALSE(w.take(Wait::wait_read));
}

TEST(DescriptorWatch, OneWakeUpMarksEveryReadyDescriptor) {
  Loop loop;
  Pipe a;
  Pipe b;
  Pipe idle;
  DescriptorWatch wa(loop.io, a.read_end());
  DescriptorWatch wb(loop.io, b.read_end());
  DescriptorWatch wi(loop.io, idle.read_end());
  for (auto* w : {&wa, &wb, &wi}) w->arm(Wait::wait_read);
  ASSERT_EQ(::write(b.write_end(), "b", 1), 1);
  ASSERT_EQ(::write(a.write_end(), "a", 1), 1);
  loop.wake();
  EXPECT_TRUE(wa.ready(Wait::wait_read));
  EXPECT_TRUE(wb.ready(Wait::wait_read));
  EXPECT_FALSE(wi.ready(Wait::wait_read));
}

TEST(DescriptorWatch, BytesLeftUnreadAreReportedAgainAfterReArming) {
  Loop loop;
  Pipe p;
  DescriptorWatch w(loop.io, p.read_end());
  w.arm(Wait::wait_read);
  ASSERT_EQ(::write(p.write_end(), "abc", 3), 3);
  loop.wake();
  ASSERT_TRUE(w.take(Wait::wait_read));
  char c = 0;
  ASSERT_EQ(::read(p.read_end(), &c, 1), 1);  // "bc" stay: no new edge will come
  w.arm(Wait::wait_read);
  loop.wake();
  EXPECT_TRUE(w.take(Wait::wait_read));
}

TEST(DescriptorWatch, HangUpCompletesTheErrorWait) {
  Loop loop;
  auto pty = transport::Pty::open();
  ASSERT_TRUE(pty) << pty.error().detail;
  const int slave = ::open(pty->slave_path().c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
  ASSERT_GE(slave, 0);
  {
    DescriptorWatch w(loop.io, slave);
    w.arm(Wait::wait_error);
    loop.io.poll();
    EXPECT_FALSE(w.ready(Wait::wait_error));
    pty = transport::Pty::open();  // closes the first pair's master: its slave hangs up
    ASSERT_TRUE(pty) << pty.error().detail;
    loop.wake();
    EXPECT_TRUE(w.ready(Wait::wait_error));
  }
  EXPECT_EQ(::close(slave), 0);  // given back open, not closed by the watch
}

TEST(DescriptorWatch, ReleasesTheDescriptorWithAWaitPending) {
  Pipe p;
  {
    boost::asio::io_context io;
    DescriptorWatch w(io, p.read_end());
    w.arm(Wait::wait_read);
  }
  EXPECT_NE(::fcntl(p.read_end(), F_GETFD), -1);
  ASSERT_EQ(::write(p.write_end(), "x", 1), 1);
  char c = 0;
  EXPECT_EQ(::read(p.read_end(), &c, 1), 1);
}

}  // namespace
}  // namespace nav::dut

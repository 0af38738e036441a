// SPDX-License-Identifier: MIT
// The reactive devices' lines read on the event loop (bench/src/run/host_lines.hpp), on real
// ptys: what a DUT writes to a slave is read by the loop, stamped and announced; take() also
// reads what the loop has not yet seen, so nothing written before it is missed (lockstep);
// take_ready() hands over what the loop read; lines not asked for are never read. In lockstep
// (Reader::kTakeOnly) only take() reads, and wait_readable() waits on the lines themselves.
#include <fcntl.h>
#include <poll.h>
#include <sys/resource.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <string>
#include <thread>

#include "nav/transport/pty.hpp"
#include "run/event_loop.hpp"
#include "run/host_lines.hpp"
#include "run/wakeup.hpp"

namespace nav::bench::detail {
namespace {

using namespace std::chrono_literals;

struct Dut {
  explicit Dut(const transport::Pty& p) : fd(::open(p.slave_path().c_str(), O_RDWR | O_NOCTTY)) {}
  ~Dut() { ::close(fd); }
  void write(const std::string& s) const { ASSERT_EQ(::write(fd, s.data(), s.size()), static_cast<ssize_t>(s.size())); }
  int fd;
};

double thread_cpu_s() {
  rusage u{};
  ::getrusage(RUSAGE_THREAD, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec) * 1e-6;
}

std::string text(const std::vector<HostLines::Received>& got, std::uint32_t line) {
  std::string s;
  for (const auto& r : got) {
    if (r.line == line) s.append(r.bytes.begin(), r.bytes.end());
  }
  return s;
}

TEST(HostLines, TheLoopReadsWhatTheDutWritesStampsItAndSaysSo) {
  auto a = transport::Pty::open();
  ASSERT_TRUE(a.has_value());
  Dut dut(*a);
  EventLoop loop;
  Wakeup news;
  std::atomic<int> told{0};
  HostLines lines(loop, {a->master()}, [&] {
    ++told;
    news.notify();
  });
  const Timestamp before = monotonic_now();
  dut.write("#01\r\n");
  std::atomic<bool> stop{false};
  std::vector<HostLines::Received> got;
  const Timestamp give_up = monotonic_now() + 5s;
  while (text(got, 0).size() < 5 && monotonic_now() < give_up) {
    news.wait_until(monotonic_now() + 100ms, stop);
    for (auto& r : lines.take_ready()) got.push_back(std::move(r));
  }
  EXPECT_EQ(text(got, 0), "#01\r\n");
  EXPECT_GE(told.load(), 1);  // the player was told, it did not have to look
  ASSERT_FALSE(got.empty());
  EXPECT_GE(got.front().rx, before);
  EXPECT_LE(got.back().rx, monotonic_now());
}

TEST(HostLines, TakeReadsEverythingWrittenBeforeItLineByLineAndSkipsLinesNotAsked) {
  auto a = transport::Pty::open();
  auto b = transport::Pty::open();
  auto c = transport::Pty::open();
  ASSERT_TRUE(a && b && c);
  Dut da(*a), db(*b), dc(*c);
  EventLoop loop;
  HostLines lines(loop, {a->master(), -1, c->master()}, [] {});
  // Many rounds, each taken at once after the writes: the loop may or may not have read
  // them yet; take() must return all of them either way, in order.
  std::string want_a, want_c;
  std::string got_a, got_c;
  for (int k = 0; k < 200; ++k) {
    const std::string sa = "a" + std::to_string(k) + ";", sc = "c" + std::to_string(k) + ";";
    da.write(sa);
    db.write("b;");
    dc.write(sc);
    want_a += sa;
    want_c += sc;
    const auto got = lines.take();
    for (std::size_t i = 1; i < got.size(); ++i) EXPECT_LE(got[i - 1].line, got[i].line);
    got_a += text(got, 0);
    EXPECT_EQ(text(got, 1), "");
    got_c += text(got, 2);
    // A read of a pty master first pushes what was written to the slave, so each round is
    // whole at once.
    ASSERT_EQ(got_a, want_a) << "round " << k;
    ASSERT_EQ(got_c, want_c) << "round " << k;
  }
  EXPECT_EQ(got_a, want_a);
  EXPECT_EQ(got_c, want_c);
  // The line not asked for was never read: its bytes are all still there (read until all
  // 400 came, or 5 s: the tty layer may hand them over in pieces on a loaded machine).
  char buf[1024];
  std::size_t n = 0;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (n < 400 && std::chrono::steady_clock::now() < give_up) {
    pollfd p{b->master(), POLLIN, 0};
    if (::poll(&p, 1, 100) <= 0) continue;
    const ssize_t got = ::read(b->master(), buf + n, sizeof buf - n);
    if (got > 0) n += static_cast<std::size_t>(got);
  }
  EXPECT_EQ(n, 400u);
}

TEST(HostLines, TakeOnlyLeavesTheLinesToTakeAndWaitsOnThemItself) {
  auto a = transport::Pty::open();
  ASSERT_TRUE(a);
  Dut da(*a);
  // A line whose other end is gone (a serial adapter unplugged; here a pipe whose writer is
  // closed): hung up, always "ready", never bytes. It must not end a wait early.
  int gone[2];
  ASSERT_EQ(::pipe2(gone, O_NONBLOCK | O_CLOEXEC), 0);
  ::close(gone[1]);
  EventLoop loop;
  std::atomic<int> told{0};
  HostLines lines(loop, {a->master(), gone[0]}, [&] { ++told; }, HostLines::Reader::kTakeOnly);
  const Timestamp t0 = monotonic_now();
  const double cpu0 = thread_cpu_s();
  lines.wait_readable(t0 + 150ms);
  EXPECT_GE(monotonic_now(), t0 + 150ms);
  EXPECT_LT(thread_cpu_s() - cpu0, 0.075);  // it slept, it did not spin on the hung-up line

  // Bytes written while the wait runs end it (long before its 20 s).
  std::thread writer([&] {
    std::this_thread::sleep_for(50ms);
    da.write("#01\r\n");
  });
  const Timestamp t1 = monotonic_now();
  lines.wait_readable(t1 + 20s);
  writer.join();
  EXPECT_LT(monotonic_now(), t1 + 10s);
  const auto got = lines.take();
  EXPECT_EQ(text(got, 0), "#01\r\n");
  EXPECT_EQ(told.load(), 0);  // the loop read nothing and told nobody
  // Written before take(): taken, whole, even though nobody waited.
  da.write("#02\r\n");
  EXPECT_EQ(text(lines.take(), 0), "#02\r\n");
  ::close(gone[0]);
}

}  // namespace
}  // namespace nav::bench::detail

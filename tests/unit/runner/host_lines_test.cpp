// SPDX-License-Identifier: MIT
// The reactive devices' lines read on the event loop (bench/src/run/host_lines.hpp), on real
// ptys: what a DUT writes to a slave is read by the loop, stamped and announced; take() also
// reads what the loop has not yet seen, so nothing written before it is missed (lockstep);
// take_ready() hands over what the loop read; lines not asked for are never read.
#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <string>

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

}  // namespace
}  // namespace nav::bench::detail

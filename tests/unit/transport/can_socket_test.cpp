// SPDX-License-Identifier: MIT
// CanSocket on a live vcan0: two sockets exchange 11- and 29-bit frames of every DLC and RTR
// frames; the kernel's loopback rules; and interop with can-utils as an independent peer
// (style.md "Shared codecs are a trap"): `cansend` frames reach CanSocket, and CanSocket's
// frames are logged by `candump -L` exactly as sent.
//
// ctest runs this binary through scripts/with-vcan (label vcan), which brings vcan0 up on the
// host or inside user-mode Linux. Run directly without vcan0, the vcan cases skip, except
// under CI (CI=true), where a missing vcan0 or can-utils is a failure.
//
//   test                           vcan0                          candump -L vcan0 (child)
//   ----                           -----                          ------------------------
//   send sync frame 0x7FF, every 20 ms  -------------------->  logs "(t) vcan0 7FF#"
//   ... until its line arrives (candump is bound; bounded wait)
//   send the frames under test  ---------------------------->  logs one line per frame
//   read lines until the last frame's line (bounded), SIGTERM candump, compare
#include <fcntl.h>
#include <net/if.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <ostream>
#include <regex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "can_test_support.hpp"
#include "nav/transport/can_socket.hpp"

extern char** environ;

namespace nav::transport {
namespace {

using namespace std::chrono_literals;

constexpr const char* kIface = "vcan0";
constexpr auto kWait = 2s;  ///< bound on every wait for a frame or a log line

using test_support::program_on_path;

std::string describe(const CanFrame& f) {
  char head[32];
  std::snprintf(head, sizeof(head), f.extended ? "%08X#" : "%03X#", static_cast<unsigned>(f.id));
  std::string s = head;
  if (f.rtr) return s + "R" + std::to_string(f.dlc);
  for (int i = 0; i < f.dlc; ++i) {
    char b[4];
    std::snprintf(b, sizeof(b), "%02X", f.data[static_cast<std::size_t>(i)]);
    s += b;
  }
  return s;
}

}  // namespace

// gtest prints frames in cansend notation (found by ADL, so outside the unnamed namespace).
void PrintTo(const CanFrame& f, std::ostream* os) { *os << describe(f); }

namespace {

CanFrame make_frame(std::uint32_t id, bool extended, std::uint8_t dlc) {
  CanFrame f;
  f.id = id;
  f.extended = extended;
  f.dlc = dlc;
  for (std::size_t i = 0; i < dlc; ++i) f.data[i] = static_cast<std::uint8_t>(0xA0 + 16 * i + dlc);
  return f;
}

Result<CanSocket> open_or_die(const CanSocketOptions& options = {}) {
  auto s = CanSocket::open(kIface, options);
  EXPECT_TRUE(s.has_value()) << (s ? "" : s.error().detail);
  return s;
}

/// Waits (bounded) for the next frame on `socket`.
std::optional<ReceivedCanFrame> receive_within(CanSocket& socket,
                                               std::chrono::milliseconds timeout = kWait) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    auto r = socket.receive();
    if (!r) {
      ADD_FAILURE() << r.error().detail;
      return std::nullopt;
    }
    if (r->has_value()) return **r;
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return std::nullopt;
    pollfd p{socket.fd(), POLLIN, 0};
    ::poll(&p, 1, static_cast<int>(left.count()));
  }
}

/// True when nothing arrives on `socket` within `quiet`.
bool stays_quiet(CanSocket& socket, std::chrono::milliseconds quiet = 200ms) {
  return !receive_within(socket, quiet).has_value();
}

void drain(CanSocket& socket) {
  while (receive_within(socket, 20ms).has_value()) {
  }
}

// ---------------------------------------------------------------------------------------
// Without vcan0: opening errors.

TEST(CanSocketOpen, MissingInterfaceNamesItAndTheReason) {
  auto s = CanSocket::open("navnosuch0");
  ASSERT_FALSE(s.has_value());
  EXPECT_EQ(s.error().code, ErrorCode::kNotFound);
  EXPECT_EQ(s.error().detail, "cannot open CAN interface navnosuch0: No such device");
}

TEST(CanSocketOpen, NameThatCannotBeAnInterfaceIsRejected) {
  for (const std::string& name : {std::string(), std::string(IFNAMSIZ, 'x')}) {
    auto s = CanSocket::open(name);
    ASSERT_FALSE(s.has_value()) << name;
    EXPECT_EQ(s.error().code, ErrorCode::kInvalidArgument) << s.error().detail;
  }
}

TEST(CanFrameEquality, IgnoresBytesPastDlcAndRtrData) {
  CanFrame a = make_frame(0x123, false, 2);
  CanFrame b = a;
  b.data[5] = 0x55;
  EXPECT_EQ(a, b);
  b.data[1] ^= 1;
  EXPECT_NE(a, b);
  a.rtr = b.rtr = true;
  EXPECT_EQ(a, b);
  b.extended = true;
  EXPECT_NE(a, b);
}

// ---------------------------------------------------------------------------------------
// Two CanSockets on vcan0.

class CanSocketVcan : public ::testing::Test {
 protected:
  void SetUp() override {
    REQUIRE_VCAN();
    auto a = open_or_die();
    auto b = open_or_die();
    ASSERT_TRUE(a && b);
    a_.emplace(std::move(*a));
    b_.emplace(std::move(*b));
    drain(*b_);
  }

  /// Sends every frame from a_ and expects b_ to receive exactly them, in order.
  void exchange(const std::vector<CanFrame>& frames) {
    const auto before = std::chrono::system_clock::now();
    for (const auto& f : frames) {
      auto sent = a_->send(f);
      ASSERT_TRUE(sent.has_value()) << sent.error().detail;
    }
    for (const auto& f : frames) {
      auto got = receive_within(*b_);
      ASSERT_TRUE(got.has_value()) << "no frame received, expected " << describe(f);
      EXPECT_EQ(got->frame, f) << "got " << describe(got->frame);
      ASSERT_TRUE(got->kernel_time.has_value()) << "no SO_TIMESTAMPNS stamp";
      const auto stamp = std::chrono::system_clock::time_point(
          std::chrono::duration_cast<std::chrono::system_clock::duration>(*got->kernel_time));
      EXPECT_GE(stamp, before - 1s);
      EXPECT_LE(stamp, std::chrono::system_clock::now() + 1s);
    }
    EXPECT_TRUE(stays_quiet(*b_, 50ms)) << "more frames than sent";
    EXPECT_TRUE(stays_quiet(*a_, 50ms)) << "the sender received its own frames";
  }

  std::optional<CanSocket> a_, b_;
};

TEST_F(CanSocketVcan, StandardFramesOfEveryDlc) {
  std::vector<CanFrame> frames;
  for (std::uint8_t dlc = 0; dlc <= 8; ++dlc) frames.push_back(make_frame(0x100u + dlc, false, dlc));
  frames.push_back(make_frame(0x000, false, 1));
  frames.push_back(make_frame(CanFrame::kMaxStandardId, false, 8));
  exchange(frames);
}

TEST_F(CanSocketVcan, ExtendedFramesOfEveryDlc) {
  std::vector<CanFrame> frames;
  // 0x09F80100 + dlc: priority 2, PGN 129025 (position rapid), source 0..8, as NMEA 2000 uses.
  for (std::uint8_t dlc = 0; dlc <= 8; ++dlc) frames.push_back(make_frame(0x09F80100u + dlc, true, dlc));
  frames.push_back(make_frame(0x000, true, 0));  // 29-bit 0 is not 11-bit 0
  frames.push_back(make_frame(CanFrame::kMaxExtendedId, true, 8));
  exchange(frames);
}

TEST_F(CanSocketVcan, RemoteFrames) {
  CanFrame standard = make_frame(0x321, false, 4);
  standard.rtr = true;
  CanFrame extended = make_frame(0x18EAFF00, true, 3);  // ISO request PGN, as N2K asks
  extended.rtr = true;
  CanFrame empty = make_frame(0x7FF, false, 0);
  empty.rtr = true;
  exchange({standard, extended, empty});
}

TEST_F(CanSocketVcan, OwnFramesComeBackOnlyWhenAsked) {
  CanSocketOptions own;
  own.receive_own_frames = true;
  auto c = open_or_die(own);
  ASSERT_TRUE(c);
  const CanFrame f = make_frame(0x42, false, 3);
  ASSERT_TRUE(c->send(f).has_value());
  auto echoed = receive_within(*c);
  ASSERT_TRUE(echoed.has_value()) << "receive_own_frames: the sender did not get its frame";
  EXPECT_EQ(echoed->frame, f);
  auto other = receive_within(*b_);
  ASSERT_TRUE(other.has_value());
  EXPECT_EQ(other->frame, f);
}

TEST_F(CanSocketVcan, LoopbackOffKeepsFramesFromOtherLocalSockets) {
  CanSocketOptions quiet;
  quiet.loopback = false;
  auto c = open_or_die(quiet);
  ASSERT_TRUE(c);
  ASSERT_TRUE(c->send(make_frame(0x43, false, 1)).has_value());
  EXPECT_TRUE(stays_quiet(*b_));
}

// An error frame (CAN_ERR_FLAG), as a controller driver reports one and as the bench plays it
// on a virtual bus: it reaches only the sockets that asked for its class.
TEST_F(CanSocketVcan, ErrorFramesReachOnlySocketsThatAskForThem) {
  CanSocketOptions errors;
  errors.error_classes = 0x1FFFFFFF;
  auto listener = open_or_die(errors);
  ASSERT_TRUE(listener);
  CanFrame e;
  e.error = true;
  e.id = 0x208;  // CAN_ERR_PROT | CAN_ERR_CNT
  e.dlc = 8;
  e.data[3] = 0x08;
  e.data[7] = 5;
  ASSERT_TRUE(a_->send(e).has_value());
  auto heard = receive_within(*listener);
  ASSERT_TRUE(heard.has_value()) << "the error frame did not arrive";
  EXPECT_TRUE(heard->frame.error);
  EXPECT_EQ(heard->frame.id, 0x208u);
  EXPECT_EQ(heard->frame, e);
  EXPECT_TRUE(stays_quiet(*b_));  // b_ did not ask for error frames
}

TEST_F(CanSocketVcan, FdPollsReadableWhenAFrameWaits) {
  pollfd p{b_->fd(), POLLIN, 0};
  EXPECT_EQ(::poll(&p, 1, 0), 0);
  auto r = b_->receive();
  ASSERT_TRUE(r.has_value());
  EXPECT_FALSE(r->has_value()) << "receive() on an empty socket returns nothing";
  ASSERT_TRUE(a_->send(make_frame(0x44, false, 0)).has_value());
  EXPECT_EQ(::poll(&p, 1, static_cast<int>(std::chrono::milliseconds(kWait).count())), 1);
  EXPECT_NE(p.revents & POLLIN, 0);
}

TEST_F(CanSocketVcan, ImpossibleFramesAreRejectedBeforeTheWire) {
  const CanFrame bad[] = {make_frame(CanFrame::kMaxStandardId + 1, false, 0),
                          make_frame(CanFrame::kMaxExtendedId + 1, true, 0),
                          [] {
                            CanFrame f = make_frame(0x1, false, 8);
                            f.dlc = 9;
                            return f;
                          }()};
  for (const auto& f : bad) {
    auto r = a_->send(f);
    ASSERT_FALSE(r.has_value()) << describe(f);
    EXPECT_EQ(r.error().code, ErrorCode::kInvalidArgument);
    EXPECT_NE(r.error().detail.find("vcan0"), std::string::npos) << r.error().detail;
  }
  EXPECT_TRUE(stays_quiet(*b_));
}

TEST_F(CanSocketVcan, MovedSocketKeepsWorking) {
  CanSocket moved = std::move(*a_);
  EXPECT_EQ(a_->fd(), -1);
  EXPECT_EQ(moved.ifname(), "vcan0");
  const CanFrame f = make_frame(0x45, false, 2);
  ASSERT_TRUE(moved.send(f).has_value());
  auto got = receive_within(*b_);
  ASSERT_TRUE(got.has_value());
  EXPECT_EQ(got->frame, f);
  a_.reset();  // destroying a moved-from socket closes nothing
}

// ---------------------------------------------------------------------------------------
// Interop with can-utils.

/// A child process with its stdout on a pipe; killed (SIGTERM, then SIGKILL) and reaped on
/// destruction.
class Child {
 public:
  explicit Child(std::vector<std::string> argv) {
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) return;
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_adddup2(&fa, fds[1], 1);
    std::vector<char*> args;
    for (auto& a : argv) args.push_back(a.data());
    args.push_back(nullptr);
    if (::posix_spawnp(&pid_, args[0], &fa, nullptr, args.data(), environ) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&fa);
    ::close(fds[1]);
    out_ = fds[0];
    ::fcntl(out_, F_SETFL, O_NONBLOCK);
  }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;
  ~Child() {
    stop();
    if (out_ >= 0) ::close(out_);
  }

  bool started() const { return pid_ > 0; }

  /// The next complete stdout line, waiting at most `timeout`.
  std::optional<std::string> read_line(std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
      const auto nl = buffer_.find('\n');
      if (nl != std::string::npos) {
        std::string line = buffer_.substr(0, nl);
        buffer_.erase(0, nl + 1);
        return line;
      }
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
          deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) return std::nullopt;
      pollfd p{out_, POLLIN, 0};
      if (::poll(&p, 1, static_cast<int>(left.count())) <= 0) continue;
      char chunk[4096];
      const ssize_t n = ::read(out_, chunk, sizeof(chunk));
      if (n == 0) return std::nullopt;  // the child closed its stdout
      if (n > 0) buffer_.append(chunk, static_cast<std::size_t>(n));
    }
  }

  /// Stops the child (SIGTERM, SIGKILL after 1 s) and returns its wait status.
  int stop() {
    if (pid_ <= 0) return status_;
    ::kill(pid_, SIGTERM);
    for (int i = 0; i < 100; ++i) {
      if (::waitpid(pid_, &status_, WNOHANG) == pid_) {
        pid_ = -1;
        return status_;
      }
      std::this_thread::sleep_for(10ms);
    }
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, &status_, 0);
    pid_ = -1;
    return status_;
  }

 private:
  pid_t pid_ = -1;
  int out_ = -1;
  int status_ = 0;
  std::string buffer_;
};

/// Runs a program to its end; its exit status, or -1 when it could not be run.
int run(std::vector<std::string> argv) {
  std::vector<char*> args;
  for (auto& a : argv) args.push_back(a.data());
  args.push_back(nullptr);
  pid_t pid = -1;
  if (::posix_spawnp(&pid, args[0], nullptr, nullptr, args.data(), environ) != 0) return -1;
  int status = 0;
  if (::waitpid(pid, &status, 0) != pid) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// One line of `candump -L`: "(1700000000.123456) vcan0 123#DEADBEEF" (RTR: "123#R", newer
/// can-utils "123#R4"). An 8-digit identifier is an extended one.
struct CandumpLine {
  double time_s = 0;  ///< receive time [s since the Unix epoch]
  std::string iface;
  CanFrame frame;
};

std::optional<CandumpLine> parse_candump_line(const std::string& line) {
  static const std::regex re(
      R"(^\((\d+\.\d{6})\) (\S+) ([0-9A-F]{3}|[0-9A-F]{8})#(R[0-8]?|(?:[0-9A-F]{2}){0,8})$)");
  std::smatch m;
  if (!std::regex_match(line, m, re)) return std::nullopt;
  CandumpLine out;
  out.time_s = std::stod(m[1].str());
  out.iface = m[2].str();
  out.frame.extended = m[3].length() == 8;
  out.frame.id = static_cast<std::uint32_t>(std::stoul(m[3].str(), nullptr, 16));
  const std::string payload = m[4].str();
  if (!payload.empty() && payload[0] == 'R') {
    out.frame.rtr = true;
    out.frame.dlc = payload.size() > 1 ? static_cast<std::uint8_t>(payload[1] - '0') : 0;
    return out;
  }
  out.frame.dlc = static_cast<std::uint8_t>(payload.size() / 2);
  for (std::size_t i = 0; i < out.frame.dlc; ++i) {
    out.frame.data[i] = static_cast<std::uint8_t>(std::stoul(payload.substr(2 * i, 2), nullptr, 16));
  }
  return out;
}

TEST(CandumpLineFormat, ParsesTheFormsCandumpWrites) {
  auto a = parse_candump_line("(1700000000.123456) vcan0 123#DEADBEEF");
  ASSERT_TRUE(a.has_value());
  EXPECT_EQ(a->iface, "vcan0");
  EXPECT_DOUBLE_EQ(a->time_s, 1700000000.123456);
  EXPECT_EQ(describe(a->frame), "123#DEADBEEF");
  auto b = parse_candump_line("(1.000000) can0 09F80100#");
  ASSERT_TRUE(b.has_value());
  EXPECT_TRUE(b->frame.extended);
  EXPECT_EQ(b->frame.dlc, 0);
  auto c = parse_candump_line("(1.000000) can0 321#R");
  ASSERT_TRUE(c.has_value());
  EXPECT_TRUE(c->frame.rtr);
  EXPECT_FALSE(parse_candump_line("(1.0) can0 321#R").has_value());
  EXPECT_FALSE(parse_candump_line("(1.000000) can0 1234#00").has_value());
}

class CanUtilsInterop : public ::testing::Test {
 protected:
  void SetUp() override {
    REQUIRE_VCAN();
    REQUIRE_OR_SKIP(program_on_path("cansend") && program_on_path("candump"),
                    "can-utils (cansend, candump) not installed: run scripts/setup");
  }
};

TEST_F(CanUtilsInterop, CansendFramesReachCanSocket) {
  auto rx = open_or_die();
  ASSERT_TRUE(rx);
  drain(*rx);
  struct Case {
    const char* text;
    CanFrame expected;
  };
  CanFrame deadbeef = make_frame(0x123, false, 4);
  deadbeef.data = {0xDE, 0xAD, 0xBE, 0xEF};
  CanFrame extended = make_frame(0x1F334455, true, 8);
  extended.data = {0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88};
  CanFrame empty = make_frame(0x5A5, false, 0);
  CanFrame remote = make_frame(0x7E0, false, 0);
  remote.rtr = true;
  for (const auto& c : {Case{"123#DEADBEEF", deadbeef}, Case{"1F334455#1122334455667788", extended},
                        Case{"5A5#", empty}, Case{"7E0#R", remote}}) {
    ASSERT_EQ(run({"cansend", kIface, c.text}), 0) << "cansend vcan0 " << c.text;
    auto got = receive_within(*rx);
    ASSERT_TRUE(got.has_value()) << "nothing received after cansend vcan0 " << c.text;
    EXPECT_EQ(got->frame, c.expected) << c.text << " arrived as " << describe(got->frame);
  }
  EXPECT_TRUE(stays_quiet(*rx, 50ms));
}

TEST_F(CanUtilsInterop, CandumpLogsCanSocketFramesAsSent) {
  auto tx = open_or_die();
  ASSERT_TRUE(tx);
  Child candump({"candump", "-L", kIface});
  ASSERT_TRUE(candump.started()) << "cannot start candump";

  // candump prints nothing until a frame arrives: send a sync frame until its line shows
  // that candump's socket is bound.
  const CanFrame sync = make_frame(CanFrame::kMaxStandardId, false, 0);
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  bool synced = false;
  while (!synced && std::chrono::steady_clock::now() < deadline) {
    ASSERT_TRUE(tx->send(sync).has_value());
    while (auto line = candump.read_line(20ms)) {
      auto parsed = parse_candump_line(*line);
      if (parsed && parsed->frame == sync) synced = true;
    }
  }
  ASSERT_TRUE(synced) << "candump -L vcan0 logged no sync frame within 5 s";

  std::vector<CanFrame> frames;
  CanFrame deadbeef = make_frame(0x123, false, 4);
  deadbeef.data = {0xDE, 0xAD, 0xBE, 0xEF};
  frames.push_back(deadbeef);
  for (std::uint8_t dlc = 0; dlc <= 8; ++dlc) frames.push_back(make_frame(0x09F80100u + dlc, true, dlc));
  CanFrame remote = make_frame(0x7E0, false, 0);
  remote.rtr = true;
  frames.push_back(remote);
  frames.push_back(make_frame(0x000, false, 8));

  const double before_s = std::chrono::duration<double>(
      std::chrono::system_clock::now().time_since_epoch()).count();
  for (const auto& f : frames) ASSERT_TRUE(tx->send(f).has_value());

  std::vector<CandumpLine> logged;
  std::vector<std::string> raw;
  while (logged.size() < frames.size()) {
    auto line = candump.read_line(kWait);
    if (!line) break;
    raw.push_back(*line);
    auto parsed = parse_candump_line(*line);
    ASSERT_TRUE(parsed.has_value()) << "not a candump -L line: '" << *line << "'";
    if (parsed->frame == sync) continue;  // a late sync frame
    logged.push_back(*parsed);
  }
  const int status = candump.stop();
  EXPECT_TRUE(WIFSIGNALED(status) || (WIFEXITED(status) && WEXITSTATUS(status) == 0))
      << "candump wait status " << status;

  ASSERT_EQ(logged.size(), frames.size()) << "candump logged " << raw.size() << " lines";
  for (std::size_t i = 0; i < frames.size(); ++i) {
    EXPECT_EQ(logged[i].iface, "vcan0");
    if (frames[i].rtr) {
      // can-utils 2020.11 writes "7E0#R" without the length; the rest must match.
      CanFrame want = frames[i];
      want.dlc = logged[i].frame.dlc;
      EXPECT_EQ(logged[i].frame, want) << raw[i];
    } else {
      EXPECT_EQ(logged[i].frame, frames[i]) << raw[i];
    }
    EXPECT_GE(logged[i].time_s, before_s - 1.0) << raw[i];
  }
}

}  // namespace
}  // namespace nav::transport

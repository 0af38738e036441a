// SPDX-License-Identifier: MIT
// `navbench record --can` and `navbench replay` of candump logs on a live vcan0, with can-utils
// as the independent peer (cansend writes, canplayer replays), and canplayer into navd.
//
//   record:  cansend ──▶ vcan0 ──▶ navbench record --can vcan0 ──▶ rec.log (candump -l)
//            rec.log ──▶ canplayer -I ──▶ vcan0 ──▶ CanSocket listener (frames, gaps)
//   replay:  hand-written candump log (gaps 50..150 ms, interface can7) ──▶ navbench replay
//            --can can7=vcan0 ──▶ vcan0 ──▶ CanSocket listener (frames, kernel-time gaps)
//   navd:    N2K frames (nmea2000 encoders) as a candump log ──▶ canplayer ──▶ vcan0 ──▶ navd
//            --can vcan0 (AHRS and output on ptys): its exit summary counts them
//   errors:  malformed line / screen print ──▶ exit 2 with FILE:LINE; no interface ──▶ exit 3
//
// ctest runs this binary through scripts/with-vcan (label vcan). Run directly without vcan0,
// the vcan cases skip, except under CI (CI=true). Timing tolerances suit a loaded VM (user-mode
// Linux): gaps of at least 50 ms are checked to 20 ms plus the largest lateness the bench
// reports for itself (a loaded machine delays the bench, which says so; the test judges that
// the frames leave at their deadlines, not the machine), after a --startup wait so that the
// first frame is not late for the replay's own start-up.
#include <net/if.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "../unit/navd/navd_pty_harness.hpp"
#include "can_log.hpp"
#include "can_test_support.hpp"
#include "nav/protocols/can_frame.hpp"
#include "nav/protocols/candump_log.hpp"
#include "nav/protocols/nmea2000.hpp"
#include "nav/transport/can_socket.hpp"
#include "source_paths.hpp"

namespace nav::testing {
namespace {

namespace fs = std::filesystem;
namespace cd = protocols::candump;
namespace n2k = protocols::n2k;
using Clock = std::chrono::steady_clock;
using transport::CanFrame;
using transport::CanSocket;

constexpr const char* kIface = "vcan0";

using test_support::Heard;
using test_support::program_on_path;
using test_support::receive_frames;
using test_support::to_socket;

// vcan0 and the can-utils that play logs onto it (cansend, canplayer).
#define REQUIRE_VCAN_AND_PLAYER()                                                     \
  REQUIRE_VCAN();                                                                     \
  REQUIRE_OR_SKIP(program_on_path("cansend") && program_on_path("canplayer"),         \
                  "can-utils (cansend, canplayer) not installed: run scripts/setup")

/// A child process (stdout and stderr to files in `cwd`), waited for with a bound.
struct Child {
  pid_t pid = -1;
  fs::path out, err;
  int exit_code = -1;

  Child() = default;
  Child(Child&& o) noexcept
      : pid(std::exchange(o.pid, -1)), out(std::move(o.out)), err(std::move(o.err)),
        exit_code(o.exit_code) {}
  Child& operator=(Child&&) = delete;
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  static Child spawn(const std::vector<std::string>& argv_strings, const fs::path& cwd,
                     const std::string& tag) {
    Child c;
    c.out = cwd / (tag + "-stdout.txt");
    c.err = cwd / (tag + "-stderr.txt");
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, c.out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&fa, 2, c.err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addchdir_np(&fa, cwd.c_str());
    std::vector<char*> argv;
    for (const auto& a : argv_strings) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    if (::posix_spawnp(&c.pid, argv[0], &fa, nullptr, argv.data(), environ) != 0) c.pid = -1;
    posix_spawn_file_actions_destroy(&fa);
    return c;
  }
  bool wait_for_output(const std::string& text, double timeout_s) const {
    const auto end = Clock::now() + std::chrono::duration<double>(timeout_s);
    while (Clock::now() < end) {
      if (slurp(out).find(text) != std::string::npos) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  }
  /// Waits for the exit (SIGKILL after `timeout_s`); the exit code, -1 if killed.
  int wait(double timeout_s) {
    const auto end = Clock::now() + std::chrono::duration<double>(timeout_s);
    while (pid > 0) {
      int status = 0;
      if (::waitpid(pid, &status, WNOHANG) == pid) {
        exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        pid = -1;
        break;
      }
      if (Clock::now() > end) {
        ::kill(pid, SIGKILL);
        ::waitpid(pid, &status, 0);
        pid = -1;
        exit_code = -1;
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return exit_code;
  }
  ~Child() {
    if (pid > 0) wait(0.0);
  }
};

/// A fresh empty folder for one test.
fs::path fresh_dir(const std::string& name) {
  const auto d = fs::path(::testing::TempDir()) /
                 ("navbench-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

struct ProcessResult {
  int exit_code = -1;
  std::string out, err;
};

/// Runs `navbench args...` in `cwd` to its end (at most 60 s).
ProcessResult run_navbench(const std::vector<std::string>& args, const fs::path& cwd) {
  std::vector<std::string> argv{nav::test_paths::binary_dir() + "/navbench"};
  argv.insert(argv.end(), args.begin(), args.end());
  Child c = Child::spawn(argv, cwd, "navbench");
  ProcessResult r;
  r.exit_code = c.wait(60.0);
  r.out = slurp(c.out);
  r.err = slurp(c.err);
  return r;
}

CanFrame make_frame(std::uint32_t id, bool extended, std::vector<std::uint8_t> data) {
  CanFrame f;
  f.id = id;
  f.extended = extended;
  f.dlc = static_cast<std::uint8_t>(data.size());
  std::copy(data.begin(), data.end(), f.data.begin());
  return f;
}

CanFrame from_record(const cd::Record& r) { return to_socket(r.frame); }

/// A candump -l line at `t_s` (epoch seconds) on `iface`.
std::string log_line(double t_s, const std::string& iface, const CanFrame& f) {
  cd::Record r;
  const auto us = static_cast<std::uint64_t>(std::llround(t_s * 1e6));
  r.time = cd::Timestamp{us / 1'000'000, static_cast<std::uint32_t>(us % 1'000'000) * 1000, 6,
                         10};
  r.interface = iface;
  r.frame.id = f.id;
  r.frame.extended = f.extended;
  r.frame.rtr = f.rtr;
  r.frame.dlc = f.dlc;
  r.frame.data = f.data;
  return cd::format_line(r);
}

// (a) record --can vcan0 while cansend writes; the log is candump -l that canplayer replays.
TEST(NavbenchCanRecord, RecordsCansendFramesAndCanplayerReplaysTheLog) {
  REQUIRE_VCAN_AND_PLAYER();
  const auto dir = fresh_dir("can-record");
  Child rec = Child::spawn({nav::test_paths::binary_dir() + "/navbench", "record", "--can", kIface,
                            "--duration", "2.5", "--out", "rec.log"},
                           dir, "record");
  ASSERT_GT(rec.pid, 0);
  ASSERT_TRUE(rec.wait_for_output("recording to rec.log", 10.0)) << slurp(rec.err);
  const std::vector<std::string> sent{"123#DEADBEEF", "09F11201#005C3DFF7FFF7FFC", "7FF#",
                                      "1ABCDEF0#0102030405060708"};
  for (const auto& s : sent) {
    Child c = Child::spawn({"cansend", kIface, s}, dir, "cansend");
    ASSERT_EQ(c.wait(10.0), 0) << s << ": " << slurp(c.err);
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
  }
  ASSERT_EQ(rec.wait(20.0), 0) << slurp(rec.err);
  EXPECT_NE(slurp(rec.out).find("navbench record: vcan0 4 frames; 4 frames in"),
            std::string::npos)
      << slurp(rec.out);
  EXPECT_FALSE(fs::exists(dir / "rec.log.partial"));
  const auto log = read_log(dir / "rec.log");
  ASSERT_EQ(log.size(), sent.size()) << slurp(dir / "rec.log");
  for (std::size_t i = 0; i < log.size(); ++i) {
    EXPECT_EQ(log[i].interface, kIface);
    EXPECT_EQ(cd::format_frame(log[i].frame), sent[i]);
    ASSERT_TRUE(log[i].time.has_value());
    EXPECT_EQ(log[i].time->decimals, 6);
    EXPECT_GT(log[i].time->seconds, 1'500'000'000u) << "an epoch time, as candump -l writes";
    if (i > 0) {
      const double gap = log[i].time->to_seconds() - log[i - 1].time->to_seconds();
      EXPECT_GT(gap, 0.1) << "frame " << i;  // 150 ms sleeps between the cansends
      EXPECT_LT(gap, 2.0) << "frame " << i;
    }
  }

  // canplayer accepts the log and plays the same frames onto vcan0 with its gaps, heard by a
  // CanSocket and by `candump -L vcan0`.
  auto listener = CanSocket::open(kIface);
  ASSERT_TRUE(listener) << listener.error().detail;
  std::optional<Child> dump;
  if (program_on_path("candump") && program_on_path("stdbuf")) {
    dump.emplace(Child::spawn({"stdbuf", "-oL", "candump", "-L", kIface}, dir, "candump"));
    // candump prints nothing until a frame arrives: a sync frame until its line shows that
    // candump's socket is bound (stdbuf -oL: candump's stdout is a file, line-buffered).
    auto sync = CanSocket::open(kIface);
    ASSERT_TRUE(sync) << sync.error().detail;
    const auto end = Clock::now() + std::chrono::seconds(5);
    bool synced = false;
    while (!synced && Clock::now() < end) {
      ASSERT_TRUE(sync->send(make_frame(0x7FE, false, {})));
      synced = dump->wait_for_output(" vcan0 7FE#", 0.05);
    }
    ASSERT_TRUE(synced) << "candump -L vcan0 logged no sync frame within 5 s";
    // Drain the sync frames from the listener (it heard them too).
    while (true) {
      auto r = listener->receive();
      ASSERT_TRUE(r) << r.error().detail;
      if (!r->has_value()) break;
    }
  }
  Child player = Child::spawn({"canplayer", "-I", (dir / "rec.log").string()}, dir, "canplayer");
  ASSERT_EQ(player.wait(20.0), 0) << slurp(player.err);
  const auto heard = receive_frames(*listener, log.size(), 5.0);
  ASSERT_EQ(heard.size(), log.size());
  for (std::size_t i = 0; i < heard.size(); ++i) {
    EXPECT_EQ(heard[i].frame, from_record(log[i])) << "frame " << i;
    if (i > 0 && heard[i].t_s > 0 && heard[i - 1].t_s > 0) {
      const double want = log[i].time->to_seconds() - log[i - 1].time->to_seconds();
      EXPECT_NEAR(heard[i].t_s - heard[i - 1].t_s, want, 0.1) << "gap before frame " << i;
    }
  }
  if (dump) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    ::kill(dump->pid, SIGTERM);
    dump->wait(5.0);
    std::vector<cd::Record> dumped;
    for (const auto& r : read_log(dump->out)) {
      if (cd::format_frame(r.frame) != "7FE#") dumped.push_back(r);
    }
    ASSERT_EQ(dumped.size(), sent.size()) << slurp(dump->out);
    for (std::size_t i = 0; i < dumped.size(); ++i) {
      EXPECT_EQ(cd::format_frame(dumped[i].frame), sent[i]) << "candump line " << i;
      EXPECT_EQ(dumped[i].interface, kIface);
    }
  }
  if (!HasFailure()) fs::remove_all(dir);
}

TEST(NavbenchCanRecord, StopsCleanlyOnSigterm) {
  REQUIRE_VCAN_AND_PLAYER();
  const auto dir = fresh_dir("can-record-term");
  Child rec = Child::spawn({nav::test_paths::binary_dir() + "/navbench", "record", "--can", kIface,
                            "-o", "rec.log"},
                           dir, "record");
  ASSERT_TRUE(rec.wait_for_output("until SIGINT/SIGTERM", 10.0)) << slurp(rec.err);
  auto sender = CanSocket::open(kIface);
  ASSERT_TRUE(sender) << sender.error().detail;
  ASSERT_TRUE(sender->send(make_frame(0x321, false, {1, 2, 3})));
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  ::kill(rec.pid, SIGTERM);
  ASSERT_EQ(rec.wait(10.0), 0) << slurp(rec.err);
  EXPECT_NE(slurp(rec.out).find("(stopped by signal)"), std::string::npos) << slurp(rec.out);
  const auto log = read_log(dir / "rec.log");
  ASSERT_EQ(log.size(), 1u);
  EXPECT_EQ(cd::format_frame(log[0].frame), "321#010203");
  if (!HasFailure()) fs::remove_all(dir);
}

// (b) replay of a candump log with known gaps onto vcan0 (interface mapped), timing kept.
TEST(NavbenchCanReplay, ReproducesTheFramesAndTheirGaps) {
  REQUIRE_VCAN_AND_PLAYER();
  const auto dir = fresh_dir("can-replay");
  const std::vector<CanFrame> frames{
      make_frame(0x100, false, {0x01}),
      make_frame(0x09F11201, true, {0x00, 0x5C, 0x3D, 0xFF, 0x7F, 0xFF, 0x7F, 0xFC}),
      make_frame(0x101, false, {}),
      make_frame(0x102, false, {0xAA, 0xBB}),
      make_frame(0x1FFFFFFF, true, {1, 2, 3, 4, 5, 6, 7, 8}),
      make_frame(0x7FF, false, {0x55})};
  // [s]; at --speed 2 still at least 50 ms.
  const std::vector<double> gaps{0.200, 0.100, 0.300, 0.160, 0.120};
  {
    std::ofstream log(dir / "gaps.log");
    double t = 1700000000.250000;
    for (std::size_t i = 0; i < frames.size(); ++i) {
      if (i > 0) t += gaps[i - 1];
      log << log_line(t, "can7", frames[i]) << "\n";
    }
  }
  for (const double speed : {1.0, 2.0}) {
    SCOPED_TRACE("speed " + std::to_string(speed));
    auto listener = CanSocket::open(kIface);
    ASSERT_TRUE(listener) << listener.error().detail;
    const auto r = run_navbench({"replay", "gaps.log", "--can", "can7=" + std::string(kIface),
                                 "--speed", std::to_string(speed), "--startup", "0.3"},
                                dir);
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    std::printf("%s", r.out.c_str());  // the summary, with the bench's own lateness
    // A gap is off by at most the difference of two frames' lateness, which the bench measures
    // and reports: allow that (bounded) on top of 20 ms for the kernel and the VM.
    std::smatch m;
    ASSERT_TRUE(std::regex_search(r.out, m, std::regex(R"(max (\d+\.\d+) ms)"))) << r.out;
    const double max_late_s = std::stod(m[1]) * 1e-3;
    EXPECT_LT(max_late_s, 0.2) << "the bench was very late: " << r.out;
    const double tolerance_s = 0.020 + max_late_s;
    EXPECT_NE(r.out.find("navbench replay: 1 CAN interfaces (can7->vcan0), 6 frames in "),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("lateness p50 "), std::string::npos) << r.out;
    const auto heard = receive_frames(*listener, frames.size(), 5.0);
    ASSERT_EQ(heard.size(), frames.size());
    for (std::size_t i = 0; i < frames.size(); ++i) {
      EXPECT_EQ(heard[i].frame, frames[i]) << "frame " << i;
      if (i == 0) continue;
      ASSERT_GT(heard[i].t_s, 0.0) << "no kernel receive time";
      EXPECT_NEAR(heard[i].t_s - heard[i - 1].t_s, gaps[i - 1] / speed, tolerance_s)
          << "gap before frame " << i;
    }
  }
  // --format candump works the same; auto detection was used above.
  auto listener = CanSocket::open(kIface);
  ASSERT_TRUE(listener) << listener.error().detail;
  const auto r = run_navbench({"replay", "gaps.log", "--format", "candump", "--can",
                               "can7=" + std::string(kIface), "--speed", "10", "--startup", "0"},
                              dir);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_EQ(receive_frames(*listener, frames.size(), 5.0).size(), frames.size());
  if (!HasFailure()) fs::remove_all(dir);
}

// --dut works with a candump log: here candump itself is the DUT, {can:LOGNAME} its interface
// (a DUT that answers nothing: exit 4, after the whole log was played to it).
TEST(NavbenchCanReplay, StartsADutWithTheCanInterfaceInItsArguments) {
  REQUIRE_VCAN_AND_PLAYER();
  REQUIRE_OR_SKIP(program_on_path("candump"), "candump (can-utils) not installed");
  const auto dir = fresh_dir("can-replay-dut");
  {
    std::ofstream log(dir / "dut.log");
    log << log_line(1700000000.0, "can7", make_frame(0x111, false, {0x11})) << "\n"
        << log_line(1700000000.1, "can7", make_frame(0x222, false, {0x22, 0x33})) << "\n";
  }
  const auto r = run_navbench({"replay", "dut.log", "--can", "can7=vcan0", "--startup", "1",
                               "--dut-log", "candump.txt", "--dut", "--", "candump", "-L",
                               "{can:can7}"},
                              dir);
  // candump writes no $PNVBSOL solution: the replay ran, and says the DUT gave none (exit 4).
  ASSERT_EQ(r.exit_code, 4) << r.out << r.err;
  EXPECT_NE(r.out.find("; DUT solutions 0"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("the DUT wrote no solution during the replay (2 lines played"),
            std::string::npos)
      << r.err;
  const std::string seen = slurp(dir / "candump.txt");
  EXPECT_NE(seen.find(" vcan0 111#11\n"), std::string::npos) << seen;
  EXPECT_NE(seen.find(" vcan0 222#2233\n"), std::string::npos) << seen;
  if (!HasFailure()) fs::remove_all(dir);
}

// (c) canplayer replays a candump log of N2K frames into navd --can vcan0, which counts them.
TEST(NavbenchCanReplay, CanplayerFeedsNavdWhichCountsTheN2kFrames) {
  REQUIRE_VCAN_AND_PLAYER();
  constexpr double kLatDeg = 36.3833;
  const auto dir = fresh_dir("can-navd");
  std::vector<CanFrame> frames;
  auto add = [&frames](n2k::Header h, const n2k::Message& m, std::uint8_t seq = 0) {
    for (const auto& f : n2k::encode_frames(h, m, seq)) frames.push_back(to_socket(f));
  };
  n2k::VesselHeading heading;
  heading.heading_rad = 0.25;
  heading.reference = n2k::DirectionReference::kTrue;
  n2k::Attitude att;
  att.yaw_rad = 0.25;
  att.pitch_rad = 0.01;
  att.roll_rad = 0.02;
  n2k::WaterDepth depth;
  depth.depth_m = 25.0;
  n2k::GnssPositionData g;
  g.sid = 7;
  g.date_days = 20000;
  g.time_s = 43200.0;
  g.lat_deg = kLatDeg;
  g.lon_deg = 127.36;
  g.altitude_m = -3.0;
  g.method = 1;
  g.satellites = 8;
  add(n2k::Header{2, 0, 0x23}, heading);
  add(n2k::Header{2, 0, 0x23}, att);
  add(n2k::Header{3, 0, 0x23}, depth);
  add(n2k::Header{3, 0, 10}, g, 2);  // a fast packet: several frames
  add(n2k::Header{2, 0, 0x23}, heading);
  ASSERT_GT(frames.size(), 6u);
  {
    std::ofstream log(dir / "n2k.log");
    log << "# N2K frames for navd (nmea2000 encoders)\n";
    for (std::size_t i = 0; i < frames.size(); ++i) {
      log << log_line(1700000100.0 + 0.01 * static_cast<double>(i), kIface, frames[i]) << "\n";
    }
  }
  TestPty ahrs, output;
  ASSERT_TRUE(ahrs.ok() && output.ok()) << "openpty failed (is /dev/pts mounted?)";
  auto listener = CanSocket::open(kIface);
  ASSERT_TRUE(listener) << listener.error().detail;
  NavdProcess navd("navd-canplayer", "");
  ASSERT_EQ(navd.spawn({"--ahrs", ahrs.path, "--output", output.path, "--can", kIface}), 0);
  const protocols::Bytes start = ahrs.read_until([](const protocols::Bytes& b) {
    return b.size() >= 4;
  }, 5000);
  ASSERT_EQ(start.size(), 4u) << navd.stderr_text();
  SolutionReader reader(output);
  ASSERT_TRUE(ahrs.write(ahrs_packet(62500, kLatDeg)));
  ASSERT_TRUE(reader.await(62500)) << navd.stderr_text();  // navd's CAN socket is bound

  Child player = Child::spawn({"canplayer", "-I", (dir / "n2k.log").string()}, dir, "canplayer");
  ASSERT_EQ(player.wait(20.0), 0) << slurp(player.err);
  const auto heard = receive_frames(*listener, frames.size(), 5.0);
  ASSERT_EQ(heard.size(), frames.size()) << "the bus did not carry every frame";
  for (std::size_t i = 0; i < frames.size(); ++i) EXPECT_EQ(heard[i].frame, frames[i]) << i;

  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_TRUE(ahrs.write(ahrs_packet(62500 + 625, kLatDeg)));
  ASSERT_TRUE(reader.await(62500 + 625)) << navd.stderr_text();
  const auto status = navd.terminate();
  ASSERT_TRUE(status.has_value());
  EXPECT_TRUE(WIFEXITED(*status) && WEXITSTATUS(*status) == 0) << *status;
  const std::string err = navd.stderr_text();
  const std::string expected =
      "can{iface=vcan0 frames=" + std::to_string(frames.size()) +
      " n2k{127250=2,127251=0,127257=1,128259=0,128267=1,129025=0,129026=0,129029=1,other=0}";
  EXPECT_NE(err.find(expected), std::string::npos) << "expected " << expected << "\nin\n" << err;
  if (!HasFailure()) {
    navd.remove_dir();
    fs::remove_all(dir);
  }
}

// (d) bad inputs: a malformed line or a screen print is exit 2 with FILE:LINE; an interface
// that cannot be opened is exit 3. The parsing cases need no vcan0.
TEST(NavbenchCanReplay, BadLogLinesAreExit2AndMissingInterfacesExit3) {
  const auto dir = fresh_dir("can-replay-bad");
  std::ofstream(dir / "bad.log") << "(1700000000.000000) vcan0 123#DEAD\n"
                                 << "\n"
                                 << "(1700000000.100000) vcan0 123#XYZ\n";
  auto r = run_navbench({"replay", "bad.log", "--startup", "0"}, dir);
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("bad.log:3: column "), std::string::npos) << r.err;

  std::ofstream(dir / "print.log") << "  can0  09F8027F   [8]  00 FC FF FF 00 00 FF FF\n";
  r = run_navbench({"replay", "print.log", "--startup", "0"}, dir);
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find("print.log:1: no timestamp"), std::string::npos) << r.err;

  std::ofstream(dir / "good.log") << "(1700000000.000000) nosuchcan0 123#DEAD\n";
  r = run_navbench({"replay", "good.log", "--can", "other=vcan0", "--startup", "0"}, dir);
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;  // no interface 'other' in the log
  EXPECT_NE(r.err.find("no interface 'other'"), std::string::npos) << r.err;
  r = run_navbench({"replay", "good.log", "--startup", "0"}, dir);
  EXPECT_EQ(r.exit_code, 3) << r.out << r.err;
  EXPECT_NE(r.err.find("nosuchcan0"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;

  r = run_navbench({"record", "--can", "nosuchcan0", "--duration", "0.1", "-o", "x.log"}, dir);
  EXPECT_EQ(r.exit_code, 3) << r.out << r.err;
  EXPECT_FALSE(fs::exists(dir / "x.log"));
  EXPECT_FALSE(fs::exists(dir / "x.log.partial"));
  r = run_navbench({"record", "a=/dev/null@9600", "--can", "vcan0", "-o", "x.log"}, dir);
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  if (!HasFailure()) fs::remove_all(dir);
}

}  // namespace
}  // namespace nav::testing

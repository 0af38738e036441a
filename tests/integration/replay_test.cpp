// SPDX-License-Identifier: MIT
// `navbench record` and `navbench replay` end to end, over ptys created here.
//
//   record:  test Pty master --(known bytes at known times)--> slave <-- navbench record
//   replay:  hand-written capture --> navbench replay --> ptys --> navd --> output pty
//            --> replay-rx.log (decoded here: one $PNVBSOL per GX3 packet)
//
// Timing bounds are generous (hundreds of ms): the tests check that timing is kept, not how
// well. Every child is waited for with a bound and killed if it overstays.
#include <poll.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "nav/bench/decode.hpp"
#include "nav/protocols/microstrain_gx3.hpp"
#include "nav/protocols/navd_solution.hpp"
#include "nav/protocols/nmea0183.hpp"
#include "nav/transport/pty.hpp"
#include "navbench_cli.hpp"
#include "source_paths.hpp"

namespace nav::testing {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

/// A navbench child whose stdout can be watched while it runs.
struct Child {
  pid_t pid = -1;
  fs::path out, err;
  int exit_code = -1;

  static Child spawn(const std::vector<std::string>& args, const fs::path& cwd) {
    Child c;
    const std::string exe = nav::test_paths::binary_dir() + "/navbench";
    c.out = cwd / "child-stdout.txt";
    c.err = cwd / "child-stderr.txt";
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, c.out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&fa, 2, c.err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addchdir_np(&fa, cwd.c_str());
    std::vector<char*> argv{const_cast<char*>(exe.c_str())};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    if (::posix_spawn(&c.pid, exe.c_str(), &fa, nullptr, argv.data(), environ) != 0) c.pid = -1;
    posix_spawn_file_actions_destroy(&fa);
    return c;
  }
  /// Waits until stdout holds `text` (bounded); false on timeout or exit.
  bool wait_for_output(const std::string& text, double timeout_s) const {
    const auto end = Clock::now() + std::chrono::duration<double>(timeout_s);
    while (Clock::now() < end) {
      if (slurp(out).find(text) != std::string::npos) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  }
  /// Non-blocking: true once the child has exited (exit_code set).
  bool poll_exit() {
    if (pid < 0) return true;
    int status = 0;
    if (::waitpid(pid, &status, WNOHANG) != pid) return false;
    exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    pid = -1;
    return true;
  }
  /// Waits for the exit (bounded; SIGKILL after the bound); returns the exit code.
  int wait(double timeout_s) {
    const auto end = Clock::now() + std::chrono::duration<double>(timeout_s);
    while (!poll_exit()) {
      if (Clock::now() > end) {
        ::kill(pid, SIGKILL);
        int status = 0;
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

struct Parsed {
  double t = 0;
  std::string port;
  std::string hex;
};

std::vector<Parsed> capture_lines(const std::string& text) {
  std::vector<Parsed> out;
  const std::regex line(R"(\((-?\d+\.\d{9})\) (\S+) ([0-9A-F]*)\n)");
  for (std::sregex_iterator it(text.begin(), text.end(), line), end; it != end; ++it) {
    out.push_back({std::stod((*it)[1]), (*it)[2], (*it)[3]});
  }
  return out;
}

std::string to_hex(const std::string& bytes) {
  std::string h;
  char b[3];
  for (unsigned char c : bytes) {
    std::snprintf(b, sizeof b, "%02X", c);
    h += b;
  }
  return h;
}

void write_line(std::FILE* f, double t, const std::string& port, protocols::ByteSpan bytes) {
  std::fprintf(f, "(%.9f) %s ", t, port.c_str());
  for (auto b : bytes) std::fprintf(f, "%02X", b);
  std::fputc('\n', f);
}

TEST(NavbenchRecord, CapturesBytesWrittenToAPtyInOrderWithTimes) {
  const auto dir = fresh_dir("record");
  auto pty = transport::Pty::open();
  ASSERT_TRUE(pty) << pty.error().detail;
  Child c = Child::spawn({"record", "gps=" + pty->slave_path() + "@9600", "--duration", "1.5",
                          "-o", "cap.log"}, dir);
  ASSERT_GT(c.pid, 0);
  ASSERT_TRUE(c.wait_for_output("recording to cap.log", 5.0)) << slurp(c.err);
  // The recorder's t=0 is just before it printed; our own times are relative to now.
  const auto t_ready = Clock::now();
  const std::vector<std::string> chunks = {"$GPGGA,first*00\r\n", std::string("\x00\xFF\x7F", 3),
                                           "third chunk", "$GPRMC,last*11\r\n"};
  std::vector<double> sent_at;
  for (std::size_t i = 0; i < chunks.size(); ++i) {
    std::this_thread::sleep_until(t_ready + std::chrono::milliseconds(100 + 250 * i));
    sent_at.push_back(std::chrono::duration<double>(Clock::now() - t_ready).count());
    ASSERT_EQ(::write(pty->master(), chunks[i].data(), chunks[i].size()),
              static_cast<ssize_t>(chunks[i].size()));
  }
  ASSERT_EQ(c.wait(10.0), 0) << slurp(c.err);
  EXPECT_TRUE(fs::exists(dir / "cap.log"));
  EXPECT_FALSE(fs::exists(dir / "cap.log.partial"));
  const std::string out = slurp(c.out);
  EXPECT_NE(out.find("navbench record: gps " +
                     std::to_string(chunks[0].size() + 3 + chunks[2].size() + chunks[3].size()) +
                     " bytes"), std::string::npos) << out;

  const std::string text = slurp(dir / "cap.log");
  const auto lines = capture_lines(text);
  ASSERT_FALSE(lines.empty()) << text;
  std::string all;
  for (const auto& c2 : chunks) all += c2;
  std::string got;
  for (const auto& l : lines) {
    EXPECT_EQ(l.port, "gps");
    got += l.hex;
  }
  EXPECT_EQ(got, to_hex(all));  // exactly those bytes, in order
  // Plausible times: non-decreasing, inside the duration, and spaced like the writes.
  for (std::size_t i = 1; i < lines.size(); ++i) EXPECT_GE(lines[i].t, lines[i - 1].t);
  EXPECT_GE(lines.front().t, 0.0);
  EXPECT_LE(lines.back().t, 1.6);
  // The first line holds the first chunk, the last line the last chunk.
  EXPECT_EQ(lines.front().hex.substr(0, 4), to_hex("$G"));
  const double recorded_span = lines.back().t - lines.front().t;
  const double sent_span = sent_at.back() - sent_at.front();
  EXPECT_NEAR(recorded_span, sent_span, 0.2) << text;
  EXPECT_NEAR(lines.front().t, sent_at.front(), 0.3) << text;
}

TEST(NavbenchRecord, StopsCleanlyOnSigterm) {
  const auto dir = fresh_dir("record-term");
  auto pty = transport::Pty::open();
  ASSERT_TRUE(pty) << pty.error().detail;
  Child c = Child::spawn({"record", "a=" + pty->slave_path() + "@115200", "-o", "cap.log"}, dir);
  ASSERT_GT(c.pid, 0);
  ASSERT_TRUE(c.wait_for_output("until SIGINT/SIGTERM", 5.0)) << slurp(c.err);
  ASSERT_EQ(::write(pty->master(), "hello", 5), 5);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  ::kill(c.pid, SIGTERM);
  ASSERT_EQ(c.wait(5.0), 0) << slurp(c.err);
  EXPECT_FALSE(fs::exists(dir / "cap.log.partial"));
  const auto lines = capture_lines(slurp(dir / "cap.log"));
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0].hex, to_hex("hello"));
}

TEST(NavbenchRecord, BadArgumentsAndMissingPorts) {
  const auto dir = fresh_dir("record-bad");
  EXPECT_EQ(run_navbench({"record", "gps=/dev/null", "-o", "x.log"}, dir).exit_code, 2);
  EXPECT_EQ(run_navbench({"record", "gps=/dev/null@1234", "-o", "x.log"}, dir).exit_code, 2);
  EXPECT_EQ(run_navbench({"record", "gps/dev/null@9600", "-o", "x.log"}, dir).exit_code, 2);
  const auto r = run_navbench({"record", "gps=/dev/nonexistent-tty@9600", "--duration", "0.1",
                               "-o", "x.log"}, dir);
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_NE(r.err.find("/dev/nonexistent-tty"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "x.log"));
}

/// GX3 packets at 100 Hz for 1 s on "ahrs", GGA+RMC at 1 Hz on "gps".
fs::path write_nav_capture(const fs::path& dir, int* packets) {
  const auto path = dir / "nav.log";
  std::FILE* f = std::fopen(path.c_str(), "w");
  *packets = 0;
  for (int k = 0; k < 100; ++k) {
    const double t = 0.010 * k;
    if (k % 100 == 10) {
      protocols::nmea::Gga g;
      g.time.hour = 12;
      g.time.second = 0.0;
      g.lat_deg = 36.383333333;
      g.lon_deg = 127.36;
      g.quality = 1;
      g.satellites = 9;
      g.hdop = 0.9;
      g.alt_msl_m = 0.0;
      g.geoid_sep_m = 0.0;
      protocols::nmea::Rmc r;
      r.time.year = 2026;
      r.time.month = 11;
      r.time.day = 22;
      r.time.hour = 12;
      r.valid = true;
      r.lat_deg = g.lat_deg;
      r.lon_deg = g.lon_deg;
      r.sog_kn = 0.0;
      r.cog_deg = 0.0;
      const std::string s = protocols::nmea::frame(protocols::nmea::to_sentence(g)) +
                            protocols::nmea::frame(protocols::nmea::to_sentence(r));
      write_line(f, t - 0.002, "gps",
                 protocols::ByteSpan(reinterpret_cast<const std::uint8_t*>(s.data()), s.size()));
    }
    protocols::gx3::AccelRateMag m;
    m.accel_g = {0.0f, 0.0f, -1.0f};
    m.mag_gauss = {0.2f, 0.0f, 0.4f};
    m.timer_ticks = static_cast<std::uint32_t>(62500 + 625 * k);
    write_line(f, t, "ahrs", protocols::gx3::encode(m));
    ++*packets;
  }
  std::fclose(f);
  return path;
}

TEST(NavbenchReplay, PlaysACaptureToNavdWhichAnswersEveryPacket) {
  const auto dir = fresh_dir("replay-navd");
  int packets = 0;
  const auto cap = write_nav_capture(dir, &packets);
  const auto r = run_navbench({"replay", cap.string(), "--startup", "0.5", "--dut", "--", "navd",
                               "--ahrs", "{port:ahrs}", "--gps", "{port:gps}", "--output",
                               "{port:output}"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err << slurp(dir / "replay-dut.log");
  EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(^ahrs: /dev/pts/\d+$)", std::regex::multiline)))
      << r.out;
  EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(^gps: /dev/pts/\d+$)", std::regex::multiline)))
      << r.out;
  // One summary line with the counts and the lateness figures.
  EXPECT_TRUE(std::regex_search(
      r.out, std::regex(R"(navbench replay: 2 ports, \d+ bytes, 101 lines in [\d.]+ s; lateness )"
                        R"(p50 [\d.]+ ms p99 [\d.]+ ms max [\d.]+ ms; DUT solutions (\d+))")))
      << r.out;
  EXPECT_GE(r.wall_s, 1.3);  // 0.5 s startup + ~1 s of capture

  // The DUT's output, decoded: about one $PNVBSOL per GX3 packet, naming their timers.
  const std::string rx = slurp(dir / "replay-rx.log");
  auto bytes = bench::bytes_from_capture(rx, "output", "replay-rx.log");
  ASSERT_TRUE(bytes) << bytes.error().detail;
  std::size_t solutions = 0, used = 0;
  std::vector<std::uint64_t> tags;
  while (used < bytes->size()) {
    const auto res = protocols::nmea::parse_with_limit(
        protocols::ByteSpan(bytes->data() + used, bytes->size() - used),
        protocols::navd::kMaxSentence);
    if (res.status == protocols::ParseStatus::kNeedMore) break;
    used += res.consumed;
    if (res.status != protocols::ParseStatus::kComplete) continue;
    if (res.message->talker + res.message->type != protocols::navd::kAddress) continue;
    auto sol = protocols::navd::decode(*res.message);
    ASSERT_TRUE(sol) << sol.error().detail;
    tags.push_back(sol->trigger_tag);
    ++solutions;
  }
  EXPECT_GE(solutions, static_cast<std::size_t>(packets - 5)) << rx.substr(0, 2000);
  EXPECT_LE(solutions, static_cast<std::size_t>(packets));
  ASSERT_FALSE(tags.empty());
  EXPECT_TRUE(std::is_sorted(tags.begin(), tags.end()));
  EXPECT_GE(tags.front(), 62500u);
  EXPECT_LE(tags.back(), 62500u + 625u * 99u);
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.out, m, std::regex(R"(DUT solutions (\d+))")));
  EXPECT_EQ(std::stoul(m[1]), solutions) << r.out;
}

// A DUT that stays alive and silent (it hung, or it does not listen) used to pass (exit 0);
// one that exits at once is exit 4 as well.
TEST(NavbenchReplay, ADutThatWritesNoSolutionOrEndsEarlyIsExit4) {
  const auto dir = fresh_dir("replay-silent");
  int packets = 0;
  const auto cap = write_nav_capture(dir, &packets);
  const auto silent = run_navbench(
      {"replay", cap.string(), "--startup", "0.2", "--dut", "--", "/bin/sleep", "1000"}, dir);
  EXPECT_EQ(silent.exit_code, 4) << silent.out << silent.err;
  EXPECT_NE(silent.err.find("navbench: the DUT wrote no solution during the replay (101 lines "
                            "played; log: replay-dut.log)"),
            std::string::npos)
      << silent.err;
  EXPECT_LT(silent.wall_s, 30.0);
  const auto ended = run_navbench(
      {"replay", cap.string(), "--startup", "0.2", "--dut", "--", "/bin/true"}, dir);
  EXPECT_EQ(ended.exit_code, 4) << ended.out << ended.err;
  EXPECT_NE(ended.err.find("before the end of the replay"), std::string::npos) << ended.err;
}

TEST(NavbenchReplay, MappedPortGetsTheBytesWithScaledTiming) {
  const auto dir = fresh_dir("replay-mapped");
  auto pty = transport::Pty::open();
  ASSERT_TRUE(pty) << pty.error().detail;
  {
    std::FILE* f = std::fopen((dir / "cap.log").c_str(), "w");
    std::fputs("(0.000000000) gps 414243\n(0.400000000) gps 44\n(0.800000000) gps 4546\n", f);
    std::fclose(f);
  }
  Child c = Child::spawn({"replay", "cap.log", "--port", "gps=" + pty->slave_path() + "@9600",
                          "--speed", "2", "--startup", "0.1"}, dir);
  ASSERT_GT(c.pid, 0);
  std::string got;
  std::vector<double> at;
  const auto t0 = Clock::now();
  while (!c.poll_exit() && Clock::now() - t0 < std::chrono::seconds(10)) {
    pollfd p{pty->master(), POLLIN, 0};
    if (::poll(&p, 1, 10) <= 0) continue;
    char buf[64];
    const ssize_t n = ::read(pty->master(), buf, sizeof buf);
    if (n <= 0) continue;
    got.append(buf, static_cast<std::size_t>(n));
    at.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
  }
  char buf[64];
  for (ssize_t n; (n = ::read(pty->master(), buf, sizeof buf)) > 0;) {
    got.append(buf, static_cast<std::size_t>(n));
    at.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
  }
  ASSERT_EQ(c.wait(5.0), 0) << slurp(c.err);
  EXPECT_EQ(got, "ABCDEF");
  ASSERT_GE(at.size(), 2u);
  EXPECT_NEAR(at.back() - at.front(), 0.4, 0.2);  // 0.8 s of capture at --speed 2
  const std::string out = slurp(c.out);
  EXPECT_EQ(out.find("gps: /dev/pts"), std::string::npos) << out;  // mapped: no pty printed
  EXPECT_NE(out.find("navbench replay: 1 ports, 6 bytes, 3 lines"), std::string::npos) << out;
  EXPECT_NE(out.find("no DUT"), std::string::npos) << out;
}

TEST(NavbenchReplay, MalformedCaptureAndBadPortsAreUsageErrors) {
  const auto dir = fresh_dir("replay-bad");
  {
    std::FILE* f = std::fopen((dir / "bad.log").c_str(), "w");
    std::fputs("(0.000000000) gps 4142\n(0.010000000) gps 43\n0.02 gps 44\n", f);
    std::fclose(f);
    f = std::fopen((dir / "odd.log").c_str(), "w");
    std::fputs("(0.000000000) gps 4142\n\n(0.010000000) gps 434\n", f);
    std::fclose(f);
    f = std::fopen((dir / "good.log").c_str(), "w");
    std::fputs("(0.000000000) gps 4142\n", f);
    std::fclose(f);
  }
  auto r = run_navbench({"replay", "bad.log", "--startup", "0"}, dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("navbench: bad.log:3: expected '(<sec>.<nsec>) <port> <hex>'"),
            std::string::npos) << r.err;
  r = run_navbench({"replay", "odd.log", "--startup", "0"}, dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("odd.log:3: expected"), std::string::npos) << r.err;
  r = run_navbench({"replay", "good.log", "--port", "ahrs=/dev/null", "--startup", "0"}, dir);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("no port 'ahrs'"), std::string::npos) << r.err;
  r = run_navbench({"replay", "good.log", "--port", "gps=/dev/nonexistent-tty", "--startup", "0"},
                   dir);
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("/dev/nonexistent-tty"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace nav::testing

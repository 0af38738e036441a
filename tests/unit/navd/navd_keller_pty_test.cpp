// SPDX-License-Identifier: MIT
// navd polling a Keller depth sensor over ptys, in hand-driven lockstep. The test plays the
// AHRS, the GPS and the Keller device (answers built with keller::encode, requests read
// with keller::parse_request):
//
//   test                                  navd (child process)
//   keller master  ◀── F48 (start) ──────  --input depth=keller:<slave>
//                  ── F48 answer ───────▶
//   gps master     ── GGA (anchor) ─────▶  --gps
//   ahrs master    ── 0xCB k ───────────▶  --ahrs    (timer starts just before its wrap)
//   output master  ◀── $PNVBSOL k ───────  --output
//   keller master  ◀── F73 P1, if due at k (read right after solution k: it must already
//                       be there, i.e. written BEFORE the solution)
//                  ── P1 answer ────────▶  (readable before trigger k+1 is written)
//
// Checks: requests only at the AHRS samples where a poll period has elapsed, each readable
// when its trigger's solution arrives; exception 32 answered by F48 at the next trigger; the
// solution's depth follows the answered pressure; the exit summary counts it all.
#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "nav/common/geodesy.hpp"
#include "nav/common/units.hpp"
#include "nav/protocols/keller_bus.hpp"
#include "nav/protocols/microstrain_gx3.hpp"
#include "nav/protocols/navd_solution.hpp"
#include "nav/protocols/nmea0183.hpp"

extern char** environ;

namespace nav {
namespace {

namespace keller = protocols::keller;
namespace gx3 = protocols::gx3;
namespace nmea = protocols::nmea;
using protocols::Bytes;
using protocols::ByteSpan;

constexpr double kLatDeg = 36.3833;
constexpr double kLonDeg = 127.36;
constexpr double kAtmospherePa = 101325.0;
constexpr double kDensity = 1025.0;
constexpr std::uint32_t kStep = 625;  // 100 Hz AHRS [ticks]
constexpr int kPollEvery = 10;        // depth_poll_period_s 0.1 s at 100 Hz [samples]

/// A pty pair; the test keeps the slave open too (raw), so nothing hangs up early.
struct TestPty {
  int master = -1;
  int slave = -1;
  std::string path;

  TestPty() {
    char name[256] = {};
    termios tio{};
    ::cfmakeraw(&tio);
    tio.c_cflag |= CLOCAL | CREAD;
    if (::openpty(&master, &slave, name, &tio, nullptr) != 0) return;
    path = name;
    ::fcntl(master, F_SETFL, ::fcntl(master, F_GETFL) | O_NONBLOCK);
    ::fcntl(master, F_SETFD, FD_CLOEXEC);
    ::fcntl(slave, F_SETFD, FD_CLOEXEC);
  }
  ~TestPty() {
    if (master >= 0) ::close(master);
    if (slave >= 0) ::close(slave);
  }
  TestPty(const TestPty&) = delete;
  TestPty& operator=(const TestPty&) = delete;

  bool ok() const { return master >= 0; }

  bool write(const Bytes& b) const {
    return ::write(master, b.data(), b.size()) == static_cast<ssize_t>(b.size());
  }
  bool write(const std::string& s) const {
    return write(Bytes(s.begin(), s.end()));
  }
  /// Makes what was written readable by the slave's reader before anything written later
  /// (n_tty_poll flushes the pending master writes), as the bench does in lockstep.
  void flush_to_slave() const {
    pollfd p{slave, POLLIN, 0};
    (void)::poll(&p, 1, 0);
  }
  /// What the slave side (navd) wrote so far, without waiting.
  Bytes read_now() const {
    Bytes out;
    std::uint8_t buf[512];
    for (ssize_t n; (n = ::read(master, buf, sizeof buf)) > 0;) out.insert(out.end(), buf, buf + n);
    return out;
  }
  /// Reads until `done(bytes)` or the timeout [ms].
  template <typename Done>
  Bytes read_until(Done done, int timeout_ms) const {
    Bytes out;
    const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    while (!done(out) && std::chrono::steady_clock::now() < end) {
      pollfd p{master, POLLIN, 0};
      (void)::poll(&p, 1, 20);
      const Bytes got = read_now();
      out.insert(out.end(), got.begin(), got.end());
    }
    return out;
  }
};

Bytes ahrs_packet(std::uint32_t ticks) {
  // Level, heading North, at rest: specific force −g (local normal gravity) on z.
  const double g = geodesy::normal_gravity(units::deg_to_rad(kLatDeg), 0.0);
  gx3::AccelRateMag m;
  m.accel_g = {0.0f, 0.0f, static_cast<float>(-g / units::kStandardGravity)};
  m.mag_gauss = {0.2f, 0.0f, 0.4f};
  m.timer_ticks = ticks;
  return gx3::encode(m);
}

std::string gga_anchor() {
  nmea::Gga g;
  g.time.hour = 12;
  g.lat_deg = kLatDeg;
  g.lon_deg = kLonDeg;
  g.quality = 1;
  g.satellites = 8;
  g.hdop = 0.9;
  g.alt_msl_m = 0.0;
  g.geoid_sep_m = 0.0;
  return nmea::frame(nmea::to_sentence(g));
}

Bytes p1_answer(double depth_m) {
  const double p1_bar = (kAtmospherePa + kDensity * units::kStandardGravity * depth_m) / 1e5;
  return keller::encode(
      keller::Response{1, keller::ChannelValue{static_cast<float>(p1_bar), 0}});
}

/// The solutions in `bytes` (other bytes skipped).
std::vector<protocols::navd::Solution> solutions_in(const Bytes& bytes) {
  std::vector<protocols::navd::Solution> out;
  std::size_t used = 0;
  while (used < bytes.size()) {
    const auto r = nmea::parse_with_limit(ByteSpan(bytes).subspan(used),
                                          protocols::navd::kMaxSentence);
    if (r.status == protocols::ParseStatus::kNeedMore) break;
    used += std::max<std::size_t>(r.consumed, 1);
    if (r.status != protocols::ParseStatus::kComplete) continue;
    if (r.message->talker + r.message->type != protocols::navd::kAddress) continue;
    if (auto s = protocols::navd::decode(*r.message)) out.push_back(*s);
  }
  return out;
}

/// Every request in `bytes`.
std::vector<keller::Request> requests_in(const Bytes& bytes) {
  std::vector<keller::Request> out;
  std::size_t used = 0;
  while (used < bytes.size()) {
    const auto r = keller::parse_request(ByteSpan(bytes).subspan(used));
    if (r.status == protocols::ParseStatus::kNeedMore) break;
    used += std::max<std::size_t>(r.consumed, 1);
    if (r.status == protocols::ParseStatus::kComplete) out.push_back(*r.message);
  }
  return out;
}

std::string slurp(const std::filesystem::path& p) {
  std::ifstream f(p);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

TEST(NavdKellerPty, PollsBeforeEachSolutionAndFusesTheAnsweredDepth) {
  TestPty ahrs, gps, bus, output;
  ASSERT_TRUE(ahrs.ok() && gps.ok() && bus.ok() && output.ok()) << "openpty failed";
  const auto dir = std::filesystem::path(::testing::TempDir()) /
                   ("navd-keller-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto config = dir / "navd.yaml";
  std::ofstream(config) << "depth_poll_period_s: 0.1\ndepth_std_m: 0.05\n";
  const auto err_path = dir / "stderr.txt";

  const std::string exe = std::string(NAV_BINARY_DIR) + "/navd";
  const std::vector<std::string> args = {exe,
                                         "--ahrs", ahrs.path,
                                         "--gps", gps.path,
                                         "--input", "depth=keller:" + bus.path + "@9600",
                                         "--output", output.path,
                                         "--config", config.string()};
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  pid_t pid = -1;
  ASSERT_EQ(::posix_spawn(&pid, exe.c_str(), &fa, nullptr, argv.data(), environ), 0) << exe;
  posix_spawn_file_actions_destroy(&fa);
  struct Reaper {
    pid_t pid;
    ~Reaper() {
      if (pid > 0 && ::waitpid(pid, nullptr, WNOHANG) == 0) {
        ::kill(pid, SIGKILL);
        ::waitpid(pid, nullptr, 0);
      }
    }
  } reaper{pid};

  // Start-up: navd initialises the sensor (F48 to 250) on its own; answer it.
  const Bytes init = bus.read_until([](const Bytes& b) { return b.size() >= 4; }, 5000);
  ASSERT_EQ(init, (Bytes{0xFA, 0x30, 0x04, 0x43})) << slurp(err_path);
  ASSERT_TRUE(bus.write(keller::encode(keller::Response{1, keller::InitInfo{5, 20, 10, 5, 0, 1}})));
  bus.flush_to_slave();
  ASSERT_TRUE(gps.write(gga_anchor()));
  gps.flush_to_slave();

  // Lockstep by hand. Depth 6 m, then 9 m; one poll answered with exception 32.
  const int kSamples = 420;
  const std::uint32_t t0 = 0xFFFFFFFFu - 100 * kStep;  // the timer wraps after ~1 s
  std::vector<protocols::navd::Solution> sols;
  std::vector<int> request_at;          // sample index of every F73 request
  std::vector<int> init_at;             // sample index of every F48 request after start-up
  int polls = 0;
  Bytes pending_output;
  for (int k = 0; k < kSamples; ++k) {
    const std::uint32_t tag = t0 + static_cast<std::uint32_t>(k) * kStep;
    ASSERT_TRUE(ahrs.write(ahrs_packet(tag)));
    bool got = false;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(3);
    while (!got && std::chrono::steady_clock::now() < deadline) {
      const Bytes b = output.read_until([](const Bytes& x) { return !x.empty(); }, 100);
      pending_output.insert(pending_output.end(), b.begin(), b.end());
      const auto last_lf = std::find(pending_output.rbegin(), pending_output.rend(), '\n');
      if (last_lf == pending_output.rend()) continue;
      const Bytes complete(pending_output.begin(), last_lf.base());
      pending_output.erase(pending_output.begin(), last_lf.base());
      for (const auto& s : solutions_in(complete)) {
        sols.push_back(s);
        got = got || s.trigger_tag == tag;
      }
    }
    ASSERT_TRUE(got) << "no solution for sample " << k << "\n" << slurp(err_path);
    // The request due at this sample was written before its solution: readable now.
    for (const auto& q : requests_in(bus.read_now())) {
      EXPECT_EQ(q.address, keller::kTransparentAddress);
      if (q.function == keller::Function::kInit) {
        init_at.push_back(k);
        ASSERT_TRUE(bus.write(
            keller::encode(keller::Response{1, keller::InitInfo{5, 20, 10, 5, 0, 1}})));
        continue;
      }
      ASSERT_EQ(q.function, keller::Function::kReadChannel);
      EXPECT_EQ(q.data, static_cast<std::uint8_t>(keller::Channel::kP1));
      request_at.push_back(k);
      ++polls;
      if (polls == 5) {
        const keller::Exception not_initialised{
            static_cast<std::uint8_t>(keller::Function::kReadChannel),
            static_cast<std::uint8_t>(keller::ExceptionCode::kNotInitialised)};
        ASSERT_TRUE(bus.write(keller::encode(keller::Response{1, not_initialised})));
      } else {
        ASSERT_TRUE(bus.write(p1_answer(k < 200 ? 6.0 : 9.0)));
      }
    }
    bus.flush_to_slave();  // the answer is readable before the next trigger
  }

  // Polls every 10th sample from the first one (the schedule's origin), across the wrap.
  ASSERT_EQ(request_at.size(), static_cast<std::size_t>((kSamples - 1) / kPollEvery));
  for (std::size_t i = 0; i < request_at.size(); ++i) {
    EXPECT_EQ(request_at[i], static_cast<int>(i + 1) * kPollEvery);
  }
  // Exception 32 on the 5th poll (sample 50): F48 at the very next sample.
  ASSERT_EQ(init_at.size(), 1u);
  EXPECT_EQ(init_at[0], 5 * kPollEvery + 1);

  // Depth: anchored at 0 m (GGA altitude 0); the first answered poll (sample 10) is fused at
  // sample 11, then the estimate follows the answers: 6 m, and 9 m from sample 200 on.
  ASSERT_EQ(sols.size(), static_cast<std::size_t>(kSamples));
  ASSERT_TRUE(sols[1].position_valid);
  EXPECT_NEAR(sols[10].depth_m, 0.0, 0.01);
  EXPECT_NEAR(sols[11].depth_m, 6.0, 0.01);
  EXPECT_NEAR(sols[195].depth_m, 6.0, 0.01);
  EXPECT_GT(sols[211].depth_m, 6.5);  // the first 9 m answer pulls it down at once
  EXPECT_NEAR(sols.back().depth_m, 9.0, 0.05);

  // Exit summary after SIGTERM.
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  reaper.pid = -1;
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  const std::string err = slurp(err_path);
  const std::string polls_text =
      "poll{requests=" + std::to_string(request_at.size() + 2) +
      " inits=2 answers=" + std::to_string(request_at.size() + 1) +
      " exceptions=1 timeouts=0 unexpected=0 write_errors=0}";
  EXPECT_NE(err.find("input depth=keller messages="), std::string::npos) << err;
  EXPECT_NE(err.find(polls_text), std::string::npos) << polls_text << "\n" << err;
  EXPECT_NE(err.find("depth_fused=" + std::to_string(request_at.size() - 1)), std::string::npos)
      << err;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace nav

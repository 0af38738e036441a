// SPDX-License-Identifier: MIT
// navd sharing its position over an acoustic modem line (--modem), over ptys, in hand-driven
// lockstep. The test plays the AHRS, the GPS and the modem's serial side (the other vehicles):
//
//   test                                  navd (child process, --vehicle-id 3)
//   ahrs master    ── 0xCB k ───────────▶  --ahrs    (timer starts just before its wrap)
//   gps master     ── GGA (anchor) ─────▶  --gps     (only before sample kAnchorAt)
//   output master  ◀── $PNVBSOL k ───────  --output
//   modem master   ◀── $PNVBPOS, if due at k (read right after solution k: it must already
//                       be there, i.e. written BEFORE the solution)
//                  ── $PNVBPOS of vehicle 9, of vehicle 3 (own id), garbage ──▶
//
// Checks: no report before the GPS anchor; the first at the anchored sample, then one every
// modem_period_s of AHRS time (across the timer wrap), each readable when its trigger's
// solution arrives and carrying that trigger's time and position; the exit summary counts
// the reports sent and the peer heard (own id ignored, garbage rejected).
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
#include "nav/protocols/microstrain_gx3.hpp"
#include "nav/protocols/navd_modem.hpp"
#include "nav/protocols/navd_solution.hpp"
#include "nav/protocols/nmea0183.hpp"

extern char** environ;

namespace nav {
namespace {

namespace gx3 = protocols::gx3;
namespace nmea = protocols::nmea;
namespace modem = protocols::navd_modem;
using protocols::Bytes;
using protocols::ByteSpan;

constexpr double kLatDeg = 36.3833;
constexpr double kLonDeg = 127.36;
constexpr std::uint32_t kStep = 625;  // 100 Hz AHRS [ticks]
constexpr int kReportEvery = 50;     // modem_period_s 0.5 s at 100 Hz [samples]

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

std::string slurp(const std::filesystem::path& p) {
  std::ifstream f(p);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

/// Every $PNVBPOS in `bytes` (anything else is a test failure).
std::vector<modem::Position> reports_in(const Bytes& bytes) {
  std::vector<modem::Position> out;
  std::size_t used = 0;
  while (used < bytes.size()) {
    const auto r = modem::parse(ByteSpan(bytes).subspan(used));
    EXPECT_NE(r.status, protocols::ParseStatus::kNeedMore) << "a partial report";
    if (r.status == protocols::ParseStatus::kNeedMore) break;
    EXPECT_EQ(r.status, protocols::ParseStatus::kComplete) << r.error;
    used += std::max<std::size_t>(r.consumed, 1);
    if (r.status == protocols::ParseStatus::kComplete) out.push_back(*r.message);
  }
  return out;
}

TEST(NavdModemPty, ReportsBeforeTheSolutionOnceAnchoredAndCountsPeers) {
  TestPty ahrs, gps, modem_line, output;
  ASSERT_TRUE(ahrs.ok() && gps.ok() && modem_line.ok() && output.ok()) << "openpty failed";
  const auto dir = std::filesystem::path(::testing::TempDir()) /
                   ("navd-modem-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto config = dir / "navd.yaml";
  std::ofstream(config) << "modem_period_s: 0.5\n";
  const auto err_path = dir / "stderr.txt";

  const std::string exe = std::string(NAV_BINARY_DIR) + "/navd";
  const std::vector<std::string> args = {exe,
                                         "--ahrs", ahrs.path,
                                         "--gps", gps.path,
                                         "--modem", modem_line.path + "@9600",
                                         "--vehicle-id", "3",
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

  // The GX3 start command shows that navd has opened its ports.
  const Bytes start = ahrs.read_until([](const Bytes& b) { return b.size() >= 4; }, 5000);
  ASSERT_EQ(start.size(), 4u) << slurp(err_path);

  // What the other vehicles say, written at sample kPeersAt: a report of vehicle 9, one with
  // navd's own id 3 (ignored), and one with a broken checksum (rejected).
  modem::Position peer;
  peer.vehicle_id = 9;
  peer.t_s = 41.5;
  peer.lat_deg = 36.39;
  peer.lon_deg = 127.37;
  peer.depth_m = 25.0;
  peer.horizontal_std_m = 3.0;
  modem::Position echo = peer;
  echo.vehicle_id = 3;
  std::string corrupt = modem::encode(peer);
  corrupt[corrupt.find('*') + 1] = corrupt[corrupt.find('*') + 1] == '0' ? '1' : '0';
  const std::string from_peers = modem::encode(peer) + modem::encode(echo) + corrupt;

  constexpr int kSamples = 300;
  constexpr int kAnchorAt = 20;
  constexpr int kPeersAt = 100;
  const std::uint32_t t0 = 0xFFFFFFFFu - 150 * kStep;  // the timer wraps after 1.5 s
  std::vector<protocols::navd::Solution> sols;
  std::vector<int> report_at;
  std::vector<modem::Position> reports;
  Bytes pending_output;
  for (int k = 0; k < kSamples; ++k) {
    if (k == kAnchorAt) {  // readable before trigger k: sample k is the first anchored one
      ASSERT_TRUE(gps.write(gga_anchor()));
      gps.flush_to_slave();
    }
    if (k == kPeersAt) {
      ASSERT_TRUE(modem_line.write(from_peers));
      modem_line.flush_to_slave();
    }
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
    // The report due at this sample was written before its solution: readable now, whole.
    for (const auto& r : reports_in(modem_line.read_now())) {
      report_at.push_back(k);
      reports.push_back(r);
      EXPECT_EQ(r.vehicle_id, 3);
      EXPECT_NEAR(r.t_s, tag / gx3::kTicksPerSecond, 0.5e-3) << k;
      ASSERT_EQ(sols.back().trigger_tag, tag);
      ASSERT_TRUE(sols.back().position_valid) << k;
      EXPECT_NEAR(r.lat_deg, sols.back().lat_deg, 0.6e-6) << k;
      EXPECT_NEAR(r.lon_deg, sols.back().lon_deg, 0.6e-6) << k;
      EXPECT_NEAR(r.depth_m, sols.back().depth_m, 0.5e-2 + 1e-3) << k;
      EXPECT_GT(r.horizontal_std_m, 0.0);
      EXPECT_LT(r.horizontal_std_m, 10.0);
    }
  }

  // First report at the anchored sample, then every kReportEvery samples, across the wrap.
  std::vector<int> expected;
  for (int k = kAnchorAt; k < kSamples; k += kReportEvery) expected.push_back(k);
  EXPECT_EQ(report_at, expected);
  ASSERT_FALSE(reports.empty());
  EXPECT_NEAR(reports.front().lat_deg, kLatDeg, 1e-6);
  EXPECT_NEAR(reports.front().lon_deg, kLonDeg, 1e-6);
  EXPECT_FALSE(sols[kAnchorAt - 1].position_valid);
  EXPECT_LT(reports.back().t_s, reports.front().t_s);  // the timer wrapped in between

  // Exit summary after SIGTERM.
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  reaper.pid = -1;
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  const std::string err = slurp(err_path);
  const std::string modem_text = "modem{sent=" + std::to_string(expected.size()) +
                                 " received=1 rejected=1 peers=[9:1] dropped=0 skipped=0 own=1"
                                 " other=0 rejects{checksum=1 ";
  EXPECT_NE(err.find(modem_text), std::string::npos) << modem_text << "\n" << err;
  EXPECT_NE(err.find("navd: modem peer 9 t=41.500 s lat=36.390000 lon=127.370000 depth=25.00 m"),
            std::string::npos)
      << err;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace nav

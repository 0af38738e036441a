// SPDX-License-Identifier: MIT
// What the navd pty tests (navd_keller_pty_test, navd_modem_pty_test) share: ptys the test
// drives as navd's devices, the AHRS packets and the GGA anchor it writes, the solutions it
// reads back in lockstep on --output, and navd itself as a child process (a scratch directory
// with its config and its stderr, killed if the test ends early, SIGTERMed at the end for
// the exit summary on stderr).
#pragma once

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
#include <cstdint>
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
#include "nav/protocols/navd_solution.hpp"
#include "nav/protocols/nmea0183.hpp"
#include "source_paths.hpp"

extern char** environ;

namespace nav::testing {

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

  bool write(const protocols::Bytes& b) const {
    return ::write(master, b.data(), b.size()) == static_cast<ssize_t>(b.size());
  }
  bool write(const std::string& s) const {
    return write(protocols::Bytes(s.begin(), s.end()));
  }
  /// Makes what was written readable by the slave's reader before anything written later
  /// (n_tty_poll flushes the pending master writes), as the bench does in lockstep.
  void flush_to_slave() const {
    pollfd p{slave, POLLIN, 0};
    (void)::poll(&p, 1, 0);
  }
  /// What the slave side (navd) wrote so far, without waiting.
  protocols::Bytes read_now() const {
    protocols::Bytes out;
    std::uint8_t buf[512];
    for (ssize_t n; (n = ::read(master, buf, sizeof buf)) > 0;) out.insert(out.end(), buf, buf + n);
    return out;
  }
  /// Reads until `done(bytes)` or the timeout [ms].
  template <typename Done>
  protocols::Bytes read_until(Done done, int timeout_ms) const {
    protocols::Bytes out;
    const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    while (!done(out) && std::chrono::steady_clock::now() < end) {
      pollfd p{master, POLLIN, 0};
      (void)::poll(&p, 1, 20);
      const protocols::Bytes got = read_now();
      out.insert(out.end(), got.begin(), got.end());
    }
    return out;
  }
};

/// A GX3 0xCB packet with timer `ticks`: level, heading North, at rest at latitude `lat_deg`
/// (specific force −g, the local normal gravity, on z).
inline protocols::Bytes ahrs_packet(std::uint32_t ticks, double lat_deg) {
  const double g = geodesy::normal_gravity(units::deg_to_rad(lat_deg), 0.0);
  protocols::gx3::AccelRateMag m;
  m.accel_g = {0.0f, 0.0f, static_cast<float>(-g / units::kStandardGravity)};
  m.mag_gauss = {0.2f, 0.0f, 0.4f};
  m.timer_ticks = ticks;
  return protocols::gx3::encode(m);
}

/// A GGA fix at (`lat_deg`, `lon_deg`), altitude 0 m: anchors navd's position.
inline std::string gga_anchor(double lat_deg, double lon_deg) {
  protocols::nmea::Gga g;
  g.time.hour = 12;
  g.lat_deg = lat_deg;
  g.lon_deg = lon_deg;
  g.quality = 1;
  g.satellites = 8;
  g.hdop = 0.9;
  g.alt_msl_m = 0.0;
  g.geoid_sep_m = 0.0;
  return protocols::nmea::frame(protocols::nmea::to_sentence(g));
}

/// The solutions in `bytes` (other bytes skipped).
inline std::vector<protocols::navd::Solution> solutions_in(const protocols::Bytes& bytes) {
  std::vector<protocols::navd::Solution> out;
  std::size_t used = 0;
  while (used < bytes.size()) {
    const auto r = protocols::nmea::parse_with_limit(protocols::ByteSpan(bytes).subspan(used),
                                                     protocols::navd::kMaxSentence);
    if (r.status == protocols::ParseStatus::kNeedMore) break;
    used += std::max<std::size_t>(r.consumed, 1);
    if (r.status != protocols::ParseStatus::kComplete) continue;
    if (r.message->talker + r.message->type != protocols::navd::kAddress) continue;
    if (auto s = protocols::navd::decode(*r.message)) out.push_back(*s);
  }
  return out;
}

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream f(p);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

/// navd's --output read in lockstep: every solution read so far, in order.
class SolutionReader {
 public:
  explicit SolutionReader(const TestPty& output) : output_(output) {}
  SolutionReader(const SolutionReader&) = delete;
  SolutionReader& operator=(const SolutionReader&) = delete;

  /// Reads whole lines until the solution for trigger `tag` is among them (at most 3 s);
  /// false if it did not come.
  bool await(std::uint32_t tag) {
    bool got = false;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(3);
    while (!got && std::chrono::steady_clock::now() < deadline) {
      const protocols::Bytes b =
          output_.read_until([](const protocols::Bytes& x) { return !x.empty(); }, 100);
      pending_.insert(pending_.end(), b.begin(), b.end());
      const auto last_lf = std::find(pending_.rbegin(), pending_.rend(), '\n');
      if (last_lf == pending_.rend()) continue;
      const protocols::Bytes complete(pending_.begin(), last_lf.base());
      pending_.erase(pending_.begin(), last_lf.base());
      for (const auto& s : solutions_in(complete)) {
        solutions_.push_back(s);
        got = got || s.trigger_tag == tag;
      }
    }
    return got;
  }

  const std::vector<protocols::navd::Solution>& solutions() const { return solutions_; }

 private:
  const TestPty& output_;
  protocols::Bytes pending_;  // an incomplete last line
  std::vector<protocols::navd::Solution> solutions_;
};

/// navd as a child process, with a scratch directory <TempDir>/<name>-<pid> holding its
/// config (navd.yaml) and its stderr (stderr.txt). Killed (SIGKILL) if still running when
/// this goes out of scope, e.g. after a failed assertion.
class NavdProcess {
 public:
  NavdProcess(const std::string& name, const std::string& config_yaml)
      : dir_(std::filesystem::path(::testing::TempDir()) /
             (name + "-" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(dir_);
    std::ofstream(dir_ / "navd.yaml") << config_yaml;
  }
  ~NavdProcess() {
    if (pid_ > 0 && ::waitpid(pid_, nullptr, WNOHANG) == 0) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  NavdProcess(const NavdProcess&) = delete;
  NavdProcess& operator=(const NavdProcess&) = delete;

  const std::string& exe() const { return exe_; }

  /// Spawns `navd args... --config <dir>/navd.yaml` with stderr to <dir>/stderr.txt;
  /// posix_spawn's result (0 on success).
  int spawn(const std::vector<std::string>& args) {
    std::vector<std::string> all{exe_};
    all.insert(all.end(), args.begin(), args.end());
    all.insert(all.end(), {"--config", (dir_ / "navd.yaml").string()});
    std::vector<char*> argv;
    for (const auto& a : all) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    const std::string err_path = (dir_ / "stderr.txt").string();
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                     0644);
    const int rc = ::posix_spawn(&pid_, exe_.c_str(), &fa, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0) pid_ = -1;
    return rc;
  }

  /// SIGTERM, then reaps navd: its wait status, nullopt if kill or waitpid failed.
  std::optional<int> terminate() {
    if (pid_ <= 0 || ::kill(pid_, SIGTERM) != 0) return std::nullopt;
    int status = 0;
    if (::waitpid(pid_, &status, 0) != pid_) return std::nullopt;
    pid_ = -1;
    return status;
  }

  /// What navd wrote on stderr so far (after terminate(): with its exit summary).
  std::string stderr_text() const { return slurp(dir_ / "stderr.txt"); }

  /// Removes the scratch directory (left in place when a test fails early, for a look).
  void remove_dir() const { std::filesystem::remove_all(dir_); }

 private:
  std::string exe_ = nav::test_paths::binary_dir() + "/navd";
  std::filesystem::path dir_;
  pid_t pid_ = -1;
};

}  // namespace nav::testing

// SPDX-License-Identifier: MIT
// gpsd as an independent peer of the GPS emulator: Debian's gpsd reads the NMEA that
// generate_gps() emits on a pty and must report fixes equal to the emitted truth. This is the
// check against symmetric codec bugs (style.md "Shared codecs are a trap"): the decoder here
// is gpsd's, not nav_protocol's.
//
//   test                         pty master -> slave            gpsd (child, own port)
//   ----                         ---------------------          ----------------------
//   start gpsd -N -n -b -S port -F sock <slave>  ------------>  opens the slave at startup
//   connect 127.0.0.1:port, ?WATCH json  <---------------------  VERSION, DEVICES, WATCH
//   wait for DEVICES naming the slave (bounded)
//   epoch k at t0 + kTimeCompression * t_send(k):  GGA+RMC --->  decodes, reports TPV
//   collect TPV lines until the last epoch's time arrives (bounded)
//   stop gpsd (SIGTERM, then SIGKILL), compare TPVs with truth
//
// Time is compressed (an epoch every 0.2 s of wall time): gpsd stamps fixes with the sentence
// times, not the arrival times. Every wait is bounded, and gpsd is stopped by the RAII
// DutProcess even when an assertion fails. gpsd listens on a free port of 127.0.0.1 picked
// here, never on 2947, and its control socket lives in the test's own folder, so a system gpsd
// is left alone; it runs in its own IPC namespace (unshare) so that its NTP shared-memory
// units never carry the emulated time to the host's chronyd/ntpd. A missing gpsd skips the test, except under CI (CI=true), where
// scripts/setup installs it and its absence is a failure.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "nav/bench/dut_process.hpp"
#include "nav/transport/pty.hpp"
#include "nav/common/geodesy.hpp"
#include "nav/common/units.hpp"
#include "nav/emulators/device.hpp"
#include "nav/emulators/truth.hpp"

namespace nav::testing {
namespace {

namespace fs = std::filesystem;
using SteadyClock = std::chrono::steady_clock;
using nlohmann::json;

constexpr int kEpochs = 10;                  ///< GPS epochs emitted (1 Hz) [-]
constexpr double kTimeCompression = 0.2;     ///< wall seconds per emitted second [-]
constexpr double kLatLonTol_deg = 1e-6;      ///< lat/lon agreement with truth [deg]
constexpr double kSpeedTol_mps = 0.01;       ///< speed agreement [m/s]
constexpr double kTrackTol_deg = 0.01;       ///< course agreement (COG printed to 0.01) [deg]
constexpr double kTimeTol_s = 1e-3;          ///< gpsd prints milliseconds [s]
constexpr int kMinEpochsReported = kEpochs - 2;  ///< gpsd may miss the first epoch(s) [-]
constexpr auto kStartTimeout = std::chrono::seconds(5);
constexpr auto kDrainTimeout = std::chrono::seconds(3);

/// True under a CI runner (CI=true, as GitHub Actions and GitLab CI set it).
bool running_in_ci() {
  const char* ci = std::getenv("CI");
  if (ci == nullptr) return false;
  std::string v(ci);
  std::transform(v.begin(), v.end(), v.begin(), [](unsigned char c) { return std::tolower(c); });
  return v == "true" || v == "1" || v == "yes";
}

/// Absolute path of gpsd: PATH first, then the sbin folders a non-root PATH may lack.
std::optional<std::string> find_gpsd() {
  if (auto p = bench::DutProcess::resolve("gpsd")) return p;
  for (const char* p : {"/usr/sbin/gpsd", "/usr/local/sbin/gpsd", "/sbin/gpsd"}) {
    if (auto r = bench::DutProcess::resolve(p)) return r;
  }
  return std::nullopt;
}

/// A prefix that runs gpsd in its own System V IPC namespace. gpsd attaches the NTP
/// shared-memory units (ntpshm: units 0 and 1 when root, 2..7 otherwise) and its export
/// segment; a host's chronyd or ntpd may read those units as a reference clock, and the
/// emulated UTC must never reach them. Root gets `unshare --ipc`; other users
/// `unshare --user --ipc` (an unprivileged user namespace, gpsd keeps the caller's uid).
/// Empty when unshare is missing or not permitted: gpsd then runs in the host namespace.
std::vector<std::string> ipc_isolation_prefix(const fs::path& dir) {
  const auto unshare = bench::DutProcess::resolve("unshare");
  if (!unshare) return {};
  std::vector<std::string> prefix{*unshare};
  if (::geteuid() != 0) prefix.emplace_back("--user");
  prefix.emplace_back("--ipc");
  std::vector<std::string> probe_argv = prefix;
  probe_argv.emplace_back("true");
  auto probe = bench::DutProcess::start(probe_argv, (dir / "unshare-probe.log").string());
  if (!probe) return {};
  const auto deadline = SteadyClock::now() + std::chrono::seconds(2);
  while (probe->running() && SteadyClock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  probe->stop(0.5);
  if (probe->exit_description() != "exited with status 0") return {};
  prefix.emplace_back("--");
  return prefix;
}

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

/// A file descriptor closed on destruction.
class UniqueFd {
 public:
  UniqueFd() = default;
  explicit UniqueFd(int fd) : fd_(fd) {}
  UniqueFd(UniqueFd&& o) noexcept : fd_(std::exchange(o.fd_, -1)) {}
  UniqueFd& operator=(UniqueFd&& o) noexcept {
    if (this != &o) {
      reset();
      fd_ = std::exchange(o.fd_, -1);
    }
    return *this;
  }
  UniqueFd(const UniqueFd&) = delete;
  UniqueFd& operator=(const UniqueFd&) = delete;
  ~UniqueFd() { reset(); }
  int get() const { return fd_; }
  void reset() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

 private:
  int fd_ = -1;
};

/// A TCP port of 127.0.0.1 that was free a moment ago (the kernel picks it).
std::optional<std::uint16_t> free_loopback_port() {
  UniqueFd s(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0));
  if (s.get() < 0) return std::nullopt;
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = 0;
  if (::bind(s.get(), reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) return std::nullopt;
  socklen_t len = sizeof a;
  if (::getsockname(s.get(), reinterpret_cast<sockaddr*>(&a), &len) != 0) return std::nullopt;
  return ntohs(a.sin_port);
}

/// A gpsd client: newline-delimited JSON over TCP, every read bounded by a deadline.
class GpsdClient {
 public:
  /// Connects to 127.0.0.1:port; nullopt when refused.
  static std::optional<GpsdClient> connect(std::uint16_t port) {
    UniqueFd s(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0));
    if (s.get() < 0) return std::nullopt;
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = htons(port);
    if (::connect(s.get(), reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) return std::nullopt;
    GpsdClient c;
    c.fd_ = std::move(s);
    return c;
  }

  bool send(const std::string& text) const {
    return ::send(fd_.get(), text.data(), text.size(), MSG_NOSIGNAL) ==
           static_cast<ssize_t>(text.size());
  }

  /// Next complete line, or nullopt at the deadline or when gpsd closed the connection.
  std::optional<std::string> next_line(SteadyClock::time_point deadline) {
    for (;;) {
      if (const auto nl = buf_.find('\n'); nl != std::string::npos) {
        std::string line = buf_.substr(0, nl);
        buf_.erase(0, nl + 1);
        if (!line.empty() && line.back() == '\r') line.pop_back();
        return line;
      }
      if (closed_) return std::nullopt;
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
          deadline - SteadyClock::now());
      if (left.count() <= 0) return std::nullopt;
      pollfd p{fd_.get(), POLLIN, 0};
      const int r = ::poll(&p, 1, static_cast<int>(left.count()));
      if (r < 0 && errno == EINTR) continue;
      if (r <= 0) return std::nullopt;
      char chunk[4096];
      const ssize_t n = ::recv(fd_.get(), chunk, sizeof chunk, 0);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        closed_ = true;
        continue;
      }
      buf_.append(chunk, static_cast<std::size_t>(n));
    }
  }

 private:
  GpsdClient() = default;
  UniqueFd fd_;
  std::string buf_;
  bool closed_ = false;
};

/// Writes all bytes to the non-blocking pty master, waiting (bounded) when it is full.
bool write_all(int fd, const protocols::Bytes& bytes) {
  std::size_t off = 0;
  const auto deadline = SteadyClock::now() + std::chrono::seconds(1);
  while (off < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + off, bytes.size() - off);
    if (n > 0) {
      off += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno != EAGAIN && errno != EINTR) return false;
    if (SteadyClock::now() > deadline) return false;
    pollfd p{fd, POLLOUT, 0};
    (void)::poll(&p, 1, 10);
  }
  return true;
}

/// Seconds since the Unix epoch of gpsd's ISO 8601 time "YYYY-MM-DDTHH:MM:SS.sssZ".
std::optional<double> parse_iso8601_utc(const std::string& s) {
  int y = 0, mo = 0, d = 0, h = 0, mi = 0;
  double sec = 0.0;
  char z = 0;
  if (std::sscanf(s.c_str(), "%d-%d-%dT%d:%d:%lf%c", &y, &mo, &d, &h, &mi, &sec, &z) != 7 ||
      z != 'Z') {
    return std::nullopt;
  }
  std::tm tm{};
  tm.tm_year = y - 1900;
  tm.tm_mon = mo - 1;
  tm.tm_mday = d;
  tm.tm_hour = h;
  tm.tm_min = mi;
  return static_cast<double>(::timegm(&tm)) + sec;
}

/// What the emulator sent at one epoch, from truth (not from our own NMEA decoder).
struct Expected {
  double utc_s = 0.0;       ///< UTC of the epoch [s since 1970]
  double lat_deg = 0.0;     ///< [deg]
  double lon_deg = 0.0;     ///< [deg]
  double speed_mps = 0.0;   ///< horizontal speed [m/s]
  double track_deg = 0.0;   ///< course over ground in [0, 360) [deg]
};

/// One test case: where on Earth and when.
struct GpsdCase {
  const char* name;
  double datum_lat_deg;
  double datum_lon_deg;
  double utc_start_unix_s;  ///< UTC at scenario time 0 [s]
  double start_yaw_deg;     ///< heading of the straight [deg]
};

void PrintTo(const GpsdCase& c, std::ostream* os) { *os << c.name; }

/// gpsd running on a pty with a client watching it.
struct GpsdSession {
  bench::DutProcess process;
  GpsdClient client;
  std::string command;
};

class GpsdPeer : public ::testing::TestWithParam<GpsdCase> {};

TEST_P(GpsdPeer, ReportsTheEmittedTruth) {
  const GpsdCase& tc = GetParam();
  const auto gpsd = find_gpsd();
  if (!gpsd) {
    if (running_in_ci()) {
      FAIL() << "gpsd is not installed, but CI is set: scripts/setup installs gpsd";
    }
    GTEST_SKIP() << "gpsd not installed (Debian: apt-get install gpsd, or "
                    "scripts/setup)";
  }

  // Truth: a straight at 1 m/s on the surface, from rest (the speed ramp is ~2 s).
  emulators::TrajectorySpec spec;
  spec.start_yaw_rad = units::deg_to_rad(tc.start_yaw_deg);
  spec.max_accel_mps2 = 1.0;
  emulators::Segment straight;
  straight.kind = emulators::Segment::Kind::kStraight;
  straight.length_m = 100.0;
  straight.speed_mps = 1.0;
  spec.segments.push_back(straight);
  const auto truth = emulators::TruthTrajectory::build(spec);
  ASSERT_TRUE(truth) << truth.error().detail;

  emulators::GpsConfig cfg;
  cfg.rate_hz = 1.0;
  cfg.horizontal_std_m = 0.0;
  cfg.vertical_std_m = 0.0;
  cfg.velocity_std_mps = 0.0;
  cfg.utc_start_unix_s = tc.utc_start_unix_s;
  cfg.datum_lat_rad = units::deg_to_rad(tc.datum_lat_deg);
  cfg.datum_lon_rad = units::deg_to_rad(tc.datum_lon_deg);
  cfg.datum_alt_m = 0.0;
  const auto messages = emulators::generate_gps(cfg, *truth, std::chrono::seconds(kEpochs), 1);
  ASSERT_EQ(messages.size(), static_cast<std::size_t>(kEpochs));

  const geodesy::LocalTangentPlane ltp(
      geodesy::Geodetic{cfg.datum_lat_rad, cfg.datum_lon_rad, cfg.datum_alt_m});
  std::vector<Expected> expected;
  for (const auto& m : messages) {
    const emulators::TruthSample s = truth->at(m.t_valid);
    const geodesy::Geodetic g = ltp.to_geodetic(s.p_n);
    Expected e;
    e.utc_s = cfg.utc_start_unix_s + to_seconds(m.t_valid);
    e.lat_deg = units::rad_to_deg(g.lat_rad);
    e.lon_deg = units::rad_to_deg(g.lon_rad);
    e.speed_mps = std::hypot(s.v_n.x(), s.v_n.y());
    e.track_deg = std::fmod(units::rad_to_deg(std::atan2(s.v_n.y(), s.v_n.x())) + 360.0, 360.0);
    expected.push_back(e);
  }

  auto pty = transport::Pty::open();
  ASSERT_TRUE(pty) << pty.error().detail;
  const fs::path dir = fs::path(::testing::TempDir()) /
                       ("navbench-gpsd-" + std::string(tc.name) + "-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path log = dir / "gpsd.log";

  const std::vector<std::string> isolation = ipc_isolation_prefix(dir);
  // Start gpsd on a free port; a port taken between picking and binding gets another try.
  std::optional<GpsdSession> session;
  std::string failures;
  for (int attempt = 0; attempt < 3 && !session; ++attempt) {
    const auto port = free_loopback_port();
    ASSERT_TRUE(port) << "no free TCP port on 127.0.0.1";
    std::vector<std::string> argv = isolation;
    argv.insert(argv.end(), {*gpsd, "-N", "-n", "-b", "-S", std::to_string(*port), "-F",
                             (dir / "gpsd.sock").string(), pty->slave_path()});
    std::string command;
    for (const auto& a : argv) command += (command.empty() ? "" : " ") + a;
    auto proc = bench::DutProcess::start(argv, log.string());
    ASSERT_TRUE(proc) << proc.error().detail;
    const auto deadline = SteadyClock::now() + kStartTimeout;
    std::optional<GpsdClient> client;
    while (!client && proc->running() && SteadyClock::now() < deadline) {
      client = GpsdClient::connect(*port);
      if (!client) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    if (client) {
      session.emplace(GpsdSession{std::move(*proc), std::move(*client), command});
    } else {
      failures += command + ": " +
                  (proc->running() ? std::string("no connection") : proc->exit_description()) +
                  "\n";
    }
  }
  ASSERT_TRUE(session) << failures << "gpsd log:\n" << slurp(log);
  std::cout << "gpsd command: " << session->command << "\n";

  // Watch, and wait until gpsd lists the pty as an active device before sending: bytes sent
  // before gpsd opened the slave could be flushed by its serial setup.
  ASSERT_TRUE(session->client.send("?WATCH={\"enable\":true,\"json\":true}\n"));
  std::string version;
  bool device_active = false;
  {
    const auto deadline = SteadyClock::now() + kStartTimeout;
    while (!device_active) {
      const auto line = session->client.next_line(deadline);
      if (!line) break;
      const json j = json::parse(*line, nullptr, false);
      if (j.is_discarded()) continue;
      const std::string cls = j.value("class", "");
      if (cls == "VERSION") version = j.value("release", "");
      if (cls == "DEVICES") {
        for (const auto& d : j.value("devices", json::array())) {
          if (d.value("path", "") == pty->slave_path()) device_active = true;
        }
      }
      if (cls == "DEVICE" && j.value("path", "") == pty->slave_path() &&
          j.contains("activated")) {
        device_active = true;
      }
    }
  }
  ASSERT_TRUE(device_active) << "gpsd did not report " << pty->slave_path()
                             << " as a device\ngpsd log:\n" << slurp(log);
  std::cout << "gpsd release: " << version << "\n";

  // Send each epoch at its compressed wire time, collecting what gpsd reports meanwhile.
  std::vector<json> tpvs;
  std::vector<std::string> lines;
  auto take = [&](const std::string& line) {
    lines.push_back(line);
    const json j = json::parse(line, nullptr, false);
    if (!j.is_discarded() && j.value("class", "") == "TPV") tpvs.push_back(j);
  };
  const auto t0 = SteadyClock::now();
  for (const auto& m : messages) {
    const auto due = t0 + std::chrono::duration_cast<SteadyClock::duration>(
                              std::chrono::duration<double>(kTimeCompression *
                                                            to_seconds(m.t_send)));
    while (const auto line = session->client.next_line(due)) take(*line);
    std::this_thread::sleep_until(due);
    ASSERT_TRUE(write_all(pty->master(), m.bytes)) << "write to the pty master failed";
  }
  // Drain until a TPV carries the last epoch's time (its report is complete), bounded.
  const double last_utc = expected.back().utc_s;
  const auto drain_deadline = SteadyClock::now() + kDrainTimeout;
  auto has_last = [&] {
    return std::any_of(tpvs.begin(), tpvs.end(), [&](const json& j) {
      const auto t = parse_iso8601_utc(j.value("time", ""));
      return t && std::abs(*t - last_utc) < kTimeTol_s && j.contains("speed");
    });
  };
  while (!has_last()) {
    const auto line = session->client.next_line(drain_deadline);
    if (!line) break;
    take(*line);
  }
  // One more short drain: gpsd may follow with a fuller report of the same epoch.
  while (const auto line =
             session->client.next_line(SteadyClock::now() + std::chrono::milliseconds(300))) {
    take(*line);
  }
  session->process.stop(2.0);

  std::string transcript;
  for (const auto& l : lines) transcript += l + "\n";
  const std::string context = "gpsd said:\n" + transcript + "gpsd log:\n" + slurp(log);

  // Every reported time must be one we sent; the last report of an epoch is its fix.
  std::map<int, json> fix_of_epoch;
  for (const json& j : tpvs) {
    if (!j.contains("time")) continue;
    const auto t = parse_iso8601_utc(j["time"].get<std::string>());
    ASSERT_TRUE(t) << "unparsable TPV time in " << j.dump() << "\n" << context;
    const double k = std::round(*t - cfg.utc_start_unix_s);
    const bool ours = k >= 0 && k < kEpochs &&
                      std::abs(*t - expected[static_cast<std::size_t>(k)].utc_s) < kTimeTol_s;
    ASSERT_TRUE(ours) << "gpsd reported a time that was never emitted: " << j.dump() << "\n"
                      << context;
    if (j.contains("lat") && j.contains("lon")) fix_of_epoch[static_cast<int>(k)] = j;
  }
  ASSERT_GE(static_cast<int>(fix_of_epoch.size()), kMinEpochsReported)
      << "gpsd reported a position for too few epochs\n" << context;

  double max_dlat = 0.0, max_dlon = 0.0, max_dspeed = 0.0, max_dtrack = 0.0;
  int with_speed = 0;
  for (const auto& [k, j] : fix_of_epoch) {
    const Expected& e = expected[static_cast<std::size_t>(k)];
    SCOPED_TRACE("epoch " + std::to_string(k) + ": " + j.dump());
    EXPECT_GE(j.value("mode", 0), 2);
    const double dlat = std::abs(j["lat"].get<double>() - e.lat_deg);
    const double dlon = std::abs(j["lon"].get<double>() - e.lon_deg);
    EXPECT_LE(dlat, kLatLonTol_deg);
    EXPECT_LE(dlon, kLatLonTol_deg);
    max_dlat = std::max(max_dlat, dlat);
    max_dlon = std::max(max_dlon, dlon);
    if (j.contains("speed")) {
      ++with_speed;
      const double dspeed = std::abs(j["speed"].get<double>() - e.speed_mps);
      EXPECT_LE(dspeed, kSpeedTol_mps);
      max_dspeed = std::max(max_dspeed, dspeed);
    }
    if (j.contains("track") && e.speed_mps >= 0.05) {
      double dtrack = std::abs(j["track"].get<double>() - e.track_deg);
      dtrack = std::min(dtrack, 360.0 - dtrack);
      EXPECT_LE(dtrack, kTrackTol_deg);
      max_dtrack = std::max(max_dtrack, dtrack);
    }
  }
  EXPECT_GE(with_speed, kMinEpochsReported) << "too few fixes carry a speed\n" << context;

  std::printf("gpsd %s: %zu of %d epochs reported, max |dlat| = %.3g deg, max |dlon| = %.3g deg,"
              " max |dspeed| = %.3g m/s, max |dtrack| = %.3g deg\n",
              version.c_str(), fix_of_epoch.size(), kEpochs, max_dlat, max_dlon, max_dspeed,
              max_dtrack);
  RecordProperty("gpsd_release", version);
  RecordProperty("epochs_reported", static_cast<int>(fix_of_epoch.size()));
  RecordProperty("max_dlat_deg", std::to_string(max_dlat));
  RecordProperty("max_dlon_deg", std::to_string(max_dlon));
  RecordProperty("max_dspeed_mps", std::to_string(max_dspeed));
  if (!HasFailure()) fs::remove_all(dir);
}

// Both hemisphere signs of the NMEA N/S and E/W letters, and a UTC start with a fraction.
INSTANTIATE_TEST_SUITE_P(
    Datums, GpsdPeer,
    ::testing::Values(GpsdCase{"daejeon_ne", 36.3833, 127.3600, 1780315200.0, 30.0},
                      GpsdCase{"rio_sw", -22.9068, -43.1729, 1780315200.5, 200.0}),
    [](const ::testing::TestParamInfo<GpsdCase>& p) { return std::string(p.param.name); });

}  // namespace
}  // namespace nav::testing

// SPDX-License-Identifier: MIT
// A DUT that misbehaves on purpose, for the bench's tests. It reads the GX3 0xCB packets on
// its trigger port (the AHRS streams from power-on: `continuous: true`) and answers each with
// a well-formed $PNVBSOL solution, except that:
//
//   --lie            every solution names trigger 4000000000, which was never sent: a bench
//                    must judge it hung, not wait forever for the trigger it sent;
//   --crash-at SEC   it exits (status 3) on the first packet at or after scenario time SEC
//                    (timer ticks / 62500 from the first packet): a lockstep bench must name
//                    that scenario time;
//   --open-after SEC it opens its ports (and --gps PATH, which it never reads) only SEC after
//                    it started: a bench must warn that it had not opened them in time;
//   --stubborn FILE  it ignores SIGTERM, SIGHUP and SIGINT, starts a child (in its process
//                    group) that ignores them too and sleeps, and writes "PID CHILD_PID" to
//                    FILE: the group must still end with the bench, however the bench ends;
//   --flood          it writes random bytes (/dev/urandom) to its output and its stderr as
//                    fast as they go, and answers nothing: the bench must cut its logs;
//   --garble         every other solution has a wrong checksum: the bench must say which
//                    lines were malformed, and why.
//
//   lying_dut --ahrs PATH --output PATH [--gps PATH] [--lie] [--crash-at SEC] [--open-after SEC]
//             [--stubborn FILE] [--flood] [--garble]
#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <optional>
#include <string>
#include <vector>

#include "nav/protocols/microstrain_gx3.hpp"
#include "nav/protocols/navd_solution.hpp"

namespace gx3 = nav::protocols::gx3;

int main(int argc, char** argv) {
  std::string ahrs_path, output_path, gps_path, stubborn_file;
  bool lie = false, flood = false, garble = false;
  double crash_at = -1.0, open_after = 0.0;
  for (int i = 1; i < argc; ++i) {
    const std::string k = argv[i];
    if (k == "--lie") {
      lie = true;
    } else if (k == "--flood") {
      flood = true;
    } else if (k == "--garble") {
      garble = true;
    } else if (i + 1 < argc && k == "--ahrs") {
      ahrs_path = argv[++i];
    } else if (i + 1 < argc && k == "--output") {
      output_path = argv[++i];
    } else if (i + 1 < argc && k == "--crash-at") {
      crash_at = std::atof(argv[++i]);
    } else if (i + 1 < argc && k == "--gps") {
      gps_path = argv[++i];
    } else if (i + 1 < argc && k == "--open-after") {
      open_after = std::atof(argv[++i]);
    } else if (i + 1 < argc && k == "--stubborn") {
      stubborn_file = argv[++i];
    }
  }
  if (ahrs_path.empty() || output_path.empty()) {
    std::fprintf(stderr, "usage: lying_dut --ahrs PATH --output PATH [--gps PATH] [--lie] "
                         "[--crash-at SEC] [--open-after SEC] [--stubborn FILE] [--flood] "
                         "[--garble]\n");
    return 2;
  }
  if (!stubborn_file.empty()) {
    for (int sig : {SIGTERM, SIGHUP, SIGINT}) ::signal(sig, SIG_IGN);
    const pid_t child = ::fork();  // inherits the ignored signals
    if (child == 0) {
      for (;;) ::pause();
    }
    const std::string part = stubborn_file + ".part";  // whole or absent for a reader
    if (std::FILE* f = std::fopen(part.c_str(), "w")) {
      std::fprintf(f, "%d %d\n", static_cast<int>(::getpid()), static_cast<int>(child));
      std::fclose(f);
      std::rename(part.c_str(), stubborn_file.c_str());
    }
  }
  if (open_after > 0) {
    const timespec ts{static_cast<time_t>(open_after),
                      static_cast<long>((open_after - static_cast<double>(static_cast<time_t>(open_after))) * 1e9)};
    ::nanosleep(&ts, nullptr);
  }
  const int gps = gps_path.empty() ? -1 : ::open(gps_path.c_str(), O_RDONLY | O_NOCTTY);
  (void)gps;  // held open, never read
  const int in = ::open(ahrs_path.c_str(), O_RDONLY | O_NOCTTY);
  const int out = ::open(output_path.c_str(), O_WRONLY | O_NOCTTY);
  if (in < 0 || out < 0) {
    std::perror("lying_dut: open");
    return 1;
  }
  if (flood) {
    const int random = ::open("/dev/urandom", O_RDONLY);
    std::uint8_t noise[65536];
    for (;;) {
      const ssize_t got = ::read(random, noise, sizeof noise);
      if (got <= 0) return 1;
      if (::write(out, noise, static_cast<std::size_t>(got)) < 0) return 0;
      if (::write(STDERR_FILENO, noise, static_cast<std::size_t>(got)) < 0) return 0;
    }
  }
  nav::protocols::navd::Solution s;
  s.input = "AHRS";
  std::optional<std::uint32_t> first;
  std::vector<std::uint8_t> rx;
  std::uint8_t buf[256];
  for (;;) {
    const ssize_t n = ::read(in, buf, sizeof buf);
    if (n <= 0) return 0;
    rx.insert(rx.end(), buf, buf + n);
    std::size_t pos = 0;
    while (pos < rx.size()) {
      const auto r = gx3::parse(nav::protocols::ByteSpan(rx.data() + pos, rx.size() - pos));
      if (r.status == nav::protocols::ParseStatus::kNeedMore) break;
      pos += r.consumed > 0 ? r.consumed : 1;
      if (r.status != nav::protocols::ParseStatus::kComplete || !r.message) continue;
      const std::uint32_t ticks = r.message->timer_ticks;
      if (!first) first = ticks;
      if (crash_at >= 0 && static_cast<double>(ticks - *first) / gx3::kTicksPerSecond >= crash_at) {
        return 3;
      }
      s.trigger_tag = lie ? 4000000000ULL : ticks;
      std::string line = nav::protocols::navd::encode(s);
      if (garble && s.seq % 2 == 1) {  // "*HH\r\n": the checksum's last digit changed
        char& digit = line[line.size() - 3];
        digit = digit == '0' ? '1' : '0';
      }
      if (::write(out, line.data(), line.size()) < 0) return 0;
      ++s.seq;
    }
    rx.erase(rx.begin(), rx.begin() + static_cast<std::ptrdiff_t>(pos));
  }
}

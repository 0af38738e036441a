// SPDX-License-Identifier: MIT
// modem_peer: a tiny test DUT for multi-vehicle scenarios (scenarios/two-vehicles-modem.yaml,
// modem_test.cpp). It starts its GX3's continuous mode, answers every 0xCB packet with a
// $PNVBSOL (no position: status ALIGNING) echoing the packet's timer tag, and before every
// N-th answer writes "$PEER,<k>*hh" CRLF to its acoustic modem's serial line. Whatever
// arrives on the modem line is logged to stderr (the run's dut-<vehicle>.log) and counted.
//
//   modem_peer --ahrs PATH --output PATH --modem PATH [--every N]
//
// Exit 0 on SIGTERM/SIGINT or a hang-up of the AHRS line; 2 on bad arguments or ports.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <termios.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "nav/protocols/microstrain_gx3.hpp"
#include "nav/protocols/navd_solution.hpp"
#include "nav/protocols/nmea0183.hpp"

namespace {

volatile std::sig_atomic_t g_stop = 0;
extern "C" void on_signal(int) { g_stop = 1; }

int open_raw(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
  if (fd < 0) return -1;
  termios t{};
  if (::tcgetattr(fd, &t) == 0) {
    ::cfmakeraw(&t);
    ::tcsetattr(fd, TCSANOW, &t);
  }
  return fd;
}

void write_all(int fd, const void* data, std::size_t n) {
  const auto* p = static_cast<const std::uint8_t*>(data);
  while (n > 0) {
    const ssize_t w = ::write(fd, p, n);
    if (w > 0) {
      p += w;
      n -= static_cast<std::size_t>(w);
      continue;
    }
    pollfd q{fd, POLLOUT, 0};
    ::poll(&q, 1, 10);
    if (g_stop) return;
  }
}

}  // namespace

int main(int argc, char** argv) {
  namespace gx3 = nav::protocols::gx3;
  std::string ahrs_path, output_path, modem_path;
  long every = 100;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    if (k == "--ahrs") ahrs_path = argv[i + 1];
    else if (k == "--output") output_path = argv[i + 1];
    else if (k == "--modem") modem_path = argv[i + 1];
    else if (k == "--every") every = std::strtol(argv[i + 1], nullptr, 10);
    else {
      std::fprintf(stderr, "modem_peer: unknown option %s\n", k.c_str());
      return 2;
    }
  }
  if (ahrs_path.empty() || output_path.empty() || modem_path.empty() || every < 1) {
    std::fprintf(stderr, "usage: modem_peer --ahrs PATH --output PATH --modem PATH [--every N]\n");
    return 2;
  }
  const int ahrs = open_raw(ahrs_path), out = open_raw(output_path), modem = open_raw(modem_path);
  if (ahrs < 0 || out < 0 || modem < 0) {
    std::fprintf(stderr, "modem_peer: cannot open a port: %s\n", std::strerror(errno));
    return 2;
  }
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  ::sigaction(SIGTERM, &sa, nullptr);
  ::sigaction(SIGINT, &sa, nullptr);
  ::signal(SIGPIPE, SIG_IGN);

  const auto start = gx3::encode_set_continuous(gx3::kCmdAccelRateMag);
  write_all(ahrs, start.data(), start.size());

  std::vector<std::uint8_t> rx;
  std::string modem_rx;
  std::uint64_t packets = 0, sent = 0, received = 0;
  while (!g_stop) {
    pollfd p[2] = {{ahrs, POLLIN, 0}, {modem, POLLIN, 0}};
    if (::poll(p, 2, 100) < 0) continue;
    std::uint8_t buf[512];
    if (p[1].revents & POLLIN) {
      for (ssize_t n; (n = ::read(modem, buf, sizeof buf)) > 0;) {
        modem_rx.append(reinterpret_cast<const char*>(buf), static_cast<std::size_t>(n));
      }
      for (auto eol = modem_rx.find('\n'); eol != std::string::npos; eol = modem_rx.find('\n')) {
        ++received;
        std::fprintf(stderr, "modem rx %llu: %s\n", static_cast<unsigned long long>(received),
                     modem_rx.substr(0, eol).c_str());
        modem_rx.erase(0, eol + 1);
      }
    }
    if (p[0].revents & (POLLHUP | POLLERR) && !(p[0].revents & POLLIN)) break;
    if (!(p[0].revents & POLLIN)) continue;
    for (ssize_t n; (n = ::read(ahrs, buf, sizeof buf)) > 0;) rx.insert(rx.end(), buf, buf + n);
    std::size_t pos = 0;
    while (pos < rx.size()) {
      const auto r = gx3::parse(nav::protocols::ByteSpan(rx.data() + pos, rx.size() - pos));
      if (r.status == nav::protocols::ParseStatus::kNeedMore) break;
      pos += std::max<std::size_t>(r.consumed, 1);
      if (r.status != nav::protocols::ParseStatus::kComplete || !r.message) continue;
      if (++packets % static_cast<std::uint64_t>(every) == 0) {
        // The modem message first: in lockstep the bench reads it before the answer.
        nav::protocols::nmea::Sentence s;
        s.talker = "P";
        s.type = "EER";
        s.fields = {std::to_string(++sent)};
        const std::string line = nav::protocols::nmea::frame(s);
        write_all(modem, line.data(), line.size());
      }
      nav::protocols::navd::Solution sol;
      sol.input = "AHRS";
      sol.trigger_tag = r.message->timer_ticks;
      sol.seq = packets - 1;
      sol.status = "ALIGNING";
      const std::string answer = nav::protocols::navd::encode(sol);
      write_all(out, answer.data(), answer.size());
    }
    rx.erase(rx.begin(), rx.begin() + static_cast<std::ptrdiff_t>(pos));
  }
  std::fprintf(stderr, "modem_peer: %llu packets, %llu modem messages sent, %llu received\n",
               static_cast<unsigned long long>(packets), static_cast<unsigned long long>(sent),
               static_cast<unsigned long long>(received));
  return 0;
}

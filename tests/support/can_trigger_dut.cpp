// SPDX-License-Identifier: MIT
// A minimal DUT for end-to-end tests of a CAN trigger (docs/dut-contract.md): it answers every
// NMEA 2000 trigger frame of one source address with one `$PNVBSOL` and records, for each,
// how many serial lines and CAN frames it had received when it answered. It estimates
// nothing (no position, attitude 0). navd answers only GX3 triggers, hence this program.
//
//   can_trigger_dut --can IFACE --source N --serial PATH --output PATH
//
// Per wake-up, as dut-contract section 5 asks of a DUT with a CAN trigger: read the CAN
// socket (the trigger's) until it would block, then the serial line, then answer the trigger
// frames of the wake-up in arrival order. Each answer is logged on stderr (the run's dut.log):
//
//   can_trigger_dut: trigger tag=32576007 serial_lines=12 can_frames=57
//
// serial_lines counts LF bytes received on the serial line, can_frames every frame received;
// both include what was read in the same wake-up. The trigger tag (PGN * 256 + SID) and the
// checksum are computed here from the bytes, not with the bench's codecs. Exits 0 when the
// serial line or the output hangs up, 2 on bad usage, 3 when a port cannot be opened.
#include <fcntl.h>
#include <poll.h>
#include <systemd/sd-daemon.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "nav/transport/can_socket.hpp"

namespace {

int open_raw(const char* path) {
  const int fd = ::open(path, O_RDWR | O_NOCTTY | O_NONBLOCK);
  if (fd < 0) return -1;
  termios t{};
  if (::tcgetattr(fd, &t) == 0) {
    ::cfmakeraw(&t);
    t.c_cflag |= CLOCAL | CREAD;
    ::tcsetattr(fd, TCSANOW, &t);
  }
  return fd;
}

/// The trigger tag of an NMEA 2000 frame of `source`: a single-frame PGN with a SID.
bool trigger_tag(const nav::transport::CanFrame& f, unsigned source, std::uint64_t& tag) {
  if (!f.extended || f.rtr || f.dlc != 8 || (f.id & 0xFFu) != source) return false;
  const std::uint32_t pf = (f.id >> 16) & 0xFFu;
  std::uint32_t pgn = (f.id >> 8) & 0x3FFFFu;
  if (pf < 240) pgn &= ~0xFFu;
  switch (pgn) {
    case 127250: case 127251: case 127257: case 128259: case 128267: case 129026:
      tag = std::uint64_t{pgn} * 256 + f.data[0];
      return true;
    default:
      return false;
  }
}

std::string solution(std::uint64_t tag, std::uint64_t seq) {
  const std::string body = "PNVBSOL,N2K," + std::to_string(tag) + "," + std::to_string(seq) +
                           ",,,,,,,0.0000,0.0000,0.0000,ALIGNING";
  unsigned sum = 0;
  for (const char c : body) sum ^= static_cast<unsigned char>(c);
  char tail[8];
  std::snprintf(tail, sizeof tail, "*%02X\r\n", sum);
  return "$" + body + tail;
}

bool write_all(int fd, const std::string& s) {
  std::size_t off = 0;
  while (off < s.size()) {
    const ssize_t n = ::write(fd, s.data() + off, s.size() - off);
    if (n > 0) {
      off += static_cast<std::size_t>(n);
    } else if (n < 0 && errno == EAGAIN) {
      pollfd p{fd, POLLOUT, 0};
      ::poll(&p, 1, 100);
    } else {
      return false;
    }
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  std::string iface, serial_path, output_path;
  unsigned source = 256;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    if (k == "--can") iface = argv[i + 1];
    else if (k == "--source") source = static_cast<unsigned>(std::atoi(argv[i + 1]));
    else if (k == "--serial") serial_path = argv[i + 1];
    else if (k == "--output") output_path = argv[i + 1];
  }
  if (iface.empty() || serial_path.empty() || output_path.empty() || source > 251) {
    std::fprintf(stderr, "usage: can_trigger_dut --can IFACE --source N --serial PATH --output PATH\n");
    return 2;
  }
  auto can = nav::transport::CanSocket::open(iface);
  const int serial = open_raw(serial_path.c_str());
  const int output = open_raw(output_path.c_str());
  if (!can || serial < 0 || output < 0) {
    std::fprintf(stderr, "can_trigger_dut: cannot open %s\n",
                 !can ? can.error().detail.c_str() : serial < 0 ? serial_path.c_str()
                                                               : output_path.c_str());
    return 3;
  }
  // Ready (docs/dut-contract.md §1): a lockstep run starts now, not after its whole startup.
  sd_notify(0, "READY=1");
  std::uint64_t lines = 0, frames = 0, seq = 0;
  for (;;) {
    pollfd p[2] = {{can->fd(), POLLIN, 0}, {serial, POLLIN, 0}};
    if (::poll(p, 2, 1000) < 0 && errno != EINTR) return 3;
    std::vector<std::uint64_t> triggers;
    for (;;) {  // the trigger's socket first
      auto r = can->receive();
      if (!r || !*r) break;
      ++frames;
      std::uint64_t tag = 0;
      if (trigger_tag((*r)->frame, source, tag)) triggers.push_back(tag);
    }
    bool hangup = (p[1].revents & POLLHUP) != 0;
    for (;;) {
      char buf[4096];
      const ssize_t n = ::read(serial, buf, sizeof buf);
      if (n <= 0) {
        hangup = hangup || n == 0 || (errno != EAGAIN && errno != EINTR);
        break;
      }
      for (ssize_t i = 0; i < n; ++i) lines += buf[i] == '\n' ? 1 : 0;
    }
    for (const std::uint64_t tag : triggers) {
      std::fprintf(stderr, "can_trigger_dut: trigger tag=%llu serial_lines=%llu can_frames=%llu\n",
                   static_cast<unsigned long long>(tag), static_cast<unsigned long long>(lines),
                   static_cast<unsigned long long>(frames));
      if (!write_all(output, solution(tag, seq++))) return 0;  // the output hung up
    }
    if (hangup && triggers.empty()) return 0;
  }
}

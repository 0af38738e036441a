// SPDX-License-Identifier: MIT
#include "nav/transport/pty.hpp"

#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <utility>

namespace nav::transport {

Result<Pty> Pty::open() {
  Pty p;
  char name[PATH_MAX] = {};
  termios tio{};
  ::cfmakeraw(&tio);
  tio.c_cflag |= CLOCAL | CREAD;
  if (::openpty(&p.master_, &p.slave_, name, &tio, nullptr) != 0) {
    return tl::unexpected(io_error("openpty", errno));
  }
  p.slave_path_ = name;
  for (int fd : {p.master_, p.slave_}) {
    if (::fcntl(fd, F_SETFD, FD_CLOEXEC) != 0) return tl::unexpected(io_error("fcntl", errno));
  }
  const int flags = ::fcntl(p.master_, F_GETFL);
  if (flags < 0 || ::fcntl(p.master_, F_SETFL, flags | O_NONBLOCK) != 0) {
    return tl::unexpected(io_error("fcntl O_NONBLOCK", errno));
  }
  return p;
}

Pty::Pty(Pty&& o) noexcept
    : master_(std::exchange(o.master_, -1)),
      slave_(std::exchange(o.slave_, -1)),
      slave_path_(std::move(o.slave_path_)) {}

Pty& Pty::operator=(Pty&& o) noexcept {
  if (this != &o) {
    this->~Pty();
    master_ = std::exchange(o.master_, -1);
    slave_ = std::exchange(o.slave_, -1);
    slave_path_ = std::move(o.slave_path_);
  }
  return *this;
}

Pty::~Pty() {
  if (master_ >= 0) ::close(master_);
  if (slave_ >= 0) ::close(slave_);
}

void Pty::flush_to_slave() const {
  // n_tty_poll() runs tty_buffer_flush_work() when no input is available yet, which waits
  // for the pending flush of the master's writes into the slave's line discipline.
  pollfd p{slave_, POLLIN, 0};
  (void)::poll(&p, 1, 0);
}

void Pty::discard_unread() const {
  flush_to_slave();  // what is still on its way is discarded too
  (void)::tcflush(slave_, TCIFLUSH);
}

}  // namespace nav::transport

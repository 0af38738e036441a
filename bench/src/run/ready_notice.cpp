// SPDX-License-Identifier: MIT
#include "run/ready_notice.hpp"

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstddef>
#include <cstring>
#include <string_view>

namespace nav::bench {

bool says_ready(std::string_view datagram) {
  while (!datagram.empty()) {
    const std::size_t end = datagram.find('\n');
    if (datagram.substr(0, end) == "READY=1") return true;
    if (end == std::string_view::npos) break;
    datagram.remove_prefix(end + 1);
  }
  return false;
}

Result<ReadyNotice> ReadyNotice::open() {
  const int fd = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) return tl::unexpected(io_error("readiness socket", errno));
  // Binding the family alone: the kernel picks a name of its own in the abstract namespace
  // (unix(7), "autobind"), so that no two runs ever share one.
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  const int one = 1;
  if (::setsockopt(fd, SOL_SOCKET, SO_PASSCRED, &one, sizeof one) != 0 ||
      ::bind(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof(sa_family_t)) != 0) {
    const int e = errno;
    ::close(fd);
    return tl::unexpected(io_error("readiness socket", e));
  }
  socklen_t len = sizeof addr;
  if (::getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &len) != 0 ||
      len <= offsetof(sockaddr_un, sun_path) + 1 || addr.sun_path[0] != '\0') {
    const int e = errno;
    ::close(fd);
    return tl::unexpected(io_error("readiness socket: no abstract name", e));
  }
  const std::size_t name_len = len - offsetof(sockaddr_un, sun_path) - 1;
  return ReadyNotice(fd, "@" + std::string(addr.sun_path + 1, name_len));
}

ReadyNotice::ReadyNotice(ReadyNotice&& o) noexcept
    : fd_(o.fd_), address_(std::move(o.address_)), ready_(o.ready_) {
  o.fd_ = -1;
}

ReadyNotice::~ReadyNotice() {
  if (fd_ >= 0) ::close(fd_);
}

bool ReadyNotice::read(pid_t group) {
  std::array<char, 4096> buf{};
  alignas(cmsghdr) std::array<char, CMSG_SPACE(sizeof(ucred))> control{};
  for (;;) {
    iovec iov{buf.data(), buf.size()};
    msghdr msg{};
    msg.msg_iov = &iov;
    msg.msg_iovlen = 1;
    msg.msg_control = control.data();
    msg.msg_controllen = control.size();
    const ssize_t n = ::recvmsg(fd_, &msg, MSG_CMSG_CLOEXEC);
    if (n < 0) break;  // EAGAIN: nothing more queued
    pid_t sender = -1;
    for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c != nullptr; c = CMSG_NXTHDR(&msg, c)) {
      if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_CREDENTIALS) {
        ucred cred{};
        std::memcpy(&cred, CMSG_DATA(c), sizeof cred);
        sender = cred.pid;
      }
    }
    const bool ours = sender > 0 && (sender == group || ::getpgid(sender) == group);
    if (ours && says_ready(std::string_view(buf.data(), static_cast<std::size_t>(n)))) {
      ready_ = true;
    }
  }
  return ready_;
}

}  // namespace nav::bench

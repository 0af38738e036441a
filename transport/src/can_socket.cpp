// SPDX-License-Identifier: MIT
#include "nav/transport/can_socket.hpp"

#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <sys/socket.h>
#include <sys/uio.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <utility>

namespace nav::transport {
namespace {

tl::unexpected<Error> open_error(const std::string& ifname, int err) {
  const ErrorCode code = err == ENODEV ? ErrorCode::kNotFound : ErrorCode::kIo;
  return fail(code, "cannot open CAN interface " + ifname + ": " +
                        std::generic_category().message(err));
}

tl::unexpected<Error> io_failure(const std::string& ifname, const std::string& what, int err) {
  return fail(ErrorCode::kIo, "CAN interface " + ifname + ": cannot " + what + ": " +
                                  std::generic_category().message(err));
}

std::string hex(std::uint32_t value) {
  char text[16];
  std::snprintf(text, sizeof(text), "%X", static_cast<unsigned>(value));
  return text;
}

int set_flag(int fd, int level, int name, bool on) {
  const int value = on ? 1 : 0;
  return ::setsockopt(fd, level, name, &value, sizeof(value));
}

}  // namespace

bool operator==(const CanFrame& a, const CanFrame& b) {
  if (a.id != b.id || a.extended != b.extended || a.rtr != b.rtr || a.dlc != b.dlc ||
      a.error != b.error) {
    return false;
  }
  if (a.rtr) return true;
  const std::size_t n = std::min<std::size_t>(a.dlc, a.data.size());
  return std::equal(a.data.begin(), a.data.begin() + static_cast<std::ptrdiff_t>(n),
                    b.data.begin());
}

Result<CanSocket> CanSocket::open(const std::string& ifname, const CanSocketOptions& options) {
  if (ifname.empty() || ifname.size() >= IFNAMSIZ) {
    return fail(ErrorCode::kInvalidArgument,
                "cannot open CAN interface '" + ifname + "': not an interface name (1 to " +
                    std::to_string(IFNAMSIZ - 1) + " characters)");
  }
  // Look the interface up first: "No such device" is the useful answer even on a kernel
  // without CAN, where socket() below would fail first.
  const unsigned ifindex = ::if_nametoindex(ifname.c_str());
  if (ifindex == 0) return open_error(ifname, errno);

  const int fd = ::socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
  if (fd < 0) return open_error(ifname, errno);
  // From here the socket owns fd, so every early return closes it.
  CanSocket socket(fd, ifname);

  if (set_flag(fd, SOL_CAN_RAW, CAN_RAW_LOOPBACK, options.loopback) != 0 ||
      set_flag(fd, SOL_CAN_RAW, CAN_RAW_RECV_OWN_MSGS, options.receive_own_frames) != 0) {
    return open_error(ifname, errno);
  }
  if (options.error_classes != 0) {
    const can_err_mask_t mask = options.error_classes & CAN_ERR_MASK;
    if (::setsockopt(fd, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &mask, sizeof(mask)) != 0) {
      return open_error(ifname, errno);
    }
  }
  // A kernel that cannot stamp only costs the timestamps, not the socket.
  if (options.timestamps) (void)set_flag(fd, SOL_SOCKET, SO_TIMESTAMPNS, true);

  sockaddr_can addr{};
  addr.can_family = AF_CAN;
  addr.can_ifindex = static_cast<int>(ifindex);
  if (::bind(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof(addr)) != 0) {
    return open_error(ifname, errno);
  }
  return socket;
}

CanSocket::CanSocket(int fd, std::string ifname) : fd_(fd), ifname_(std::move(ifname)) {}

CanSocket::CanSocket(CanSocket&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), ifname_(std::move(other.ifname_)) {}

CanSocket& CanSocket::operator=(CanSocket&& other) noexcept {
  if (this != &other) {
    close_fd();
    fd_ = std::exchange(other.fd_, -1);
    ifname_ = std::move(other.ifname_);
  }
  return *this;
}

CanSocket::~CanSocket() { close_fd(); }

void CanSocket::close_fd() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

Result<void> CanSocket::send(const CanFrame& frame) {
  const std::uint32_t max_id = frame.extended || frame.error ? CanFrame::kMaxExtendedId
                                                             : CanFrame::kMaxStandardId;
  if (frame.id > max_id || frame.dlc > CAN_MAX_DLEN) {
    return fail(ErrorCode::kInvalidArgument,
                "CAN interface " + ifname_ + ": cannot send frame with id 0x" +
                    hex(frame.id) + (frame.extended ? " (29-bit)" : " (11-bit)") + " and dlc " +
                    std::to_string(frame.dlc) + ": out of range");
  }
  can_frame out{};  // zeroed: bytes past dlc go out as 0, not as stack garbage
  out.can_id = frame.id;
  if (frame.extended) out.can_id |= CAN_EFF_FLAG;
  if (frame.rtr) out.can_id |= CAN_RTR_FLAG;
  if (frame.error) out.can_id = (frame.id & CAN_ERR_MASK) | CAN_ERR_FLAG;
  out.len = frame.dlc;
  if (!frame.rtr) std::copy_n(frame.data.begin(), frame.dlc, out.data);

  for (;;) {
    const ssize_t n = ::write(fd_, &out, sizeof(out));
    if (n == static_cast<ssize_t>(sizeof(out))) return {};
    if (n >= 0) return fail(ErrorCode::kIo, "CAN interface " + ifname_ + ": short write");
    if (errno == EINTR) continue;
    // A full socket send buffer gives EAGAIN, a full interface queue ENOBUFS: both mean
    // "not now", which callers count as a dropped frame.
    if (errno == EAGAIN || errno == EWOULDBLOCK || errno == ENOBUFS) {
      return fail(ErrorCode::kTimeout,
                  "CAN interface " + ifname_ + ": transmit queue full, frame not sent");
    }
    return io_failure(ifname_, "send", errno);
  }
}

Result<std::optional<ReceivedCanFrame>> CanSocket::receive() {
  can_frame in{};
  iovec iov{&in, sizeof(in)};
  alignas(cmsghdr) char control[CMSG_SPACE(sizeof(timespec))];
  msghdr msg{};
  msg.msg_iov = &iov;
  msg.msg_iovlen = 1;
  msg.msg_control = control;
  msg.msg_controllen = sizeof(control);

  ssize_t n = 0;
  for (;;) {
    n = ::recvmsg(fd_, &msg, 0);
    if (n >= 0) break;
    if (errno == EINTR) continue;
    if (errno == EAGAIN || errno == EWOULDBLOCK) return std::optional<ReceivedCanFrame>{};
    return io_failure(ifname_, "receive", errno);
  }
  if (n != static_cast<ssize_t>(sizeof(in))) {
    return fail(ErrorCode::kIo, "CAN interface " + ifname_ + ": received " + std::to_string(n) +
                                    " bytes, not a classic CAN frame");
  }

  ReceivedCanFrame received;
  CanFrame& frame = received.frame;
  frame.error = (in.can_id & CAN_ERR_FLAG) != 0;
  frame.extended = !frame.error && (in.can_id & CAN_EFF_FLAG) != 0;
  frame.rtr = !frame.error && (in.can_id & CAN_RTR_FLAG) != 0;
  frame.id = in.can_id & (frame.error ? CAN_ERR_MASK : frame.extended ? CAN_EFF_MASK : CAN_SFF_MASK);
  frame.dlc = std::min<std::uint8_t>(in.len, CAN_MAX_DLEN);
  if (!frame.rtr) std::copy_n(in.data, frame.dlc, frame.data.begin());

  for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c != nullptr; c = CMSG_NXTHDR(&msg, c)) {
    if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_TIMESTAMPNS) {
      timespec ts{};
      std::memcpy(&ts, CMSG_DATA(c), sizeof(ts));
      received.kernel_time = std::chrono::seconds(ts.tv_sec) + std::chrono::nanoseconds(ts.tv_nsec);
    }
  }
  return received;
}

}  // namespace nav::transport

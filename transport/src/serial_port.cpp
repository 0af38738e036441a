// SPDX-License-Identifier: MIT
#include "nav/transport/serial_port.hpp"

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <utility>

namespace nav::transport {
namespace {

struct BaudConstant {
  int baud;        // [bit/s]
  speed_t speed;   // termios constant
};

// Common rates from NMEA's 4800 to USB-serial adapters' 921600.
constexpr BaudConstant kBauds[] = {
    {4800, B4800},     {9600, B9600},     {19200, B19200},   {38400, B38400},
    {57600, B57600},   {115200, B115200}, {230400, B230400}, {460800, B460800},
    {500000, B500000}, {576000, B576000}, {921600, B921600},
};

std::string bauds_list() {
  std::string s;
  for (const auto& b : kBauds) {
    if (!s.empty()) s += ", ";
    s += std::to_string(b.baud);
  }
  return s;
}

tl::unexpected<Error> os_error(const std::string& what, const std::string& path, int err) {
  const ErrorCode code = err == ENOENT ? ErrorCode::kNotFound : ErrorCode::kIo;
  return fail(code, what + " " + path + ": " + std::generic_category().message(err));
}

}  // namespace

std::vector<int> SerialPort::supported_bauds() {
  std::vector<int> out;
  for (const auto& b : kBauds) out.push_back(b.baud);
  return out;
}

Result<SerialPort> SerialPort::open(const std::string& path, int baud) {
  const auto* it = std::find_if(std::begin(kBauds), std::end(kBauds),
                                [baud](const BaudConstant& b) { return b.baud == baud; });
  if (it == std::end(kBauds)) {
    return fail(ErrorCode::kInvalidArgument, "unsupported baud " + std::to_string(baud) +
                                                 " for " + path + " (supported: " +
                                                 bauds_list() + ")");
  }
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return os_error("cannot open", path, errno);
  // From here the port owns fd, so every early return closes it.
  SerialPort port(fd, path, baud);

  termios tio{};
  if (::tcgetattr(fd, &tio) != 0) {
    const int err = errno;
    return fail(ErrorCode::kIo, "cannot use " + path + " as a serial port: " +
                                    std::generic_category().message(err));
  }
  ::cfmakeraw(&tio);                     // no echo, no line editing, no CR/LF translation
  tio.c_cflag &= ~(CSIZE | PARENB | CSTOPB | CRTSCTS);
  tio.c_cflag |= CS8 | CLOCAL | CREAD;   // 8N1, ignore modem lines, enable receiver
  tio.c_iflag &= ~(IXON | IXOFF | IXANY);
  // VMIN 1 / VTIME 0: with O_NONBLOCK a read without data fails with EAGAIN. (VMIN 0 would
  // make it return 0, indistinguishable from end of file.)
  tio.c_cc[VMIN] = 1;
  tio.c_cc[VTIME] = 0;
  if (::cfsetispeed(&tio, it->speed) != 0 || ::cfsetospeed(&tio, it->speed) != 0) {
    return os_error("cannot set baud " + std::to_string(baud) + " on", path, errno);
  }
  if (::tcsetattr(fd, TCSANOW, &tio) != 0) return os_error("cannot configure", path, errno);
  return port;
}

SerialPort::SerialPort(int fd, std::string path, int baud)
    : fd_(fd), path_(std::move(path)), baud_(baud) {}

SerialPort::SerialPort(SerialPort&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), path_(std::move(other.path_)), baud_(other.baud_) {}

SerialPort& SerialPort::operator=(SerialPort&& other) noexcept {
  if (this != &other) {
    close_fd();
    fd_ = std::exchange(other.fd_, -1);
    path_ = std::move(other.path_);
    baud_ = other.baud_;
  }
  return *this;
}

SerialPort::~SerialPort() { close_fd(); }

void SerialPort::close_fd() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

Result<std::size_t> SerialPort::read_some(std::span<std::uint8_t> buffer) {
  if (buffer.empty()) return std::size_t{0};
  for (;;) {
    const ssize_t n = ::read(fd_, buffer.data(), buffer.size());
    if (n > 0) return static_cast<std::size_t>(n);
    if (n == 0) return fail(ErrorCode::kIo, path_ + ": end of file");
    if (errno == EINTR) continue;
    if (errno == EAGAIN || errno == EWOULDBLOCK) return std::size_t{0};
    // A pty slave reports EIO once its master side is closed: that is a hang-up.
    if (errno == EIO) return fail(ErrorCode::kIo, path_ + ": hang-up (input/output error)");
    return os_error("cannot read", path_, errno);
  }
}

Result<std::size_t> SerialPort::write_some(std::span<const std::uint8_t> bytes) {
  if (bytes.empty()) return std::size_t{0};
  for (;;) {
    const ssize_t n = ::write(fd_, bytes.data(), bytes.size());
    if (n >= 0) return static_cast<std::size_t>(n);
    if (errno == EINTR) continue;
    if (errno == EAGAIN || errno == EWOULDBLOCK) return std::size_t{0};
    if (errno == EIO) return fail(ErrorCode::kIo, path_ + ": hang-up (input/output error)");
    return os_error("cannot write", path_, errno);
  }
}

Result<void> SerialPort::write_all(std::span<const std::uint8_t> bytes,
                                   std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!bytes.empty()) {
    auto written = write_some(bytes);
    if (!written) return tl::unexpected(written.error());
    bytes = bytes.subspan(*written);
    if (bytes.empty()) break;
    if (*written > 0) continue;
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      return fail(ErrorCode::kTimeout, "cannot write " + path_ + ": output blocked for " +
                                           std::to_string(timeout.count()) + " ms");
    }
    pollfd p{fd_, POLLOUT, 0};
    const int r = ::poll(&p, 1, static_cast<int>(left.count()));
    if (r < 0 && errno != EINTR) return os_error("cannot poll", path_, errno);
    if (r > 0 && (p.revents & (POLLHUP | POLLERR | POLLNVAL)) != 0 &&
        (p.revents & POLLOUT) == 0) {
      return fail(ErrorCode::kIo, path_ + ": hang-up while writing");
    }
  }
  return {};
}

}  // namespace nav::transport

// SPDX-License-Identifier: MIT
#include "nav/transport/serial_port.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <libserial/SerialPort.h>

#include <algorithm>
#include <cerrno>
#include <exception>
#include <utility>

#include "nav/common/bauds.hpp"

// LibSerial 1.0.0 (Debian 12's libserial-dev) on ttys and pty slaves, as used here:
// - Open() opens O_RDWR|O_NOCTTY|O_NONBLOCK (not close-on-exec), sets TIOCEXCL, saves the
//   settings it finds, applies its raw defaults (c_iflag IGNBRK only, c_oflag 0, c_lflag 0,
//   CLOCAL|CREAD, 8N1, 115200, VMIN 1, VTIME 0) and flushes both queues: bytes that reached
//   a pty before the port was opened are dropped, as on a real line.
// - When open() fails it reports the errno of its own close(-1), "Bad file descriptor",
//   whatever the cause; when TIOCEXCL fails (not a tty) it throws with the descriptor still
//   open.
// - Close(), also run by its destructor, restores the saved settings and throws when that
//   fails: on a pty slave whose master has closed (hang-up) or a descriptor that is no tty.
//   From the noexcept destructor that would be std::terminate; see release_line().
// - Every baud in kBauds has a BaudRate constant, and a pty takes any of them (it stores the
//   rate and does not pace bytes).
namespace nav::transport {
namespace {

struct BaudConstant {
  int baud;                      // [bit/s]
  LibSerial::BaudRate constant;  // LibSerial's name for it
};

// LibSerial's setting of each of the project's bauds (nav/common/bauds.hpp), in its order.
constexpr BaudConstant kBauds[] = {
    {300, LibSerial::BaudRate::BAUD_300},       {600, LibSerial::BaudRate::BAUD_600},
    {1200, LibSerial::BaudRate::BAUD_1200},     {2400, LibSerial::BaudRate::BAUD_2400},
    {4800, LibSerial::BaudRate::BAUD_4800},     {9600, LibSerial::BaudRate::BAUD_9600},
    {19200, LibSerial::BaudRate::BAUD_19200},   {38400, LibSerial::BaudRate::BAUD_38400},
    {57600, LibSerial::BaudRate::BAUD_57600},   {115200, LibSerial::BaudRate::BAUD_115200},
    {230400, LibSerial::BaudRate::BAUD_230400}, {460800, LibSerial::BaudRate::BAUD_460800},
    {500000, LibSerial::BaudRate::BAUD_500000}, {576000, LibSerial::BaudRate::BAUD_576000},
    {921600, LibSerial::BaudRate::BAUD_921600},
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

/// Closes a LibSerial port that may be open, without throwing. Close() restores the settings
/// saved at Open(); when it cannot (hang-up, no tty) the descriptor stays open and the
/// object's destructor would call Close() again and terminate the process. Such a port's
/// descriptor is closed here and the object itself kept, unreachable by anyone else, until
/// the process exits (a few bytes, at most once per port).
void release_line(std::unique_ptr<LibSerial::SerialPort> line) noexcept {
  if (!line || !line->IsOpen()) return;
  try {
    line->Close();
    return;
  } catch (const std::exception&) {
    // Settings not restored: the line is gone or was never a tty.
  }
  try {
    ::close(line->GetFileDescriptor());
  } catch (const std::exception&) {
    // Not open after all: nothing to close.
  }
  static auto* const kept = new std::vector<LibSerial::SerialPort*>();
  try {
    kept->push_back(line.get());
    (void)line.release();
  } catch (const std::exception&) {
    // No memory to keep it: let its destructor run (it only throws while still open).
  }
}

/// Why open(2) fails on `path`: LibSerial's message does not say (see above).
tl::unexpected<Error> open_error(const std::string& path, const std::exception& e) {
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return os_error("cannot open", path, errno);
  ::close(fd);  // opens now: report what LibSerial said
  return fail(ErrorCode::kIo, "cannot open " + path + ": " + e.what());
}

}  // namespace

static_assert(std::size(kBauds) == kSerialBauds.size());
constexpr bool same_bauds() {
  for (std::size_t i = 0; i < kSerialBauds.size(); ++i) {
    if (kBauds[i].baud != kSerialBauds[i]) return false;
  }
  return true;
}
static_assert(same_bauds(), "kBauds lists kSerialBauds in their order");

std::vector<int> SerialPort::supported_bauds() {
  return std::vector<int>(kSerialBauds.begin(), kSerialBauds.end());
}

Result<SerialPort> SerialPort::open(const std::string& path, int baud) {
  const auto* it = std::find_if(std::begin(kBauds), std::end(kBauds),
                                [baud](const BaudConstant& b) { return b.baud == baud; });
  if (it == std::end(kBauds)) {
    return fail(ErrorCode::kInvalidArgument, "unsupported baud " + std::to_string(baud) +
                                                 " for " + path + " (supported: " +
                                                 bauds_list() + ")");
  }
  auto line = std::make_unique<LibSerial::SerialPort>();
  try {
    line->Open(path);
  } catch (const std::exception& e) {
    if (!line->IsOpen()) return open_error(path, e);
    release_line(std::move(line));
    return fail(ErrorCode::kIo, "cannot use " + path + " as a serial port: " + e.what());
  }
  const int fd = line->GetFileDescriptor();
  // From here the port owns the line, so every early return closes it.
  SerialPort port(std::move(line), path, baud);
  try {
    port.line_->SetBaudRate(it->constant);
  } catch (const std::exception& e) {
    return fail(ErrorCode::kIo,
                "cannot set baud " + std::to_string(baud) + " on " + path + ": " + e.what());
  }
  try {
    port.line_->SetCharacterSize(LibSerial::CharacterSize::CHAR_SIZE_8);
    port.line_->SetParity(LibSerial::Parity::PARITY_NONE);
    port.line_->SetStopBits(LibSerial::StopBits::STOP_BITS_1);
    port.line_->SetFlowControl(LibSerial::FlowControl::FLOW_CONTROL_NONE);
    // VMIN 1 / VTIME 0: with O_NONBLOCK a read without data fails with EAGAIN. (VMIN 0 would
    // make it return 0, indistinguishable from end of file.)
    port.line_->SetVMin(1);
    port.line_->SetVTime(0);
  } catch (const std::exception& e) {
    return fail(ErrorCode::kIo, "cannot configure " + path + ": " + e.what());
  }
  // Not exclusive: TIOCEXCL outlives the process on a pty the bench keeps open, so a DUT
  // restarted on it (a restart fault) could not open it again without CAP_SYS_ADMIN. Not
  // inherited by a child (the bench starts the DUT). Non-blocking whatever LibSerial does.
  const int flags = ::fcntl(fd, F_GETFL);
  if (::ioctl(fd, TIOCNXCL) != 0 || ::fcntl(fd, F_SETFD, FD_CLOEXEC) != 0 || flags < 0 ||
      ::fcntl(fd, F_SETFL, flags | O_NONBLOCK) != 0) {
    return os_error("cannot configure", path, errno);
  }
  return port;
}

SerialPort::SerialPort(std::unique_ptr<LibSerial::SerialPort> line, std::string path, int baud)
    : line_(std::move(line)), fd_(line_->GetFileDescriptor()), path_(std::move(path)),
      baud_(baud) {}

SerialPort::SerialPort(SerialPort&& other) noexcept
    : line_(std::move(other.line_)),
      fd_(std::exchange(other.fd_, -1)),
      path_(std::move(other.path_)),
      baud_(other.baud_) {}

SerialPort& SerialPort::operator=(SerialPort&& other) noexcept {
  if (this != &other) {
    close_line();
    line_ = std::move(other.line_);
    fd_ = std::exchange(other.fd_, -1);
    path_ = std::move(other.path_);
    baud_ = other.baud_;
  }
  return *this;
}

SerialPort::~SerialPort() { close_line(); }

void SerialPort::close_line() {
  release_line(std::move(line_));
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

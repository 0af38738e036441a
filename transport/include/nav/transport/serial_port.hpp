// SPDX-License-Identifier: MIT
// A serial line: a real tty (/dev/ttyUSB0) or the slave side of a pty (/dev/pts/N), opened
// and configured raw 8N1 at a given baud by LibSerial (LibSerial::SerialPort), then used
// through its file descriptor, non-blocking. The port owns the LibSerial port (RAII,
// move-only); callers wait on fd() (poll(), or an Asio stream_descriptor) and then call
// read_some()/write_some(), which never block.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "nav/common/result.hpp"

namespace LibSerial {
class SerialPort;
}  // namespace LibSerial

namespace nav::transport {

/// An open serial line (raw, 8N1, no flow control, receiver on, modem lines ignored).
class SerialPort {
 public:
  /// Opens `path` with LibSerial (O_RDWR|O_NOCTTY|O_NONBLOCK; raw: no echo, no line editing,
  /// no CR/LF translation, breaks ignored; both queues flushed) and sets `baud` [bit/s], 8
  /// data bits, no parity, 1 stop bit, no flow control, CLOCAL|CREAD, VMIN 1 / VTIME 0. The
  /// descriptor is then made close-on-exec and not exclusive (see serial_port.cpp). Errors
  /// are one line naming the path, e.g. "cannot open /dev/ttyUSB9: No such file or
  /// directory", or naming the baud when it is not one of supported_bauds().
  static Result<SerialPort> open(const std::string& path, int baud);

  /// Bauds open() accepts, ascending [bit/s].
  static std::vector<int> supported_bauds();

  SerialPort(SerialPort&& other) noexcept;
  SerialPort& operator=(SerialPort&& other) noexcept;
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;
  ~SerialPort();

  /// Reads what is available without blocking: the number of bytes read, 0 when nothing is
  /// available (EAGAIN). End of file and hang-up (EIO on a pty slave whose master closed)
  /// are errors, as is any other failed read.
  Result<std::size_t> read_some(std::span<std::uint8_t> buffer);

  /// Writes what the line accepts without blocking: the number of bytes written, 0 when the
  /// output buffer is full (EAGAIN). A hang-up (EIO) or other failure is an error.
  Result<std::size_t> write_some(std::span<const std::uint8_t> bytes);

  /// Writes every byte, waiting with poll() while the output buffer is full, at most
  /// `timeout` in total (then a kTimeout error naming the path). For callers that may
  /// block; navd's event loop uses write_some() instead.
  Result<void> write_all(std::span<const std::uint8_t> bytes,
                         std::chrono::milliseconds timeout = std::chrono::milliseconds(1000));

  /// The file descriptor, for poll() or an Asio descriptor; -1 after a move.
  int fd() const { return fd_; }
  /// The path it was opened with.
  const std::string& path() const { return path_; }
  /// The configured line rate [bit/s].
  int baud() const { return baud_; }

 private:
  SerialPort(std::unique_ptr<LibSerial::SerialPort> line, std::string path, int baud);
  void close_line();

  std::unique_ptr<LibSerial::SerialPort> line_;  ///< owns the descriptor; null after a move
  int fd_ = -1;                                  ///< line_'s descriptor
  std::string path_;
  int baud_ = 0;
};

}  // namespace nav::transport

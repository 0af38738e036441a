// SPDX-License-Identifier: MIT
// SerialPort (opened and configured by LibSerial) on the slave side of a pty: the line
// settings it leaves, bytes both ways without blocking, hang-up, and its errors. A pty
// stores the baud (it does not pace bytes), so tcgetattr shows what open() set.
#include <fcntl.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

#include <array>
#include <cstdint>
#include <span>
#include <string>

#include <gtest/gtest.h>

#include "nav/transport/pty.hpp"
#include "nav/transport/serial_port.hpp"

namespace nav::transport {
namespace {

termios settings_of(int fd) {
  termios tio{};
  EXPECT_EQ(::tcgetattr(fd, &tio), 0);
  return tio;
}

std::span<const std::uint8_t> bytes_of(const std::string& s) {
  return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

TEST(SerialPort, OpensAPtySlaveRaw8N1AtTheBaudNonBlocking) {
  const struct {
    int baud;
    speed_t speed;
  } cases[] = {{4800, B4800}, {9600, B9600}, {115200, B115200}, {500000, B500000},
               {921600, B921600}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.baud);
    auto pty = Pty::open();
    ASSERT_TRUE(pty) << pty.error().detail;
    auto port = SerialPort::open(pty->slave_path(), c.baud);
    ASSERT_TRUE(port) << port.error().detail;
    EXPECT_EQ(port->baud(), c.baud);
    EXPECT_EQ(port->path(), pty->slave_path());
    const termios tio = settings_of(port->fd());
    EXPECT_EQ(::cfgetispeed(&tio), c.speed);
    EXPECT_EQ(::cfgetospeed(&tio), c.speed);
    EXPECT_EQ(tio.c_cflag & CSIZE, static_cast<tcflag_t>(CS8));
    EXPECT_EQ(tio.c_cflag & (PARENB | CSTOPB | CRTSCTS), 0u);
    EXPECT_EQ(tio.c_cflag & (CLOCAL | CREAD), static_cast<tcflag_t>(CLOCAL | CREAD));
    EXPECT_EQ(tio.c_iflag & (IXON | IXOFF | IXANY | ICRNL | INLCR | IGNCR | ISTRIP), 0u);
    EXPECT_EQ(tio.c_oflag & OPOST, 0u);
    EXPECT_EQ(tio.c_lflag & (ICANON | ECHO | ISIG | IEXTEN), 0u);
    EXPECT_EQ(tio.c_cc[VMIN], 1);
    EXPECT_EQ(tio.c_cc[VTIME], 0);
    EXPECT_NE(::fcntl(port->fd(), F_GETFL) & O_NONBLOCK, 0);
    EXPECT_NE(::fcntl(port->fd(), F_GETFD) & FD_CLOEXEC, 0);
    int exclusive = -1;
    ASSERT_EQ(::ioctl(port->fd(), TIOCGEXCL, &exclusive), 0);
    EXPECT_EQ(exclusive, 0);  // a restarted DUT can open the same pty again
  }
}

TEST(SerialPort, MovesBytesBothWaysWithoutBlocking) {
  auto pty = Pty::open();
  ASSERT_TRUE(pty) << pty.error().detail;
  auto port = SerialPort::open(pty->slave_path(), 115200);
  ASSERT_TRUE(port) << port.error().detail;
  std::array<std::uint8_t, 64> buf{};
  auto none = port->read_some(buf);
  ASSERT_TRUE(none) << none.error().detail;
  EXPECT_EQ(*none, 0u);  // EAGAIN, not end of file

  const std::string in = "$GPGGA,\r\n\x00\xFF";
  ASSERT_EQ(::write(pty->master(), in.data(), in.size()), static_cast<ssize_t>(in.size()));
  pty->flush_to_slave();
  auto n = port->read_some(buf);
  ASSERT_TRUE(n) << n.error().detail;
  EXPECT_EQ(std::string(reinterpret_cast<const char*>(buf.data()), *n), in);  // untranslated

  const std::string out = "$PNVBSOL\r\n";
  ASSERT_TRUE(port->write_all(bytes_of(out)));
  std::array<char, 64> got{};
  const ssize_t m = ::read(pty->master(), got.data(), got.size());
  EXPECT_EQ(std::string(got.data(), m > 0 ? static_cast<std::size_t>(m) : 0u), out);
}

TEST(SerialPort, DropsBytesQueuedBeforeItOpened) {
  // LibSerial flushes both queues at open, as a real line has nothing from before either.
  auto pty = Pty::open();
  ASSERT_TRUE(pty) << pty.error().detail;
  ASSERT_EQ(::write(pty->master(), "early", 5), 5);
  pty->flush_to_slave();
  auto port = SerialPort::open(pty->slave_path(), 9600);
  ASSERT_TRUE(port) << port.error().detail;
  std::array<std::uint8_t, 16> buf{};
  auto n = port->read_some(buf);
  ASSERT_TRUE(n) << n.error().detail;
  EXPECT_EQ(*n, 0u);
}

TEST(SerialPort, ClosingRestoresTheSettingsItFound) {
  // LibSerial puts back what the line had before open(): here the bench's raw pty settings.
  auto pty = Pty::open();
  ASSERT_TRUE(pty) << pty.error().detail;
  const int probe = ::open(pty->slave_path().c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC);
  ASSERT_GE(probe, 0);
  const termios before = settings_of(probe);
  {
    auto port = SerialPort::open(pty->slave_path(), 9600);
    ASSERT_TRUE(port) << port.error().detail;
    const termios open_tio = settings_of(probe);
    EXPECT_EQ(::cfgetospeed(&open_tio), static_cast<speed_t>(B9600));
  }
  const termios after = settings_of(probe);
  EXPECT_EQ(::cfgetospeed(&after), ::cfgetospeed(&before));
  EXPECT_EQ(after.c_cflag, before.c_cflag);
  EXPECT_EQ(after.c_iflag, before.c_iflag);
  EXPECT_EQ(after.c_lflag, before.c_lflag);
  ::close(probe);
}

TEST(SerialPort, HangUpIsAnErrorAndClosingAfterItIsSafe) {
  auto pty = Pty::open();
  ASSERT_TRUE(pty) << pty.error().detail;
  auto port = SerialPort::open(pty->slave_path(), 115200);
  ASSERT_TRUE(port) << port.error().detail;
  pty = Pty::open();  // closes the first pair: its slave hangs up
  ASSERT_TRUE(pty) << pty.error().detail;
  std::array<std::uint8_t, 16> buf{};
  EXPECT_FALSE(port->read_some(buf));
  EXPECT_FALSE(port->write_some(bytes_of("x")));
  // The settings cannot be restored on a hung-up line: closing must neither throw nor abort.
  { SerialPort gone = std::move(*port); }
  EXPECT_EQ(port->fd(), -1);
}

TEST(SerialPort, ErrorsAreOneLineNamingThePath) {
  auto missing = SerialPort::open("/dev/ttyNAVBENCH9", 9600);
  ASSERT_FALSE(missing);
  EXPECT_EQ(missing.error().code, ErrorCode::kNotFound);
  EXPECT_EQ(missing.error().detail, "cannot open /dev/ttyNAVBENCH9: No such file or directory");

  auto not_a_tty = SerialPort::open("/dev/null", 9600);
  ASSERT_FALSE(not_a_tty);
  EXPECT_EQ(not_a_tty.error().code, ErrorCode::kIo);
  EXPECT_EQ(not_a_tty.error().detail,
            "cannot use /dev/null as a serial port: Inappropriate ioctl for device");

  auto pty = Pty::open();
  ASSERT_TRUE(pty) << pty.error().detail;
  auto bad_baud = SerialPort::open(pty->slave_path(), 1234);
  ASSERT_FALSE(bad_baud);
  EXPECT_EQ(bad_baud.error().code, ErrorCode::kInvalidArgument);
  EXPECT_EQ(bad_baud.error().detail,
            "unsupported baud 1234 for " + pty->slave_path() +
                " (supported: 300, 600, 1200, 2400, 4800, 9600, 19200, 38400, 57600, 115200, 230400, 460800, 500000, "
                "576000, 921600)");
}

}  // namespace
}  // namespace nav::transport

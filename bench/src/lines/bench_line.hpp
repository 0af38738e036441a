// SPDX-License-Identifier: MIT
// The bench's end of one line to the DUT: a pty (the DUT opens its slave path as it would
// /dev/ttyUSB0), a real serial port (a cable to the DUT's own port), or a CAN interface. One
// type for a run (run/) and for `navbench replay` (capture/). Private to nav_bench.
#pragma once

#include <string>
#include <variant>

#include "nav/common/result.hpp"
#include "nav/transport/can_socket.hpp"
#include "nav/transport/pty.hpp"
#include "nav/transport/serial_port.hpp"

namespace nav::bench {

class BenchLine {
 public:
  /// "pty" for a new pty pair, else a serial device path opened at baud (raw 8N1).
  static Result<BenchLine> open_serial(const std::string& port, int baud);
  /// A raw CAN socket of the line's own on iface.
  static Result<BenchLine> open_can(const std::string& iface,
                                    const transport::CanSocketOptions& options);
  /// A device on a run's CAN bus: the run sends every bus frame through one shared socket,
  /// so this line has no descriptor of its own; path() is the interface.
  static BenchLine on_bus(const std::string& iface);

  /// What the bench writes to and reads the DUT's bytes from; -1 for a device on a bus.
  int fd() const;
  /// What "{port:NAME}" stands for: the pty's slave path, the device path, the interface.
  std::string path() const;
  bool is_pty() const { return std::holds_alternative<transport::Pty>(end_); }
  /// The line's own CAN socket, or null.
  transport::CanSocket* can() { return std::get_if<transport::CanSocket>(&end_); }
  /// Makes what was written readable by the DUT before anything written later on another
  /// line (lockstep orders bytes across lines so; see Pty::flush_to_slave). A real line needs
  /// nothing.
  void flush() const;
  /// A pty drops what the DUT has not read (it was off: on a real line those bytes reached a
  /// dead UART and were lost). A real line or a bus needs nothing.
  void discard_unread() const;

 private:
  explicit BenchLine(std::variant<std::string, transport::Pty, transport::SerialPort,
                                  transport::CanSocket> end)
      : end_(std::move(end)) {}
  /// std::string: a device on a run's bus, by its interface name.
  std::variant<std::string, transport::Pty, transport::SerialPort, transport::CanSocket> end_;
};

}  // namespace nav::bench

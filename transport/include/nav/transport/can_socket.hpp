// SPDX-License-Identifier: MIT
// A SocketCAN raw socket (CAN_RAW) bound to one interface: a real controller (can0) or a
// virtual bus (vcan0). Classic CAN 2.0 frames, 11- and 29-bit identifiers; CAN FD is not
// enabled. The socket owns its file descriptor (RAII, move-only) and never blocks: callers
// poll() on fd() and then call receive() until it has nothing, or send() (which fails with
// kTimeout when the transmit queue is full, so that callers can count dropped frames).
//
// Loopback, as the kernel does it: a frame sent on a socket reaches every other CAN_RAW
// socket on the same interface of this host (`loopback`, kernel default on), but not the
// sending socket itself unless `receive_own_frames` is set (kernel default off).
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "nav/common/result.hpp"

namespace nav::transport {

/// A classic CAN 2.0 frame (ISO 11898-1), as on the wire minus bit timing and CRC.
struct CanFrame {
  /// Largest 11-bit (base) identifier.
  static constexpr std::uint32_t kMaxStandardId = 0x7FF;
  /// Largest 29-bit (extended) identifier.
  static constexpr std::uint32_t kMaxExtendedId = 0x1FFFFFFF;

  std::uint32_t id = 0;       ///< identifier: 0..0x7FF, or 0..0x1FFFFFFF when `extended`
  bool extended = false;      ///< 29-bit identifier (CAN 2.0B extended frame format)
  bool rtr = false;           ///< remote transmission request: carries no data, only `dlc`
  std::uint8_t dlc = 0;       ///< data length code 0..8 [bytes] (requested length for RTR)
  /// A SocketCAN error frame (CAN_ERR_FLAG): `id` holds its error classes (CAN_ERR_*), the
  /// data its details (linux/can/error.h). Sent on a virtual bus to play a controller's
  /// reports; received only with CanSocketOptions::error_classes.
  bool error = false;
  std::array<std::uint8_t, 8> data{};  ///< payload; bytes from `dlc` on are not sent

  /// Same identifier, format, RTR flag, DLC and the first `dlc` data bytes (none for RTR).
  friend bool operator==(const CanFrame& a, const CanFrame& b);
};

/// A frame as received, with the kernel's receive time when it provided one.
struct ReceivedCanFrame {
  CanFrame frame;  ///< the frame
  /// When the kernel received the frame (SO_TIMESTAMPNS) [ns since the Unix epoch,
  /// CLOCK_REALTIME]; empty if the kernel did not stamp it.
  std::optional<std::chrono::nanoseconds> kernel_time;
};

/// Socket options; the defaults are the kernel's.
struct CanSocketOptions {
  /// Deliver this socket's own sent frames back to it (CAN_RAW_RECV_OWN_MSGS).
  bool receive_own_frames = false;
  /// Deliver sent frames to the other sockets on this interface of this host
  /// (CAN_RAW_LOOPBACK). Off, two programs on one vcan0 no longer hear each other.
  bool loopback = true;
  /// Ask the kernel for receive timestamps (SO_TIMESTAMPNS).
  bool timestamps = true;
  /// Error classes to receive as error frames (CAN_RAW_ERR_FILTER): 0, the kernel's
  /// default, none; CAN_ERR_MASK (0x1FFFFFFF) all.
  std::uint32_t error_classes = 0;
};

/// An open CAN_RAW socket bound to one CAN interface.
class CanSocket {
 public:
  /// Opens a non-blocking CAN_RAW socket, applies `options` and binds it to `ifname`.
  /// Errors are one line naming the interface, e.g. "cannot open CAN interface vcan0: No
  /// such device" (kNotFound when the interface does not exist; kIo when, e.g., the kernel
  /// has no CAN: "Address family not supported by protocol"; kInvalidArgument for a name
  /// that cannot be an interface's).
  static Result<CanSocket> open(const std::string& ifname, const CanSocketOptions& options = {});

  CanSocket(CanSocket&& other) noexcept;
  CanSocket& operator=(CanSocket&& other) noexcept;
  CanSocket(const CanSocket&) = delete;
  CanSocket& operator=(const CanSocket&) = delete;
  ~CanSocket();

  /// Queues one frame for transmission without blocking. Errors: kInvalidArgument for a
  /// frame that cannot exist (identifier out of range for its format, dlc > 8); kTimeout
  /// when the interface's transmit queue is full right now (EAGAIN/ENOBUFS): the frame was
  /// not sent, poll fd() for POLLOUT or count it as dropped; kIo for any other failure
  /// (e.g. "CAN interface vcan0: cannot send: Network is down").
  Result<void> send(const CanFrame& frame);

  /// Takes the next received frame without blocking: empty when none is waiting (EAGAIN).
  /// A failed read (e.g. the interface went down) is a kIo error.
  Result<std::optional<ReceivedCanFrame>> receive();

  /// The file descriptor, for poll(); -1 after a move.
  int fd() const { return fd_; }
  /// The interface name it was opened with.
  const std::string& ifname() const { return ifname_; }

 private:
  CanSocket(int fd, std::string ifname);
  void close_fd();

  int fd_ = -1;
  std::string ifname_;
};

}  // namespace nav::transport

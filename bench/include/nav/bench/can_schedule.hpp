// SPDX-License-Identifier: MIT
// When each frame of each CAN device goes on a shared bus.
//
// Unlike serial devices, every CAN device of a bus shares one medium: a frame occupies the
// bus for its bit length, and when the bus falls idle the pending frame with the dominant
// (numerically lowest) arbitration field wins; a frame on the bus is never preempted. The
// bit length of a classic data frame with n data bytes is its worst case with bit stuffing
// (Davis, Burns, Bril, Lukkien, "Controller Area Network (CAN) schedulability analysis:
// refuted, revisited and revised", Real-Time Systems 35, 2007, eq. (1)):
//
//   C = g + 8 n + 13 + floor((g + 8 n - 1) / 4)   bit times                          (C1)
//
// g = 34 for an 11-bit identifier, 54 for a 29-bit one: the bits exposed to stuffing (SOF to
// CRC); 13 = CRC delimiter 1, ACK 2, EOF 7 and the 3-bit interframe space, never stuffed.
// E.g. 8 data bytes: 135 bits (standard), 160 bits (extended); at 250 kbit/s 540 / 640 us.
//
// Arbitration order (ISO 11898-1): the identifier's bits from the most significant one, then
// for a standard frame RTR and IDE (dominant 0), for an extended frame SRR and IDE (both
// recessive 1), the 18 extension bits, RTR. So a standard frame beats an extended frame with
// the same 11-bit base, a data frame beats a remote frame of the same identifier, and frames
// with the same identifier keep their ready order (a device's fast-packet frames stay in
// sequence).
#pragma once

#include <cstdint>
#include <vector>

#include "nav/common/time.hpp"

namespace nav::bench {

/// One frame a device wants to send.
struct CanFrameRequest {
  Duration ready{};          ///< scenario time the frame is queued for transmission
  std::uint32_t id = 0;      ///< 11- or 29-bit identifier
  bool extended = false;     ///< 29-bit identifier
  bool remote = false;       ///< remote frame (RTR): no data bits on the bus
  std::uint8_t dlc = 8;      ///< data length code, 0..8
};

/// A frame with its place on the bus.
struct CanFrameSlot {
  Duration start{};  ///< first bit (SOF) on the bus
  Duration end{};    ///< end of its interframe space: the bus is free again
  std::uint32_t bits = 0;  ///< bit times occupied, (C1)
};

/// Bit times a frame occupies, worst-case stuffing and interframe space included (C1).
std::uint32_t can_frame_bits(bool extended, bool remote, std::uint8_t dlc);

/// Arbitration key: the lower key wins the bus (see the file comment).
std::uint64_t can_arbitration_key(std::uint32_t id, bool extended, bool remote);

/// Schedules frames on one bus of `bitrate` [bit/s]; result[i] is the slot of frames[i].
/// frames may come in any order; a frame never starts before its ready time.
std::vector<CanFrameSlot> schedule_can_bus(const std::vector<CanFrameRequest>& frames,
                                           double bitrate);

/// Fraction of [0, duration) the bus carries frames [-] (slots are clipped to the window).
double can_bus_load(const std::vector<CanFrameSlot>& slots, Duration duration);

}  // namespace nav::bench

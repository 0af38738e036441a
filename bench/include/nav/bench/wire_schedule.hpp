// SPDX-License-Identifier: MIT
// When each byte of each device's stream goes on the wire.
//
// A serial line carries one byte at a time: 10 bit times per byte (8N1). Each device has its
// own line, so its messages are serialised: a message starts at its scheduled send time or
// when the previous one has left, whichever is later. Bytes are paced by splitting a message
// into chunks of at most `chunk_period` of line time, each written at its own wire time.
#pragma once

#include <cstdint>
#include <vector>

#include "nav/common/time.hpp"
#include "nav/emulators/device.hpp"

namespace nav::bench {

/// One device stream to schedule.
struct StreamInput {
  const std::vector<emulators::WireMessage>* messages;
  int baud;  ///< [bit/s], 8N1
};

/// One message with its place on the wire.
struct ScheduledMessage {
  std::uint32_t device = 0;  ///< index into the StreamInput list
  std::uint32_t index = 0;   ///< index into that device's messages
  Duration start{};          ///< first byte on the wire (scenario time)
  Duration end{};            ///< last byte has left (scenario time)
};

/// A run of bytes of one message written at once.
struct Chunk {
  Duration t{};              ///< wire time of its first byte (scenario time)
  std::uint32_t message = 0; ///< index into WireSchedule::messages
  std::uint32_t offset = 0;  ///< first byte within the message
  std::uint32_t length = 0;  ///< bytes
};

struct WireSchedule {
  std::vector<ScheduledMessage> messages;  ///< ordered by start (ties: device order)
  std::vector<Chunk> chunks;               ///< ordered by t
};

/// Line time of n bytes at a baud rate, 8N1 [ns].
Duration byte_time(std::size_t n, int baud);

/// Builds the schedule of every stream.
WireSchedule build_schedule(const std::vector<StreamInput>& streams, Duration chunk_period);

}  // namespace nav::bench

// SPDX-License-Identifier: MIT
// MicroStrain 3DM-GX3-25 0xCB reply codec (protocols.md section 1a).
//
// Reply layout (43 bytes, all multi-byte values big-endian):
//   0       0xCB (echoed command byte; the only sync the protocol has)
//   1..12   accel x, y, z      IEEE-754 f32 [g]
//   13..24  angular rate x,y,z IEEE-754 f32 [rad/s]
//   25..36  mag x, y, z        IEEE-754 f32 [G]
//   37..40  timer              uint32 [1/62500 s]
//   41..42  checksum           uint16 = sum of bytes 0..40 mod 65536
#include "nav/protocols/microstrain_gx3.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <initializer_list>
#include <string>

namespace nav::protocols::gx3 {
namespace {

constexpr std::size_t kChecksumOffset = kAccelRateMagLength - 2;  ///< [bytes]

void put_u32_be(Bytes& out, std::uint32_t v) {
  out.push_back(static_cast<std::uint8_t>(v >> 24));
  out.push_back(static_cast<std::uint8_t>(v >> 16));
  out.push_back(static_cast<std::uint8_t>(v >> 8));
  out.push_back(static_cast<std::uint8_t>(v));
}

std::uint32_t get_u32_be(ByteSpan b, std::size_t offset) {
  return (static_cast<std::uint32_t>(b[offset]) << 24) |
         (static_cast<std::uint32_t>(b[offset + 1]) << 16) |
         (static_cast<std::uint32_t>(b[offset + 2]) << 8) |
         static_cast<std::uint32_t>(b[offset + 3]);
}

std::uint16_t get_u16_be(ByteSpan b, std::size_t offset) {
  return static_cast<std::uint16_t>((b[offset] << 8) | b[offset + 1]);
}

float get_f32_be(ByteSpan b, std::size_t offset) {
  return std::bit_cast<float>(get_u32_be(b, offset));
}

/// "0x0DEA": four upper-case hex digits, as protocols.md prints checksums.
std::string hex16(std::uint16_t v) {
  static constexpr char kDigits[] = "0123456789ABCDEF";
  std::string s = "0x";
  for (int shift = 12; shift >= 0; shift -= 4) s.push_back(kDigits[(v >> shift) & 0xF]);
  return s;
}

}  // namespace

std::uint16_t checksum(ByteSpan bytes) {
  std::uint32_t sum = 0;
  for (const std::uint8_t b : bytes) sum += b;
  return static_cast<std::uint16_t>(sum & 0xFFFFu);
}

Bytes encode(const AccelRateMag& m) {
  Bytes out;
  out.reserve(kAccelRateMagLength);
  out.push_back(kCmdAccelRateMag);
  for (const auto* vec : {&m.accel_g, &m.rate_radps, &m.mag_gauss}) {
    for (const float v : *vec) put_u32_be(out, std::bit_cast<std::uint32_t>(v));
  }
  put_u32_be(out, m.timer_ticks);
  const std::uint16_t sum = checksum(out);
  out.push_back(static_cast<std::uint8_t>(sum >> 8));
  out.push_back(static_cast<std::uint8_t>(sum));
  return out;
}

ParseResult<AccelRateMag> parse(ByteSpan buffer) {
  ParseResult<AccelRateMag> r;
  if (buffer.empty()) return r;  // kNeedMore

  if (buffer[0] != kCmdAccelRateMag) {
    // No sync byte: skip everything up to the next 0xCB (or the whole buffer).
    const auto next = std::find(buffer.begin() + 1, buffer.end(), kCmdAccelRateMag);
    r.status = ParseStatus::kMalformed;
    r.consumed = static_cast<std::size_t>(next - buffer.begin());
    r.error = "no 0xCB sync byte: skipped " + std::to_string(r.consumed) + " byte(s) to " +
              (next == buffer.end() ? std::string("the end of the buffer")
                                    : std::string("the next 0xCB"));
    return r;
  }
  if (buffer.size() < kAccelRateMagLength) return r;  // kNeedMore

  const ByteSpan frame = buffer.first(kAccelRateMagLength);
  const std::uint16_t received = get_u16_be(frame, kChecksumOffset);
  const std::uint16_t computed = checksum(frame.first(kChecksumOffset));
  if (received != computed) {
    // The 0xCB may have been a data byte of another reply: drop only it and hunt again.
    r.status = ParseStatus::kMalformed;
    r.consumed = 1;
    r.error = "checksum " + hex16(received) + " != computed " + hex16(computed);
    return r;
  }

  AccelRateMag m;
  std::size_t offset = 1;
  for (auto* vec : {&m.accel_g, &m.rate_radps, &m.mag_gauss}) {
    for (float& v : *vec) {
      v = get_f32_be(frame, offset);
      offset += 4;
    }
  }
  m.timer_ticks = get_u32_be(frame, offset);

  r.status = ParseStatus::kComplete;
  r.consumed = kAccelRateMagLength;
  r.message = m;
  return r;
}

// --- 0xCE, 0xC4 reply and the host commands -------------------------------------------------
//
// 0xCE reply (19 bytes): 0 0xCE; 1..4 roll, 5..8 pitch, 9..12 yaw (f32 [rad]); 13..16 timer;
//                        17..18 checksum of bytes 0..16.
// 0xC4 reply (8 bytes):  0 0xC4; 1 echoed <cmd>; 2..5 timer; 6..7 checksum of bytes 0..5.
//                        The timer position is UNCONFIRMED (protocols.md infers it from the
//                        length 8); the echo at offset 1 is what the ROS driver checks.
// Host commands:         C4 C1 29 <cmd> (set continuous), FA 75 B4 (stop; the device sends
//                        no reply).

namespace {

/// "0xCE": two upper-case hex digits.
std::string hex8(std::uint8_t v) {
  static constexpr char kDigits[] = "0123456789ABCDEF";
  return std::string{"0x"} + kDigits[v >> 4] + kDigits[v & 0xF];
}

/// Appends the 16-bit checksum of everything in `out` so far, big-endian.
void append_checksum(Bytes& out) {
  const std::uint16_t sum = checksum(out);
  out.push_back(static_cast<std::uint8_t>(sum >> 8));
  out.push_back(static_cast<std::uint8_t>(sum));
}

/// Malformed result skipping to the next byte of `syncs` after the first (or to the end).
template <typename Message>
ParseResult<Message> skip_to_sync(ByteSpan buffer, std::initializer_list<std::uint8_t> syncs,
                                  const std::string& what) {
  const auto next = std::find_first_of(buffer.begin() + 1, buffer.end(), syncs.begin(),
                                       syncs.end());
  ParseResult<Message> r;
  r.status = ParseStatus::kMalformed;
  r.consumed = static_cast<std::size_t>(next - buffer.begin());
  r.error = "no " + what + " sync byte: skipped " + std::to_string(r.consumed) + " byte(s) to " +
            (next == buffer.end() ? std::string("the end of the buffer")
                                  : std::string("the next ") + what);
  return r;
}

/// Fixed-length checksummed reply starting with `command`: the frame, or a non-complete
/// result (need-more, or malformed with the same rules as parse()).
template <typename Message>
ParseResult<Message> check_reply(ByteSpan buffer, std::uint8_t command, std::size_t length,
                                 ByteSpan& frame) {
  ParseResult<Message> r;
  if (buffer.empty()) return r;  // kNeedMore
  if (buffer[0] != command) return skip_to_sync<Message>(buffer, {command}, hex8(command));
  if (buffer.size() < length) return r;  // kNeedMore
  frame = buffer.first(length);
  const std::uint16_t received = get_u16_be(frame, length - 2);
  const std::uint16_t computed = checksum(frame.first(length - 2));
  if (received != computed) {
    r.status = ParseStatus::kMalformed;
    r.consumed = 1;  // the sync may have been a data byte: drop only it and hunt again
    r.error = "checksum " + hex16(received) + " != computed " + hex16(computed);
    return r;
  }
  r.status = ParseStatus::kComplete;
  r.consumed = length;
  return r;
}

}  // namespace

Bytes encode(const EulerAngles& m) {
  Bytes out;
  out.reserve(kEulerAnglesLength);
  out.push_back(kCmdEulerAngles);
  for (const float v : {m.roll_rad, m.pitch_rad, m.yaw_rad}) {
    put_u32_be(out, std::bit_cast<std::uint32_t>(v));
  }
  put_u32_be(out, m.timer_ticks);
  append_checksum(out);
  return out;
}

ParseResult<EulerAngles> parse_euler_angles(ByteSpan buffer) {
  ByteSpan frame;
  auto r = check_reply<EulerAngles>(buffer, kCmdEulerAngles, kEulerAnglesLength, frame);
  if (r.status != ParseStatus::kComplete) return r;
  EulerAngles m;
  m.roll_rad = get_f32_be(frame, 1);
  m.pitch_rad = get_f32_be(frame, 5);
  m.yaw_rad = get_f32_be(frame, 9);
  m.timer_ticks = get_u32_be(frame, 13);
  r.message = m;
  return r;
}

Bytes encode(const ContinuousModeReply& m) {
  Bytes out;
  out.reserve(kSetContinuousReplyLength);
  out.push_back(kCmdSetContinuous);
  out.push_back(m.command);
  put_u32_be(out, m.timer_ticks);
  append_checksum(out);
  return out;
}

ParseResult<ContinuousModeReply> parse_continuous_mode_reply(ByteSpan buffer) {
  ByteSpan frame;
  auto r = check_reply<ContinuousModeReply>(buffer, kCmdSetContinuous, kSetContinuousReplyLength,
                                            frame);
  if (r.status != ParseStatus::kComplete) return r;
  ContinuousModeReply m;
  m.command = frame[1];
  m.timer_ticks = get_u32_be(frame, 2);
  r.message = m;
  return r;
}

Bytes encode_set_continuous(std::uint8_t reply_command) {
  return {kCmdSetContinuous, kSetContinuousConfirm[0], kSetContinuousConfirm[1], reply_command};
}

Bytes encode_stop_continuous() {
  return {kCmdStopContinuous, kStopContinuousConfirm[0], kStopContinuousConfirm[1]};
}

Bytes encode(const HostCommand& c) {
  return c.kind == HostCommandKind::kSetContinuous ? encode_set_continuous(c.reply_command)
                                                   : encode_stop_continuous();
}

ParseResult<HostCommand> parse_host_command(ByteSpan buffer) {
  ParseResult<HostCommand> r;
  if (buffer.empty()) return r;  // kNeedMore
  const bool set = buffer[0] == kCmdSetContinuous;
  if (!set && buffer[0] != kCmdStopContinuous) {
    return skip_to_sync<HostCommand>(buffer, {kCmdSetContinuous, kCmdStopContinuous},
                                     "0xC4/0xFA");
  }
  const auto& confirm = set ? kSetContinuousConfirm : kStopContinuousConfirm;
  const std::size_t length = set ? kSetContinuousLength : kStopContinuousLength;
  for (std::size_t i = 0; i < confirm.size(); ++i) {
    if (buffer.size() <= i + 1) return r;  // kNeedMore: a proper prefix so far
    if (buffer[i + 1] != confirm[i]) {
      r.status = ParseStatus::kMalformed;
      r.consumed = 1;
      r.error = "command " + hex8(buffer[0]) + ": confirmation byte " + std::to_string(i + 1) +
                " is " + hex8(buffer[i + 1]) + ", expected " + hex8(confirm[i]);
      return r;
    }
  }
  if (buffer.size() < length) return r;  // kNeedMore: waiting for <cmd>
  HostCommand c;
  c.kind = set ? HostCommandKind::kSetContinuous : HostCommandKind::kStopContinuous;
  c.reply_command = set ? buffer[3] : std::uint8_t{0};
  r.status = ParseStatus::kComplete;
  r.consumed = length;
  r.message = c;
  return r;
}

}  // namespace nav::protocols::gx3

// SPDX-License-Identifier: MIT
// MicroStrain 3DM-GX3-25 additions: 0xCE Euler angles, the 0xC4 continuous-mode reply and the
// host commands `C4 C1 29 <cmd>` / `FA 75 B4` (protocols.md 1a).
//
// Fixtures were built outside this codebase (Python struct.pack('>fffI') and sum(...) & 0xFFFF)
// from the layouts of protocols.md 1a, so they do not share the codec's encoder.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "nav/protocols/microstrain_gx3.hpp"
#include "stream_drain.hpp"

namespace nav::protocols::gx3 {
namespace {

using test_support::drain;
using test_support::random_rounds_missing_frame;

/// 0xCE: roll 0.1, pitch -0.2, yaw 3.0 rad, timer 62500 ticks (1 s); checksum 0x07AB.
const Bytes kEuler = {0xCE, 0x3D, 0xCC, 0xCC, 0xCD,  // roll
                      0xBE, 0x4C, 0xCC, 0xCD,        // pitch
                      0x40, 0x40, 0x00, 0x00,        // yaw
                      0x00, 0x00, 0xF4, 0x24,        // timer
                      0x07, 0xAB};                   // checksum

/// 0xC4 reply to `C4 C1 29 CE`: echo 0xCE, timer 125000 ticks (position inferred); 0x02C3.
const Bytes kContinuousReply = {0xC4, 0xCE, 0x00, 0x01, 0xE8, 0x48, 0x02, 0xC3};

TEST(Gx3Euler, ConstructedFrameDecodes) {
  ASSERT_EQ(kEuler.size(), kEulerAnglesLength);
  EXPECT_EQ(checksum(ByteSpan(kEuler).first(17)), 0x07AB);
  const auto r = parse_euler_angles(kEuler);
  ASSERT_EQ(r.status, ParseStatus::kComplete) << r.error;
  EXPECT_EQ(r.consumed, 19u);
  EXPECT_EQ(r.message->roll_rad, 0.1f);
  EXPECT_EQ(r.message->pitch_rad, -0.2f);
  EXPECT_EQ(r.message->yaw_rad, 3.0f);
  EXPECT_DOUBLE_EQ(r.message->timer_ticks / kTicksPerSecond, 1.0);
}

TEST(Gx3Euler, EncodeReproducesConstructedFrame) {
  EXPECT_EQ(encode(EulerAngles{0.1f, -0.2f, 3.0f, 62500}), kEuler);
}

TEST(Gx3Euler, RoundTripKeepsEveryBit) {
  const EulerAngles m{-3.14159274f, -0.0f, 1e-38f, 0xFFFFFFFFu};
  const Bytes b = encode(m);
  const auto r = parse_euler_angles(b);
  ASSERT_EQ(r.status, ParseStatus::kComplete) << r.error;
  EXPECT_EQ(encode(*r.message), b);
  EXPECT_TRUE(std::signbit(r.message->pitch_rad));
  EXPECT_EQ(r.message->timer_ticks, 0xFFFFFFFFu);
}

TEST(Gx3Euler, ShortNeedsMoreBadChecksumAndGarbageAreMalformed) {
  EXPECT_EQ(parse_euler_angles({}).status, ParseStatus::kNeedMore);
  for (std::size_t n = 1; n < kEulerAnglesLength; ++n) {
    const auto r = parse_euler_angles(ByteSpan(kEuler).first(n));
    EXPECT_EQ(r.status, ParseStatus::kNeedMore) << n;
    EXPECT_EQ(r.consumed, 0u);
  }
  Bytes bad = kEuler;
  bad[3] ^= 0x10;
  const auto c = parse_euler_angles(bad);
  EXPECT_EQ(c.status, ParseStatus::kMalformed);
  EXPECT_EQ(c.consumed, 1u);
  EXPECT_EQ(c.error, "checksum 0x07AB != computed 0x07BB");

  Bytes noisy = {0x11, 0xCB, 0x22};
  noisy.insert(noisy.end(), kEuler.begin(), kEuler.end());
  const auto g = parse_euler_angles(noisy);
  EXPECT_EQ(g.status, ParseStatus::kMalformed);
  EXPECT_EQ(g.consumed, 3u);
  EXPECT_EQ(g.error, "no 0xCE sync byte: skipped 3 byte(s) to the next 0xCE");
  const auto d = drain<EulerAngles>(&parse_euler_angles, noisy);
  EXPECT_EQ(d.offsets, (std::vector<std::size_t>{3}));
  EXPECT_EQ(d.leftover, 0u);
}

TEST(Gx3Euler, CbRepliesAreNotEulerFrames) {
  // A 0xCB stream read with the 0xCE parser: every byte skipped, no false frame.
  const Bytes cb = encode(AccelRateMag{{0.0f, 0.0f, -1.0f}, {0.01f, -0.02f, 0.03f},
                                       {0.2f, 0.0f, 0.4f}, 62500});
  Bytes stream;
  for (int k = 0; k < 5; ++k) stream.insert(stream.end(), cb.begin(), cb.end());
  const auto d = drain<EulerAngles>(&parse_euler_angles, stream);
  EXPECT_TRUE(d.messages.empty());
}

TEST(Gx3ContinuousReply, ConstructedFrameDecodesAndEncodes) {
  const auto r = parse_continuous_mode_reply(kContinuousReply);
  ASSERT_EQ(r.status, ParseStatus::kComplete) << r.error;
  EXPECT_EQ(r.consumed, kSetContinuousReplyLength);
  EXPECT_EQ(r.message->command, kCmdEulerAngles);
  EXPECT_EQ(r.message->timer_ticks, 125000u);
  EXPECT_EQ(encode(ContinuousModeReply{0xCE, 125000}), kContinuousReply);
}

TEST(Gx3ContinuousReply, ShortBadChecksumAndGarbage) {
  for (std::size_t n = 0; n < kSetContinuousReplyLength; ++n) {
    EXPECT_EQ(parse_continuous_mode_reply(ByteSpan(kContinuousReply).first(n)).status,
              ParseStatus::kNeedMore)
        << n;
  }
  Bytes bad = kContinuousReply;
  bad[1] = 0xCB;  // echo changed, checksum not
  const auto c = parse_continuous_mode_reply(bad);
  EXPECT_EQ(c.status, ParseStatus::kMalformed);
  EXPECT_EQ(c.consumed, 1u);
  EXPECT_EQ(c.error, "checksum 0x02C3 != computed 0x02C0");
  const Bytes garbage = {0xFA, 0x75, 0xB4};
  const auto g = parse_continuous_mode_reply(garbage);
  EXPECT_EQ(g.status, ParseStatus::kMalformed);
  EXPECT_EQ(g.consumed, 3u);
}

TEST(Gx3HostCommand, EncodersMatchProtocolsMd) {
  // protocols.md 1a: "Start streaming it with C4 C1 29 CB; stop with FA 75 B4".
  EXPECT_EQ(encode_set_continuous(kCmdAccelRateMag), (Bytes{0xC4, 0xC1, 0x29, 0xCB}));
  EXPECT_EQ(encode_stop_continuous(), (Bytes{0xFA, 0x75, 0xB4}));
  EXPECT_EQ(encode(HostCommand{HostCommandKind::kSetContinuous, 0xCE}),
            (Bytes{0xC4, 0xC1, 0x29, 0xCE}));
  EXPECT_EQ(encode(HostCommand{HostCommandKind::kStopContinuous, 0}), (Bytes{0xFA, 0x75, 0xB4}));
}

TEST(Gx3HostCommand, ParsesBothCommands) {
  const auto set = parse_host_command(Bytes{0xC4, 0xC1, 0x29, 0xCB, 0xFA});
  ASSERT_EQ(set.status, ParseStatus::kComplete) << set.error;
  EXPECT_EQ(set.consumed, 4u);
  EXPECT_EQ(set.message->kind, HostCommandKind::kSetContinuous);
  EXPECT_EQ(set.message->reply_command, 0xCB);

  const auto stop = parse_host_command(Bytes{0xFA, 0x75, 0xB4});
  ASSERT_EQ(stop.status, ParseStatus::kComplete) << stop.error;
  EXPECT_EQ(stop.consumed, 3u);
  EXPECT_EQ(stop.message->kind, HostCommandKind::kStopContinuous);
  EXPECT_EQ(stop.message->reply_command, 0u);
}

TEST(Gx3HostCommand, ProperPrefixesNeedMore) {
  for (const Bytes& prefix : {Bytes{}, Bytes{0xC4}, Bytes{0xC4, 0xC1}, Bytes{0xC4, 0xC1, 0x29},
                              Bytes{0xFA}, Bytes{0xFA, 0x75}}) {
    const auto r = parse_host_command(prefix);
    EXPECT_EQ(r.status, ParseStatus::kNeedMore) << prefix.size();
    EXPECT_EQ(r.consumed, 0u);
  }
}

TEST(Gx3HostCommand, WrongConfirmationAndOtherBytesAreMalformed) {
  const auto a = parse_host_command(Bytes{0xC4, 0xC1, 0x28, 0xCB});
  EXPECT_EQ(a.status, ParseStatus::kMalformed);
  EXPECT_EQ(a.consumed, 1u);
  EXPECT_EQ(a.error, "command 0xC4: confirmation byte 2 is 0x28, expected 0x29");

  const auto b = parse_host_command(Bytes{0xFA, 0x00});
  EXPECT_EQ(b.status, ParseStatus::kMalformed);
  EXPECT_EQ(b.error, "command 0xFA: confirmation byte 1 is 0x00, expected 0x75");

  // A single-byte poll (0xCB) is not one of the two commands: skipped up to the next C4/FA.
  const auto c = parse_host_command(Bytes{0xCB, 0x01, 0xFA, 0x75, 0xB4});
  EXPECT_EQ(c.status, ParseStatus::kMalformed);
  EXPECT_EQ(c.consumed, 2u);
  EXPECT_EQ(c.error, "no 0xC4/0xFA sync byte: skipped 2 byte(s) to the next 0xC4/0xFA");
}

TEST(Gx3HostCommand, StreamOfCommandsWithNoise) {
  Bytes stream = {0x00, 0xC4, 0xC1};  // noise, then a set command cut off
  for (const Bytes& part : {encode_set_continuous(0xCE), encode_stop_continuous(),
                            encode_set_continuous(0xCB)}) {
    stream.insert(stream.end(), part.begin(), part.end());
  }
  stream.push_back(0xFA);  // the start of a stop
  const auto d = drain<HostCommand>(&parse_host_command, stream);
  ASSERT_EQ(d.messages.size(), 3u);
  EXPECT_EQ(d.offsets, (std::vector<std::size_t>{3, 7, 10}));
  EXPECT_EQ(d.messages[0].reply_command, 0xCE);
  EXPECT_EQ(d.messages[1].kind, HostCommandKind::kStopContinuous);
  EXPECT_EQ(d.messages[2].reply_command, 0xCB);
  // The noise byte; the cut-off C4 (its 0xC1 is followed by 0xC4, not 0x29); then 0xC1.
  EXPECT_EQ(d.bad_offsets, (std::vector<std::size_t>{0, 1, 2}));
  EXPECT_EQ(d.leftover, 1u);
}

TEST(Gx3HostCommand, RoundTripEveryReplyByte) {
  for (int cmd = 0; cmd < 256; ++cmd) {
    const HostCommand c{HostCommandKind::kSetContinuous, static_cast<std::uint8_t>(cmd)};
    const auto r = parse_host_command(encode(c));
    ASSERT_EQ(r.status, ParseStatus::kComplete) << cmd;
    EXPECT_EQ(r.message->reply_command, cmd);
  }
}

TEST(Gx3Additions, RandomBytesKeepTheTriStateContract) {
  // Sync-rich noise (fixed seeds); the spliced frame is always found: each of these parsers
  // drops only the sync byte of a failed candidate.
  EXPECT_EQ(random_rounds_missing_frame<EulerAngles>(&parse_euler_angles, kEuler, {0xCE}, 1), 0);
  EXPECT_EQ(random_rounds_missing_frame<ContinuousModeReply>(&parse_continuous_mode_reply,
                                                             kContinuousReply, {0xC4}, 2),
            0);
  EXPECT_EQ(random_rounds_missing_frame<HostCommand>(&parse_host_command,
                                                     encode_set_continuous(0xCB),
                                                     {0xC4, 0xC1, 0x29, 0xFA, 0x75, 0xB4}, 3),
            0);
}

}  // namespace
}  // namespace nav::protocols::gx3

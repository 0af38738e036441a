// SPDX-License-Identifier: MIT
// Wheel encoder frames of the P3 crawler robot (papers.md P3: two RLS RM44 magnetic encoders,
// 256 CPR, differential drive), read and written THROUGH a loaded DBC (fixtures/crawler.dbc):
// the code knows message and signal names and what each means, the DBC says where the bits
// are. The emulator and navd build a WheelEncoderCodec from the DBC at startup; its factory is
// the compatibility check, so a DBC edit that breaks the code is refused with a precise error
// instead of decoding garbage.
//
//   message                one per wheel (kLeftMessage, kRightMessage), cyclic
//   kTicksSignal           cumulative count, unsigned 32 bit, factor 1, unit "count";
//                          wraps modulo 2^32 (use tick_delta())
//   kSpeedSignal           wheel angular rate, signed, unit "rad/s", positive = driving forward
//   kCounterSignal         rolling message counter, unsigned, factor 1, 1..8 bits
//   kValidSignal           1 bit, 1 = reading valid
//   kCountsPerRevAttribute BO_ attribute: encoder counts per wheel revolution
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string_view>

#include "nav/common/result.hpp"
#include "nav/protocols/dbc.hpp"

namespace nav::protocols::wheel_encoder {

inline constexpr std::string_view kLeftMessage = "WheelEncoderLeft";    ///< BO_ of the left wheel
inline constexpr std::string_view kRightMessage = "WheelEncoderRight";  ///< BO_ of the right wheel
inline constexpr std::string_view kTicksSignal = "TickCount";           ///< [count]
inline constexpr std::string_view kSpeedSignal = "WheelSpeed";          ///< [rad/s]
inline constexpr std::string_view kCounterSignal = "MsgCounter";        ///< rolling counter [-]
inline constexpr std::string_view kValidSignal = "Valid";               ///< 1 = valid
inline constexpr std::string_view kTicksUnit = "count";                 ///< unit of kTicksSignal
inline constexpr std::string_view kSpeedUnit = "rad/s";                 ///< unit of kSpeedSignal
inline constexpr std::string_view kCountsPerRevAttribute = "EncoderCountsPerRev";  ///< [count/rev]

/// Which wheel of the differential drive.
enum class Wheel {
  kLeft,   ///< left (port) wheel, kLeftMessage
  kRight,  ///< right (starboard) wheel, kRightMessage
};

/// One encoder frame's content in SI units.
struct WheelEncoderSample {
  Wheel wheel = Wheel::kLeft;  ///< which wheel sent it
  std::uint32_t ticks = 0;     ///< cumulative encoder count, wraps modulo 2^32 [count]
  double omega = 0.0;          ///< wheel angular rate, positive = robot driving forward [rad/s]
  std::uint8_t counter = 0;    ///< rolling message counter, 0 .. counter_modulus() - 1 [-]
  bool valid = true;           ///< the encoder reports a valid reading
};

/// Signed tick increment from `before` to `now`, correct across the 2^32 wrap when the wheel
/// turned less than 2^31 counts in between [count].
constexpr std::int64_t tick_delta(std::uint32_t now, std::uint32_t before) {
  return static_cast<std::int32_t>(now - before);
}

/// Wheel encoder frames as one DBC describes them.
class WheelEncoderCodec {
 public:
  /// Checks that `db` has both messages with every signal the code needs and a compatible
  /// definition (length, sign, factor/offset where the code relies on integers, unit), a
  /// positive GenMsgCycleTime and kCountsPerRevAttribute; the error names the message, the
  /// signal and what differs. The codec keeps copies: `db` may go away afterwards.
  static Result<WheelEncoderCodec> from_database(const dbc::Database& db);

  /// The frame for a sample; fails when a value does not fit its signal (e.g. omega or
  /// counter out of the DBC's range).
  Result<dbc::Frame> encode(const WheelEncoderSample& sample) const;

  /// The sample in a frame; fails for a frame of neither wheel or shorter than the DLC.
  Result<WheelEncoderSample> decode(const dbc::Frame& frame) const;

  /// The wheel whose message has this identifier, nullopt for any other frame.
  std::optional<Wheel> wheel_of(std::uint32_t id, bool extended) const;

  /// The DBC message of a wheel.
  const dbc::Message& message(Wheel w) const;
  /// GenMsgCycleTime of a wheel's message.
  std::chrono::milliseconds cycle_time(Wheel w) const;
  /// Wheel rotation per encoder count, 2 pi / counts-per-revolution [rad].
  double angle_per_tick(Wheel w) const;
  /// Number of distinct counter values, 2^length of kCounterSignal [-].
  std::uint32_t counter_modulus(Wheel w) const;

 private:
  struct Layout {
    dbc::Message message;  ///< copy of the DBC message
    dbc::Signal ticks;     ///< copies of its signals the code uses
    dbc::Signal speed;
    dbc::Signal counter;
    dbc::Signal valid;
    std::chrono::milliseconds cycle_time{0};  ///< GenMsgCycleTime
    double counts_per_rev = 0.0;              ///< kCountsPerRevAttribute [count/rev]
  };
  static Result<Layout> layout_of(const dbc::Database& db, std::string_view message_name);
  WheelEncoderCodec() = default;
  const Layout& layout(Wheel w) const { return w == Wheel::kLeft ? left_ : right_; }

  Layout left_;
  Layout right_;
};

/// Checks a DBC against the code (WheelEncoderCodec::from_database without keeping it).
Result<void> check_database(const dbc::Database& db);

}  // namespace nav::protocols::wheel_encoder

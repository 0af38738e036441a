// SPDX-License-Identifier: MIT
// The P3 crawler's two wheel encoders (papers.md P3: differential drive, RLS RM44 magnetic
// encoders) on CAN, frames laid out by the DBC loaded at runtime (fixtures/crawler.dbc through
// protocols::wheel_encoder::WheelEncoderCodec). The model equations, the slip model and the
// random draws are in wheel_encoder_emulator.cpp's opening comment.
// Pure: truth in, CanWireFrames (queued times) out.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "nav/common/time.hpp"
#include "nav/emulators/can_device.hpp"
#include "nav/emulators/truth.hpp"
#include "nav/protocols/wheel_encoder.hpp"

namespace nav::emulators {

/// Encoder slip: the wheel turns (1 + slip) times the angle its ground distance needs (a
/// wheel spinning on the wall). slip(t) = fraction + walk(t), walk a random walk from 0.
struct WheelSlip {
  double left = 0.0;      ///< left wheel slip fraction, 0.05 = turns 5 % too far [-]
  double right = 0.0;     ///< right wheel slip fraction [-]
  double walk_std = 0.0;  ///< random walk of each wheel's slip [1/sqrt(s)]
};

/// The crawler's drive and its encoders. papers.md P3 names R and b but gives no values: the
/// defaults are those of a small pool-cleaning crawler (ASSUMED, set them per vehicle); the
/// counts per revolution come from the DBC (EncoderCountsPerRev, 256 for the RM44).
struct WheelEncoderConfig {
  double wheel_radius_m = 0.05;   ///< R, drive wheel radius [m]
  double track_width_m = 0.30;    ///< b, distance between the wheel contact lines [m]
  std::optional<double> rate_hz;  ///< frame rate per wheel; nullopt = 1 / GenMsgCycleTime of
                                  ///< each wheel's message in the DBC [Hz]
  Duration latency{std::chrono::milliseconds(1)};  ///< time of validity -> queued [ns]
  std::uint32_t start_ticks_left = 0;   ///< left TickCount at scenario time 0 [count]
  std::uint32_t start_ticks_right = 0;  ///< right TickCount at scenario time 0 [count]
  double speed_std_radps = 0.01;  ///< white noise on WheelSpeed [rad/s]
  /// White noise on the angle the encoder reads before it is cut to ticks (a magnetic
  /// encoder's accuracy: the RM44's ±0.7°), per sample, not accumulated [rad].
  double angle_std_rad = 0.0;
  WheelSlip slip;                 ///< encoder slip (design.md "encoder slip")
};

/// Every frame of both wheels over [0, duration), sorted by t_ready (ties: left first),
/// encoded through `codec`. Deterministic per seed; each wheel has its own engine.
std::vector<CanWireFrame> generate_wheel_encoders(
    const WheelEncoderConfig& cfg, const protocols::wheel_encoder::WheelEncoderCodec& codec,
    const Truth& truth, Duration duration, std::uint64_t seed);

}  // namespace nav::emulators

// SPDX-License-Identifier: MIT
// The settings of a `wheel-encoders` device (DeviceSpec::settings), for its kind's file and
// its tests.
#pragma once

#include <memory>
#include <string>

#include "nav/emulators/wheel_encoder_emulator.hpp"
#include "nav/protocols/wheel_encoder.hpp"

namespace nav::bench::detail {

struct WheelEncoders {
  emulators::WheelEncoderConfig drive;  ///< the drive, slip and noise
  std::string dbc_path;                 ///< the DBC file, resolved (absolute or as written)
  /// The codec of the DBC's wheel messages, checked against it at load time.
  std::shared_ptr<const protocols::wheel_encoder::WheelEncoderCodec> codec;
};

}  // namespace nav::bench::detail

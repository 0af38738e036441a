// SPDX-License-Identifier: MIT
// The baud rates of the project's serial lines: a scenario's `baud`, `navbench replay --port`
// and navd's ports all take these, and the serial port layer has a line setting for each.
#pragma once

#include <array>

namespace nav {

/// Common rates from old instruments' 300 and NMEA's 4800 to USB-serial adapters' 921600,
/// ascending [bit/s].
inline constexpr std::array<int, 15> kSerialBauds{300,    600,    1200,   2400,   4800,
                                                  9600,   19200,  38400,  57600,  115200,
                                                  230400, 460800, 500000, 576000, 921600};

}  // namespace nav

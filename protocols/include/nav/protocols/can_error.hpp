// SPDX-License-Identifier: MIT
// SocketCAN error frames (linux/can/error.h): how a Linux CAN controller driver reports bus
// errors, error counters, bus-off and restarts to a socket that asked for them
// (CAN_RAW_ERR_FILTER). Pure: the bench builds them (CAN faults), navd classifies them.
//
//   can_id  = CAN_ERR_FLAG | classes        dlc = CAN_ERR_DLC (8)
//   data[1] controller status (CAN_ERR_CRTL)   data[2] protocol error type (CAN_ERR_PROT)
//   data[3] its location (CAN_ERR_PROT)        data[6] TX error counter, data[7] RX error
//                                              counter (CAN_ERR_CNT)
#pragma once

#include <algorithm>
#include <cstdint>

#include "nav/protocols/can_frame.hpp"

namespace nav::protocols::can {

// Error classes (Frame::id of an error frame).
inline constexpr std::uint32_t kErrController = 0x004;  ///< CAN_ERR_CRTL: data[1]
inline constexpr std::uint32_t kErrProtocol = 0x008;    ///< CAN_ERR_PROT: data[2], data[3]
inline constexpr std::uint32_t kErrBusOff = 0x040;      ///< CAN_ERR_BUSOFF
inline constexpr std::uint32_t kErrRestarted = 0x100;   ///< CAN_ERR_RESTARTED
inline constexpr std::uint32_t kErrCounters = 0x200;    ///< CAN_ERR_CNT: data[6], data[7]
inline constexpr std::uint32_t kErrAllClasses = 0x1FFFFFFF;  ///< CAN_ERR_MASK
inline constexpr std::uint8_t kErrDlc = 8;              ///< CAN_ERR_DLC

// data[1], controller status.
inline constexpr std::uint8_t kCtrlRxWarning = 0x04;  ///< RX error counter reached 96
inline constexpr std::uint8_t kCtrlRxPassive = 0x10;  ///< RX error counter reached 128
inline constexpr std::uint8_t kCtrlActive = 0x40;     ///< back to error active
// data[2], protocol error type; data[3], its location.
inline constexpr std::uint8_t kProtForm = 0x02;          ///< frame format error
inline constexpr std::uint8_t kProtLocCrcSequence = 0x08;  ///< in the CRC sequence

/// What an error frame reports.
struct ErrorReport {
  std::uint32_t classes = 0;    ///< kErr* bits
  std::uint8_t controller = 0;  ///< data[1]
  std::uint8_t protocol = 0;    ///< data[2]
  std::uint8_t location = 0;    ///< data[3]
  std::uint8_t tx_errors = 0;   ///< data[6], valid with kErrCounters
  std::uint8_t rx_errors = 0;   ///< data[7], valid with kErrCounters
};

/// The error frame of a report.
inline Frame error_frame(const ErrorReport& r) {
  Frame f;
  f.error = true;
  f.id = r.classes & kErrAllClasses;
  f.dlc = kErrDlc;
  f.data[1] = r.controller;
  f.data[2] = r.protocol;
  f.data[3] = r.location;
  f.data[6] = r.tx_errors;
  f.data[7] = r.rx_errors;
  return f;
}

/// The report of an error frame (f.error set).
inline ErrorReport error_report(const Frame& f) {
  ErrorReport r;
  r.classes = f.id & kErrAllClasses;
  r.controller = f.data[1];
  r.protocol = f.data[2];
  r.location = f.data[3];
  r.tx_errors = f.data[6];
  r.rx_errors = f.data[7];
  return r;
}

}  // namespace nav::protocols::can

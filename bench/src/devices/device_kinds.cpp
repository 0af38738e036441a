// SPDX-License-Identifier: MIT
// The device registry: every kind of device a scenario may name. A new kind is its own file
// in this folder plus one line here (docs/adding-a-device.md).
#include <stdexcept>

#include "devices/device_kind.hpp"

namespace nav::bench::detail {

const std::vector<const DeviceKind*>& device_kinds() {
  static const std::vector<const DeviceKind*> kinds{
      &gx3_kind(),
      &gps_kind(),
      &dvl_kind(),
      &ebimu_kind(),
      &usbl_kind(),
      &iusbl_kind(),
      &keller_kind(),
      &acoustic_modem_kind(),
      &nmea2000_kind(),
      &wheel_encoders_kind(),
      &beacon_ins_kind(),
  };
  return kinds;
}

const DeviceKind& device_kind(const DeviceSpec& d) {
  if (const DeviceKind* k = find_device_kind(d.type)) return *k;
  throw std::logic_error("device '" + d.name + "' of type '" + d.type +
                         "', which has no kind in device_kinds.cpp");
}

const DeviceKind* find_device_kind(std::string_view name) {
  for (const auto* k : device_kinds()) {
    if (name == k->name) return k;
  }
  return nullptr;
}

const std::vector<emulators::MeasurementFault>& measurement_faults_of(const DeviceSpec& d) {
  static const std::vector<emulators::MeasurementFault> kNone;
  const auto get = device_kind(d).measurement_faults;
  // A spec its kind has not read yet has no settings, and no faults. The accessor takes a
  // mutable spec; reading through it changes nothing.
  return get && d.settings.has_value() ? *get(const_cast<DeviceSpec&>(d)) : kNone;
}

}  // namespace nav::bench::detail

namespace nav::bench {

bool DeviceSpec::on_can() const {
  return detail::device_kind(*this).link == detail::DeviceKind::Link::kCan;
}

}  // namespace nav::bench
